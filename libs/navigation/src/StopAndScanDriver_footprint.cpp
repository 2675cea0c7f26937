/* voxplore — StopAndScanDriver's footprint drive (issue 13): through a
 * passage narrower than the circle MRPT's PTGs know, turn to the planned yaw,
 * then translate (the base is holonomic) holding it. Our own code: MRPT's
 * CPTG_Holo_Blend models the robot as a circle. */
#include <mrpt/core/format.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "FootprintGuard.h"
#include "drive_log.h"

namespace voxplore::navigation
{
using mrpt::poses::CPose2D;
using namespace detail;

DriveResult StopAndScanDriver::driveFootprint(const Eigen::Vector2d& waypoint, double yaw_rad)
{
  DriveResult res;
  bool turned = false;
  if (std::abs(mrpt::math::wrapToPi(yaw_rad - robot_.pose().phi())) > params_.yaw_tolerance)
  {
    res = rotateTo(yaw_rad);
    turned = true;
    if (!res.reached())
    {
      res.goal_distance_m = distanceTo(res.final_pose, waypoint);
      res.message = "turn to the planned yaw: " + res.message;
      return res;
    }
  }
  DriveLog log(robot_, distanceTo(robot_.pose(), waypoint));
  constexpr int kHysteresis = 3;  // steps in a row the waypoint pose must be seen not free
  int blocked_steps = 0;
  const double hl = 0.5 * params_.footprint_length_m, hw = 0.5 * params_.footprint_width_m;
  mrpt::maps::CSimplePointsMap pts;
  std::vector<Eigen::Vector2d> near;
  Ending end;
  while (!end)
  {
    const CPose2D p = robot_.pose();
    const double d = distanceTo(p, waypoint);
    if (d <= params_.goal_tolerance_m)
    {
      end = {{DriveOutcome::Reached, mrpt::format("reached within %.3f m", d)}};
      break;
    }
    if (!robot_.obstacles(pts))
    {
      end = {{DriveOutcome::Error, "the robot's obstacle sensors failed"}};
      break;
    }
    // The rectangle at the waypoint, in the yaw held, must be free of sensed points.
    double tx, ty;  // the waypoint in the robot frame
    p.inverseComposePoint(waypoint.x(), waypoint.y(), tx, ty);
    const double dyaw = mrpt::math::wrapToPi(yaw_rad - p.phi());
    near.clear();
    const auto& xs = pts.getPointsBufferRef_x();
    const auto& ys = pts.getPointsBufferRef_y();
    const auto& zs = pts.getPointsBufferRef_z();
    for (std::size_t k = 0; k < xs.size(); k++)
      if (zs[k] >= params_.min_obstacle_height_m && zs[k] <= params_.max_obstacle_height_m)
        near.emplace_back(xs[k], ys[k]);
    const double at_goal = rectangleClearance(near, hl, hw, CPose2D(tx, ty, dyaw));
    blocked_steps = at_goal <= 0 ? blocked_steps + 1 : 0;
    if (blocked_steps >= kHysteresis)
    {
      end = {{DriveOutcome::Blocked,
              "a sensed obstacle point lies inside the footprint at the waypoint"}};
      break;
    }
    const double v = std::min(params_.max_v_mps, params_.max_v_mps * d / 0.3);
    const double w = std::clamp(params_.yaw_gain * dyaw, -params_.max_w, params_.max_w);
    robot_.setVelocity(v * tx / d, v * ty / d, w);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
    end = checkAfterStep(robot_, params_, log, waypoint);
    if (!end) end = guardEnding();
  }
  DriveResult tr = finishDrive(log, *end);
  if (!turned) return tr;
  appendDrive(res, tr, "");
  res.outcome = tr.outcome;
  res.guard_held = tr.guard_held;
  res.goal_distance_m = tr.goal_distance_m;
  return res;
}

}  // namespace voxplore::navigation
