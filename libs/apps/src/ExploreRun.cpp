// voxplore-explore: the exploration loop (thesis fig. 4.4) with stop-and-scan
// driving (thesis 4.6): scan -> SlamIcp -> plan -> one waypoint at a time,
// stop and scan at each; a failed drive scans and replans, a frontier that
// fails max_failures_per_target times is blacklisted (as explore_lite does).
#include <mrpt/core/format.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <iostream>

#include <voxplore/apps/app_common.h>

#include "ExploreApp_internal.h"
#include "ExploreRun.h"

namespace voxplore::apps
{
namespace
{
/// Thrown from a robot step to end the run there (mid-drive): SIGINT /
/// SIGTERM, or the simulated time limit. Not a std::exception, so that no
/// error handler on the way mistakes it for a failure.
struct RunStopped
{
  const char* reason;
};

double secondsSince(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

ExploreRun::ExploreRun(
    sim::Simulator& sim, const ExploreConfig& cfg, std::string out_dir, bool quiet)
    : sim_(sim),
      cfg_(cfg),
      out_dir_(std::move(out_dir)),
      quiet_(quiet),
      robot_(sim),
      slam_(cfg.slam),
      T_world_map_(sim.robot().groundTruth())
{
  driver_ = std::make_unique<navigation::StopAndScanDriver>(robot_, cfg_.driver);
  robot_.on_step = [this]() { onRobotStep(); };
  // Between stops the navigator sees the SLAM pose of the last stop composed
  // with the odometry increment since then (never the ground truth).
  robot_.setPoseSource(
      [this]() { return pose_at_stop_ + (robot_.odometry() - odo_at_stop_); });
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
}

void ExploreRun::computeGroundTruthFloor(const Eigen::AlignedBox2d* region)
{
  // coverage_2d: the floor the robot's real footprint (the rotated rectangle
  // the simulator's collision checker tests) reaches from the start, over
  // position and yaw, plus the floor its cameras see from there (issue 10).
  const auto t0 = std::chrono::steady_clock::now();
  const sim::Footprint footprint = cfg_.sim.robot.footprint();
  sim::FootprintReachParams fp;
  fp.res_m = cfg_.explore.gt_floor_res_m;
  fp.yaw_bins = cfg_.explore.coverage_yaw_bins;
  fp.view_range_m = cfg_.explore.coverage_view_range_m;
  gt_floor_ = sim::footprintReachableFloor(sim_.world(), sim_.checker(), T_world_map_, footprint,
                                           fp, region);
  gt_floor_.bins = {};  // the per-state masks are not needed after this (16 B per cell)
  const double footprint_s = secondsSince(t0);
  // Beside it, the circles: the planner's collision radius r_coll + sqrt(2)
  // l_res (thesis eq. 4.4; a passage narrower than that is out of the
  // method's reach by design) and the bare circumcircle.
  const auto t1 = std::chrono::steady_clock::now();
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
                   s_.floor_reachable_circumradius_m2, secondsSince(t1))
            << std::endl;
}

ExploreSummary ExploreRun::execute()
{
  openOutputs();
  try
  {
    loop();
  }
  catch (const RunStopped& stop)  // between two robot steps of a drive
  {
    robot_.stop();
    s_.termination_reason = stop.reason;
  }
  catch (const std::exception& e)
  {
    saveMapsAfterFailure();
    throw std::runtime_error(std::string(e.what()) + " (the maps and logs of the " +
                             std::to_string(slam_.numStops()) + " stops so far are in " +
                             out_dir_ + ")");
  }
  finish();
  if (last_ground_)
    explore_detail::writeCoverageMap(*last_ground_, gt_floor_, gt_floor_planner_, gt_floor_body_,
                                     T_world_map_, gt_path_, out_dir_ + "/coverage_map.png");
  return s_;
}

void ExploreRun::loop()
{
  scanAndIntegrate();
  for (std::size_t step = 0;; step++)
  {
    if (interruptRequested())
    {
      s_.termination_reason = "interrupted";
      return;
    }
    if (step >= static_cast<std::size_t>(cfg_.explore.max_steps))
    {
      s_.termination_reason = "max_steps";
      return;
    }
    if (sim_.simTime() >= cfg_.explore.max_sim_time_s)
    {
      s_.termination_reason = "max_sim_time";
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const auto plan = exploration::plan(slam_.octomap().tree(), slam_.currentPose(), cfg_.planner,
                                        blacklist_, step, swept_);
    const double plan_s = secondsSince(t0);
    compute_s_ += plan_s;
    s_.steps = step + 1;
    reportStep(plan, plan_s * 1e3);
    slam_ms_step_ = 0;
    if (!plan.ok())
    {
      s_.termination_reason = exploration::toString(plan.done);
      return;
    }
    // A frontier planned again and again without disappearing (an unseeable
    // hole, a target the robot already stands on) is given up, and a step
    // that does not move the robot counts as a failed drive.
    const Eigen::Vector2d target =
        plan.frontier ? plan.frontier->center : Eigen::Vector2d(plan.target.x(), plan.target.y());
    registerPlan(target);
    const double path_before = s_.path_length_m;
    if (driveWaypoints(plan) && s_.path_length_m - path_before < cfg_.explore.min_progress_m)
      registerFailure(target);
  }
}

void ExploreRun::scanAndIntegrate()
{
  const auto stop = sim_.scan();
  rawlog_->write(*stop.actions, *stop.observations);
  const double t = mrpt::Clock::toDouble(stop.timestamp);
  gt_tum_->write(t, mrpt::poses::CPose3D(stop.T_world_robot_gt));
  const auto t0 = std::chrono::steady_clock::now();
  const auto rep = slam_.processStop(*stop.observations, stop.odometry, stop.timestamp);
  const double dt = secondsSince(t0);
  compute_s_ += dt;
  slam_ms_step_ += dt * 1e3;
  est_tum_->write(t, mrpt::poses::CPose3D(rep.pose));
  pose_at_stop_ = rep.pose;
  odo_at_stop_ = robot_.odometry();
  if (rep.loop.closed)
  {
    // The poses so far were corrected: the swept path follows them.
    swept_.clear();
    for (const auto& r : slam_.reports()) addSwept({r.pose.x(), r.pose.y()});
    if (!quiet_)
      std::cout << "  stop " << rep.index << ": " << rep.loop.message
                << (rep.loop.rebuilt ? mrpt::format("; maps rebuilt in %.0f ms", rep.loop.t_rebuild_ms)
                                     : std::string())
                << std::endl;
  }
  addSwept({rep.pose.x(), rep.pose.y()});
  s_.stops = slam_.numStops();
  for (const auto& w : rep.warnings)
    std::cerr << "voxplore-explore: warning: stop " << rep.index << ": " << w << std::endl;
  if (rep.flagged && !quiet_)
    std::cout << "  stop " << rep.index << ": ICP flagged (" << rep.icp.reason
              << "), pose from odometry" << std::endl;
}

bool ExploreRun::driveWaypoints(const exploration::PlanResult& plan)
{
  const auto& wps = plan.waypoints;
  for (std::size_t i = 0; i < wps.size(); i++)
  {
    const bool last = i + 1 == wps.size();
    const auto r = driver_->driveTo(wps[i], last ? std::optional<double>(plan.target.phi())
                                                 : std::nullopt);
    scanAndIntegrate();
    if (!r.reached())
    {
      s_.failed_drives++;
      if (!quiet_)
        std::cout << "  waypoint " << i + 1 << "/" << wps.size() << " ("
                  << mrpt::format("%.2f, %.2f", wps[i].x(), wps[i].y())
                  << "): " << navigation::toString(r.outcome) << ": " << r.message
                  << "; replanning" << std::endl;
      registerFailure(plan.frontier ? plan.frontier->center : wps.back());
      return false;
    }
  }
  return true;
}

void ExploreRun::registerFailure(const Eigen::Vector2d& target)
{
  const double radius = cfg_.planner.sampling.blacklist_radius_m;
  auto it = std::find_if(failures_.begin(), failures_.end(),
                         [&](const auto& f) { return (f.first - target).norm() <= radius; });
  if (it == failures_.end())
  {
    failures_.emplace_back(target, 0);
    it = std::prev(failures_.end());
  }
  if (++it->second >= cfg_.explore.max_failures_per_target)
  {
    blacklist_.push_back(target);
    s_.blacklisted = blacklist_.size();
    if (!quiet_)
      std::cout << "  target " << mrpt::format("(%.2f, %.2f)", target.x(), target.y())
                << " failed " << it->second << " times: blacklisted" << std::endl;
  }
}

void ExploreRun::registerPlan(const Eigen::Vector2d& target)
{
  if (cfg_.explore.max_plans_per_target <= 0) return;
  const double radius = cfg_.planner.sampling.blacklist_radius_m;
  auto it = std::find_if(plans_.begin(), plans_.end(),
                         [&](const auto& f) { return (f.first - target).norm() <= radius; });
  if (it == plans_.end())
  {
    plans_.emplace_back(target, 0);
    it = std::prev(plans_.end());
  }
  if (++it->second >= cfg_.explore.max_plans_per_target)
  {
    blacklist_.push_back(target);
    s_.blacklisted = blacklist_.size();
    it->second = std::numeric_limits<int>::min();  // once
    if (!quiet_)
      std::cout << "  target " << mrpt::format("(%.2f, %.2f)", target.x(), target.y())
                << " planned " << cfg_.explore.max_plans_per_target
                << " times without being explored: blacklisted" << std::endl;
  }
}

void ExploreRun::addSwept(const Eigen::Vector2d& e)
{
  // The swept path in the pose estimate, 5 cm apart and continuous across
  // the jump of a SLAM correction at a stop (the body's true path is
  // continuous; either side of the jump is within the pose error).
  if (swept_.empty())
  {
    swept_.push_back(e);
    return;
  }
  const double d = (e - swept_.back()).norm();
  if (d < 0.05) return;
  const Eigen::Vector2d from = swept_.back();
  const int n = static_cast<int>(std::ceil(d / 0.05));
  for (int k = 1; k <= n; ++k) swept_.push_back(from + (e - from) * (double(k) / n));
}

void ExploreRun::onRobotStep()
{
  const auto est = robot_.pose();  // the estimate the navigator drives by
  addSwept({est.x(), est.y()});
  const auto& p = sim_.robot().groundTruth();
  const auto& q = gt_path_.back();
  const double d = std::hypot(p.x() - q.x(), p.y() - q.y());
  const double dyaw = std::abs(mrpt::math::wrapToPi(p.phi() - q.phi()));
  if (d >= 0.005 || dyaw >= mrpt::DEG2RAD(0.5))
  {
    s_.path_length_m += d;
    gt_path_.push_back(p);
  }
  // The limits hold inside a drive too (a drive may last minutes).
  if (interruptRequested()) throw RunStopped{"interrupted"};
  if (sim_.simTime() >= cfg_.explore.max_sim_time_s) throw RunStopped{"max_sim_time"};
}

void ExploreRun::reportStep(const exploration::PlanResult& plan, double plan_ms)
{
  const double coverage = plan.ground ? coverageOf(*plan.ground) : 0.0;
  const double coverage_planner =
      plan.ground
          ? explore_detail::coverage2d(*plan.ground, gt_floor_planner_.free_floor, T_world_map_)
          : 0.0;
  if (plan.ground) last_ground_ = plan.ground;
  writeCoverageRow(plan, coverage, coverage_planner);
  if (cfg_.explore.write_step_images) writeStepImage(plan);
  if (quiet_) return;
  std::cout << mrpt::format(
                   "step %3zu: stops %3zu  sim %6.1f s  path %6.2f m  coverage %5.3f  "
                   "collisions %zu  plan %6.0f ms  slam %6.0f ms  ",
                   s_.steps, s_.stops, sim_.simTime(), s_.path_length_m, coverage,
                   sim_.robot().collisions(), plan_ms, slam_ms_step_)
            << (plan.ok() ? mrpt::format("-> target (%.2f, %.2f, %.0f deg), %zu waypoints",
                                         plan.target.x(), plan.target.y(),
                                         mrpt::RAD2DEG(plan.target.phi()), plan.waypoints.size())
                          : std::string("done: ") + exploration::toString(plan.done) + " (" +
                                plan.message + ")")
            << std::endl;
}

}  // namespace voxplore::apps
