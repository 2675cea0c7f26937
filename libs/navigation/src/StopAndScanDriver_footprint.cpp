/* voxplore — StopAndScanDriver's footprint drive (issue 13): through a
 * passage narrower than the circle MRPT's PTGs know, turn to the planned yaw,
 * then translate (the base is holonomic) holding it. Our own code: MRPT's
 * CPTG_Holo_Blend models the robot as a circle. */
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <cmath>
#include <vector>

#include "FootprintGuard.h"
#include "drive_log.h"

namespace voxplore::navigation
{
using mrpt::poses::CPose2D;
using namespace detail;

DriveResult StopAndScanDriver::driveFootprint(const Eigen::Vector2d& waypoint, double yaw_rad,
                                              std::optional<double> final_yaw_rad)
{
  const DriveResult pre = backOffFootprint();
  if (pre.outcome == DriveOutcome::Error) return pre;
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
      prependDrive(pre, res);
      return res;
    }
  }
  // The rectangle at the waypoint, in the yaw held, must be free of sensed
  // points, kHysteresis steps in a row.
  constexpr int kHysteresis = 3;
  int blocked_steps = 0;
  std::vector<Eigen::Vector2d> blocking;
  const double hl = 0.5 * params_.footprint_length_m, hw = 0.5 * params_.footprint_width_m;
  const WayCheck rectangle_at_goal = [&](const std::vector<Eigen::Vector2d>& points, double tx,
                                         double ty, const CPose2D& p) -> Ending
  {
    const double dyaw = mrpt::math::wrapToPi(yaw_rad - p.phi());
    const CPose2D at(tx, ty, dyaw);
    const double at_goal = rectangleClearance(points, hl, hw, at);
    blocked_steps = at_goal <= 0 ? blocked_steps + 1 : 0;
    if (blocked_steps < kHysteresis) return std::nullopt;
    for (const auto& q : points)
    {
      double u, v;
      at.inverseComposePoint(q.x(), q.y(), u, v);
      if (std::abs(u) > hl || std::abs(v) > hw) continue;
      double mx, my;
      p.composePoint(q.x(), q.y(), mx, my);
      blocking.emplace_back(mx, my);
    }
    return {{DriveOutcome::Blocked,
             "a sensed obstacle point lies inside the footprint at the waypoint"}};
  };
  DriveResult tr = straightDrive(waypoint, yaw_rad, rectangle_at_goal);
  tr.blocking_points = std::move(blocking);
  if (turned)
  {
    appendDrive(res, tr, "");
    res.outcome = tr.outcome;
    res.guard_held = tr.guard_held;
    res.blocking_points = tr.blocking_points;
  }
  else
    res = tr;
  res.goal_distance_m = distanceTo(res.final_pose, waypoint);
  turnAtWaypoint(res, final_yaw_rad);
  prependDrive(pre, res);
  return res;
}

}  // namespace voxplore::navigation
