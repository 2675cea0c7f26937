/* voxplore — one exploration run of voxplore-explore (internal, not installed). */
#pragma once

#include <voxplore/apps/ExploreApp.h>
#include <voxplore/apps/SimRobot.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/navigation/StopAndScanDriver.h>
#include <voxplore/sim/SimConfig.h>
#include <voxplore/sim/footprint_reach.h>
#include <voxplore/sim/ground_truth.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace voxplore::apps
{
/// @brief Every parameter of a run.
struct ExploreConfig
{
  sim::SimConfig sim;
  mapping::SlamIcpParams slam;
  exploration::PlannerParams planner;
  navigation::DriverParams driver;
  ExploreParams explore;
};

/// @brief SimRobot that reports every step (to record the true trajectory).
class TrackedSimRobot : public SimRobot
{
 public:
  using SimRobot::SimRobot;
  std::function<void()> on_step;
  void step(double dt_s) override
  {
    SimRobot::step(dt_s);
    if (on_step) on_step();
  }
};

/// @brief The state of one run: simulator robot, SLAM, planner inputs,
///        writers. execute() runs the loop and writes every output.
class ExploreRun
{
 public:
  ExploreRun(sim::Simulator& sim, const ExploreConfig& cfg, std::string out_dir, bool quiet);
  /// @brief The loop, then the outputs and metrics. On an exception the
  ///        maps so far are written before it propagates.
  ExploreSummary execute();

 private:
  // --- loop (ExploreRun.cpp) ---
  void loop();
  void scanAndIntegrate();
  /// @return false when a drive failed (the caller replans)
  bool driveWaypoints(const exploration::PlanResult& plan);
  void registerFailure(const Eigen::Vector2d& target);
  /// Counts a plan for the frontier at `target`; blacklists it after max_plans_per_target.
  void registerPlan(const Eigen::Vector2d& target);
  void onRobotStep();
  /// Appends an estimated robot position to swept_ (interpolated 5 cm apart).
  void addSwept(const Eigen::Vector2d& e);
  void reportStep(const exploration::PlanResult& plan, double plan_ms);
  // --- outputs and metrics (ExploreApp_outputs.cpp) ---
  void openOutputs();
  /// Computes the three ground-truth floors (coverage_2d and the circle figures).
  void computeGroundTruthFloor(const Eigen::AlignedBox2d* region);
  void writeCoverageRow(const exploration::PlanResult& plan, double coverage,
                        double coverage_planner_circle);
  void writeStepImage(const exploration::PlanResult& plan);
  /// coverage_2d of `g`: the share of gt_floor_ known as free.
  double coverageOf(const exploration::GroundGrid& g) const;
  void finish();
  void saveMapsAfterFailure() noexcept;
  std::vector<mrpt::poses::CPose2D> trajectoryInMap(double spacing_m) const;

  sim::Simulator& sim_;
  ExploreConfig cfg_;
  std::string out_dir_;
  bool quiet_;
  TrackedSimRobot robot_;
  std::unique_ptr<navigation::StopAndScanDriver> driver_;
  mapping::SlamIcp slam_;
  mrpt::poses::CPose2D T_world_map_;  ///< the robot's true start pose
  sim::FootprintReach gt_floor_;          ///< reachable or seen by the real footprint (coverage_2d)
  sim::ReachableFloor gt_floor_planner_;  ///< reachable for the planner's collision radius (coverage_2d_planner_circle)
  sim::ReachableFloor gt_floor_body_;     ///< reachable for the bare circumcircle (coverage_2d_circumradius)
  std::shared_ptr<const exploration::GroundGrid> last_ground_;  ///< G of the last plan (coverage_map.png)

  // pose estimate between stops: SLAM pose at the last stop + odometry since
  mrpt::poses::CPose2D pose_at_stop_, odo_at_stop_;

  std::vector<Eigen::Vector2d> blacklist_;
  std::vector<std::pair<Eigen::Vector2d, int>> failures_;
  std::vector<std::pair<Eigen::Vector2d, int>> plans_;  ///< frontier centre -> plans so far
  std::vector<Eigen::Vector2d> swept_;  ///< estimated robot positions (map frame), 5 cm apart
  std::vector<mrpt::poses::CPose2D> gt_path_;  ///< true poses, every robot step that moved
  double compute_s_ = 0, slam_ms_step_ = 0;
  ExploreSummary s_;

  std::unique_ptr<common::RawlogWriter> rawlog_;
  std::unique_ptr<common::TumWriter> gt_tum_, est_tum_;
  std::ofstream coverage_csv_;
};

}  // namespace voxplore::apps
