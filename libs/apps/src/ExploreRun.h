/* voxplore — one exploration run of voxplore-explore (internal, not installed). */
#pragma once

#include <voxplore/apps/ExploreApp.h>
#include <voxplore/apps/SimRobot.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/mission/ExplorationLoop.h>
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

/// @brief One run of voxplore-explore on mrpt-sim: the simulator behind the
///        mission's interfaces (SimRobot, SimScanSource, SimClock), the
///        mission::ExplorationLoop, and around it what only a simulator can
///        give (ground-truth floor, true path, coverage, map accuracy) and the
///        outputs. execute() runs the loop and writes every output.
class ExploreRun : public mission::Listener
{
 public:
  ExploreRun(sim::Simulator& sim, const ExploreConfig& cfg, std::string out_dir, bool quiet);
  ~ExploreRun() override;
  /// @brief The loop, then the outputs and metrics. On an exception the
  ///        maps so far are written before it propagates.
  ExploreSummary execute();

  // --- mission::Listener (ExploreRun.cpp) ---
  void onScan(const mission::Scan& scan) override;
  void onStop(const mission::Scan& scan, const mapping::StopReport& rep) override;
  void onPlan(const exploration::PlanResult& plan, double plan_ms,
              const mission::ExplorationStatus& status) override;
  void onPlanInputs(const exploration::PlanInputs& inputs, const octomap::OcTree& V) override;
  void onRobotStep() override;
  void onMessage(const std::string& line) override;
  std::string stopReason() override;

 private:
  const mapping::SlamIcp& slam() const { return loop_->slam(); }
  mapping::SlamIcp& slam() { return loop_->slam(); }
  // --- outputs and metrics (ExploreApp_outputs.cpp) ---
  void openOutputs();
  /// Computes the three ground-truth floors (coverage_2d and the circle figures).
  void computeGroundTruthFloor(const Eigen::AlignedBox2d* region);
  void writeCoverageRow(const exploration::PlanResult& plan, double coverage,
                        double coverage_planner_circle, double slam_ms);
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
  SimRobot robot_;
  SimScanSource scans_;
  SimClock clock_;
  std::unique_ptr<mission::ExplorationLoop> loop_;
  mrpt::poses::CPose2D T_world_map_;  ///< the robot's true start pose
  sim::FootprintReach gt_floor_;          ///< reachable or seen by the real footprint (coverage_2d)
  sim::ReachableFloor gt_floor_planner_;  ///< reachable for the planner's collision radius (coverage_2d_planner_circle)
  sim::ReachableFloor gt_floor_body_;     ///< reachable for the bare circumcircle (coverage_2d_circumradius)
  std::shared_ptr<const exploration::GroundGrid> last_ground_;  ///< G of the last plan (coverage_map.png)

  std::vector<mrpt::poses::CPose2D> gt_path_;  ///< true poses, every robot step that moved
  ExploreSummary s_;

  std::unique_ptr<common::RawlogWriter> rawlog_;
  std::unique_ptr<common::TumWriter> gt_tum_, est_tum_;
  std::ofstream coverage_csv_;
};

}  // namespace voxplore::apps
