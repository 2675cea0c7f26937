// voxplore-explore on mrpt-sim: mission::ExplorationLoop (thesis fig. 4.4,
// 4.6) over the simulator, with the ground truth, the evaluation and the
// outputs around it.
#include <mrpt/core/format.h>
#include <mrpt/system/CTicTac.h>

#include <cmath>
#include <iostream>

#include <voxplore/apps/app_common.h>

#include "ExploreApp_internal.h"
#include "ExploreRun.h"

#include <filesystem>

namespace voxplore::apps
{
ExploreRun::ExploreRun(
    sim::Simulator& sim, const ExploreConfig& cfg, std::string out_dir, bool quiet)
    : sim_(sim),
      cfg_(cfg),
      out_dir_(std::move(out_dir)),
      quiet_(quiet),
      robot_(sim),
      scans_(sim, &robot_),
      clock_(sim),
      T_world_map_(sim.robot().groundTruth())
{
  const Eigen::AlignedBox2d region = sim::obstacleBounds(sim_.checker());
  const bool bounded = cfg_.explore.region_from_world && !region.isEmpty();
  if (bounded)
  {
    // The box's corners in the map frame (the start pose is its origin).
    const mrpt::poses::CPose2D T_map_world = -T_world_map_;
    cfg_.planner.projection.region.clear();
    for (const auto corner : {Eigen::AlignedBox2d::BottomLeft, Eigen::AlignedBox2d::BottomRight,
                              Eigen::AlignedBox2d::TopRight, Eigen::AlignedBox2d::TopLeft})
    {
      const Eigen::Vector2d w = region.corner(corner);
      double mx = 0, my = 0;
      T_map_world.composePoint(w.x(), w.y(), mx, my);
      cfg_.planner.projection.region.emplace_back(mx, my);
    }
  }
  computeGroundTruthFloor(bounded ? &region : nullptr);
  gt_path_.push_back(T_world_map_);
  // Between stops the navigator sees the SLAM pose of the last stop composed
  // with the odometry increment since then (never the ground truth).
  loop_ = std::make_unique<mission::ExplorationLoop>(robot_, scans_, clock_, cfg_.slam,
                                                     cfg_.planner, cfg_.driver, cfg_.explore, this);
}

ExploreRun::~ExploreRun() = default;

void ExploreRun::computeGroundTruthFloor(const Eigen::AlignedBox2d* region)
{
  // coverage_2d: the floor the robot's real footprint (the rotated rectangle
  // the simulator's collision checker tests) reaches from the start, over
  // position and yaw, plus the floor its cameras see from there (issue 10).
  mrpt::system::CTicTac tic;
  const sim::Footprint footprint = cfg_.sim.robot.footprint();
  sim::FootprintReachParams fp;
  fp.res_m = cfg_.explore.gt_floor_res_m;
  fp.yaw_bins = cfg_.explore.coverage_yaw_bins;
  fp.view_range_m = cfg_.explore.coverage_view_range_m;
  gt_floor_ = sim::footprintReachableFloor(sim_.world(), sim_.checker(), T_world_map_, footprint,
                                           fp, region);
  gt_floor_.bins = {};  // the per-state masks are not needed after this (16 B per cell)
  const double footprint_s = tic.Tac();
  // Beside it, the circles: the planner's collision radius r_coll + sqrt(2)
  // l_res (thesis eq. 4.4; a passage narrower than that is out of the
  // method's reach by design) and the bare circumcircle.
  tic.Tic();
  const double r_planner =
      cfg_.planner.collision.r_coll_m + std::sqrt(2.0) * cfg_.slam.octomap.l_res_m;
  gt_floor_planner_ = sim::reachableFreeFloor(sim_.world(), sim_.checker(), T_world_map_, r_planner,
                                              cfg_.explore.gt_floor_res_m, region);
  gt_floor_body_ = sim::reachableFreeFloor(sim_.world(), sim_.checker(), T_world_map_,
                                           cfg_.planner.collision.r_coll_m,
                                           cfg_.explore.gt_floor_res_m, region);
  s_.floor_reachable_m2 = gt_floor_.free_floor_area_m2;
  s_.floor_reachable_planner_circle_m2 = gt_floor_planner_.free_floor_area_m2;
  s_.floor_reachable_circumradius_m2 = gt_floor_body_.free_floor_area_m2;
  if (!gt_floor_.start_free)
    std::cerr << "voxplore-explore: warning: the footprint does not fit at the start yaw at "
                 "the start's 5 cm cell or its neighbours: coverage_2d has no floor to measure"
              << std::endl;
  if (quiet_) return;
  std::cout << mrpt::format(
                   "voxplore-explore: ground truth: floor reachable or seen by the footprint "
                   "%.1f m^2 (robot centres %.1f m^2, %d yaw bins, view range %.1f m) took %.2f s; "
                   "planner circle %.1f m^2, circumradius %.1f m^2 took %.2f s",
                   s_.floor_reachable_m2, gt_floor_.reachable_area_m2, fp.yaw_bins,
                   fp.view_range_m, footprint_s, s_.floor_reachable_planner_circle_m2,
                   s_.floor_reachable_circumradius_m2, tic.Tac())
            << std::endl;
}

ExploreSummary ExploreRun::execute()
{
  openOutputs();
  const auto& col = cfg_.planner.collision;
  s_.planner_model = col.toString(col.modelInForce(cfg_.slam.octomap.l_res_m));
  try
  {
    const auto& status = loop_->run();
    s_.termination_reason = status.termination_reason;
  }
  catch (const std::exception& e)
  {
    saveMapsAfterFailure();
    throw std::runtime_error(std::string(e.what()) + " (the maps and logs of the " +
                             std::to_string(slam().numStops()) + " stops so far are in " +
                             out_dir_ + ")");
  }
  finish();
  if (last_ground_)
    explore_detail::writeCoverageMap(*last_ground_, gt_floor_, gt_floor_planner_, gt_floor_body_,
                                     T_world_map_, gt_path_, out_dir_ + "/coverage_map.png");
  return s_;
}

void ExploreRun::onScan(const mission::Scan& scan)
{
  rawlog_->write(*scan.actions, *scan.observations);
  gt_tum_->write(mrpt::Clock::toDouble(scan.timestamp),
                 mrpt::poses::CPose3D(scans_.last().T_world_robot_gt));
}

void ExploreRun::onStop(const mission::Scan& scan, const mapping::StopReport& rep)
{
  est_tum_->write(mrpt::Clock::toDouble(scan.timestamp), mrpt::poses::CPose3D(rep.pose));
  s_.stops = slam().numStops();
  for (const auto& w : rep.warnings)
    std::cerr << "voxplore-explore: warning: stop " << rep.index << ": " << w << std::endl;
  if (rep.flagged && !quiet_)
    std::cout << "  stop " << rep.index << ": ICP flagged (" << rep.icp.reason
              << "), pose from odometry" << std::endl;
}

void ExploreRun::onRobotStep()
{
  const auto& p = sim_.robot().groundTruth();
  const auto& q = gt_path_.back();
  const double d = std::hypot(p.x() - q.x(), p.y() - q.y());
  const double dyaw = std::abs(mrpt::math::wrapToPi(p.phi() - q.phi()));
  if (d >= 0.005 || dyaw >= mrpt::DEG2RAD(0.5))
  {
    s_.path_length_m += d;
    gt_path_.push_back(p);
  }
}

void ExploreRun::onMessage(const std::string& line)
{
  if (!quiet_) std::cout << "  " << line << std::endl;
}

std::string ExploreRun::stopReason()
{
  return interruptRequested() ? "interrupted" : std::string();
}

void ExploreRun::onPlanInputs(const exploration::PlanInputs& inputs, const octomap::OcTree& V)
{
  const int keep = cfg_.explore.keep_plan_inputs;
  if (keep <= 0) return;
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(out_dir_) / "plans";
  fs::create_directories(dir);
  const auto name = [&](uint64_t step) { return dir / mrpt::format("step_%03u.txt", static_cast<unsigned>(step + 1)); };
  exploration::writePlanInputs(name(inputs.step).string(), inputs, V);
  if (inputs.step >= static_cast<uint64_t>(keep))
  {
    const fs::path old = name(inputs.step - static_cast<uint64_t>(keep));
    std::error_code ec;
    fs::remove(old, ec);
    fs::remove(old.string() + ".ot", ec);
  }
}

void ExploreRun::onPlan(const exploration::PlanResult& plan, double plan_ms,
                        const mission::ExplorationStatus& status)
{
  s_.steps = status.steps;
  s_.known_floor_m2 = status.known_floor_m2;  // coverage.csv's known_floor_m2 (G's free floor)
  s_.new_frontiers = status.new_frontiers;    // ... and new_frontiers
  const double coverage = plan.ground ? coverageOf(*plan.ground) : 0.0;
  const double coverage_planner =
      plan.ground
          ? explore_detail::coverage2d(*plan.ground, gt_floor_planner_.free_floor, T_world_map_)
          : 0.0;
  if (plan.ground) last_ground_ = plan.ground;
  writeCoverageRow(plan, coverage, coverage_planner, status.slam_ms_step);
  if (cfg_.explore.write_step_images) writeStepImage(plan);
  if (quiet_) return;
  std::cout << mrpt::format(
                   "step %3zu: stops %3zu  sim %6.1f s  path %6.2f m  coverage %5.3f  "
                   "collisions %zu  plan %6.0f ms  slam %6.0f ms  ",
                   s_.steps, s_.stops, sim_.simTime(), s_.path_length_m, coverage,
                   sim_.robot().collisions(), plan_ms, status.slam_ms_step)
            << (plan.ok() ? mrpt::format("-> target (%.2f, %.2f, %.0f deg), %zu waypoints",
                                         plan.target.x(), plan.target.y(),
                                         mrpt::RAD2DEG(plan.target.phi()), plan.waypoints.size())
                          : std::string("done: ") + exploration::toString(plan.done) + " (" +
                                plan.message + ")")
            << std::endl;
}

}  // namespace voxplore::apps
