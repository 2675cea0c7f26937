/* voxplore — the exploration loop's drives (thesis fig. 4.4, "drive to the
 * waypoints"): a plan's waypoints through StopAndScanDriver, stopping to scan
 * or (scan_mode = continuous) passing them. Split from ExplorationLoop.cpp. */
#include <mrpt/core/format.h>
#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <optional>
#include <string>

namespace voxplore::mission
{
ExplorationLoop::Drive ExplorationLoop::driveWaypoints(exploration::PlanResult& plan)
{
  const auto& wps = plan.waypoints;
  const bool continuous = params_.scan_mode == ExplorationLoopParams::ScanMode::Continuous;
  for (std::size_t i = 0; i < wps.size(); i++)
  {
    if (continuous)
    {
      leadInOnTheWay(plan, i);
      turnFirstOnTheWay(plan, i);
    }
    const bool last = i + 1 == wps.size();
    // scan_mode = continuous: through the waypoint without stopping; the
    // scans are taken on the way (onRobotStep).
    const std::optional<Pass> pass_tol = continuous ? passTolerance(plan, i) : std::nullopt;
    const bool pass = pass_tol.has_value();
    const navigation::DriveResult r = driveWaypoint(plan, i, pass_tol);
    settleScan();  // the checks below read the map
    status_.guard_scaled = driver_->guardScaledCommands();
    status_.guard_held = driver_->guardHeldCommands();
    if (!pass || !r.reached()) scanAndIntegrate();  // a drive that did not pass stopped
    else if (last)  // the view, passed (passTolerance)
    {
      status_.scans_moving++;
      scanAndIntegrate(true);
    }
    // A standing scan takes simulated time too (the sensor's exposure): a
    // limit it reached ends the run here, not one robot step into the next
    // drive (max_sim_time_s overshot by two steps: a drive ended at a stop,
    // replan_at_stops, whose scan reached the limit).
    if (!last) stopIfLimitReached();
    if (!r.reached())
    {
      noteFailedDrive(plan, i, r);
      return Drive::Failed;
    }
    if (pass && !last && params_.replan_on_the_way && targetSeen(plan))
    {
      status_.targets_seen_on_the_way++;
      return Drive::TargetSeen;  // moving: the next plan's first drive goes on from here
    }
    // Stop-and-scan (replan_at_stops): the scan at this stop saw the plan's
    // frontier; the next plan starts from here, standing.
    if (!continuous && !last && replan_at_stops_ && targetSeen(plan))
    {
      status_.targets_seen_on_the_way++;
      return Drive::TargetSeen;
    }
    if (!last && lowObstacleInterrupts(plan, i, continuous)) return Drive::Interrupted;
  }
  return Drive::Reached;
}

navigation::DriveResult ExplorationLoop::driveWaypoint(const exploration::PlanResult& plan,
                                                       std::size_t i, const std::optional<Pass>& pass)
{
  const auto& w = plan.waypoints[i];
  const std::optional<double> final_yaw =
      i + 1 == plan.waypoints.size() ? std::optional<double>(plan.target.phi()) : std::nullopt;
  const bool turn = i < plan.waypoint_turn_on_way.size() && plan.waypoint_turn_on_way[i];
  // [collision] model = footprint: where the planner's circle does not fit,
  // drive the rectangle in the planned yaw, not MRPT's circle.
  if (i < plan.waypoint_narrow.size() && plan.waypoint_narrow[i])
    return pass ? driver_->passFootprint(w, plan.waypoint_yaws[i], pass->tolerance_m, turn,
                                         pass->corner_speed_mps)
                : driver_->driveFootprint(w, plan.waypoint_yaws[i], final_yaw, turn);
  return pass ? driver_->passBy(w, pass->tolerance_m, faceYaw(plan, i))
              : driver_->driveTo(w, final_yaw, view_period_, faceYaw(plan, i));
}

void ExplorationLoop::noteFailedDrive(const exploration::PlanResult& plan, std::size_t i,
                                      const navigation::DriveResult& r)
{
  const auto& wps = plan.waypoints;
  rememberObstacles(r.blocking_points);
  status_.failed_drives++;
  message("waypoint " + std::to_string(i + 1) + "/" + std::to_string(wps.size()) + " (" +
          mrpt::format("%.2f, %.2f", wps[i].x(), wps[i].y()) +
          "): " + navigation::toString(r.outcome) + ": " + r.message + "; replanning");
  registerFailure(plan.frontier ? plan.frontier->center : wps.back());
}

bool ExplorationLoop::lowObstacleInterrupts(const exploration::PlanResult& plan, std::size_t i,
                                            bool continuous)
{
  // Not twice without the robot moving in between: a new plan ended at
  // its first stop, standing, again and again, would never drive.
  const bool moved = status_.path_length_m - path_at_interrupt_ >= params_.min_progress_m;
  if (!low_replan_ || !moved || !lowObstacleAhead(plan, i + 1)) return false;
  path_at_interrupt_ = status_.path_length_m;
  status_.low_obstacle_replans++;
  if (continuous)  // the next plan starts from a standing robot's scan, as stop-and-scan's
  {
    robot_.stop();
    scanAndIntegrate();
  }
  message("waypoint " + std::to_string(i + 1) + "/" + std::to_string(plan.waypoints.size()) +
          ": a low obstacle seen on the rest of the path; replanning");
  return true;
}

}  // namespace voxplore::mission
