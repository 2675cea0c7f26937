/* voxplore — StopAndScanDriver's straight drive, its turn at a waypoint, and
 * its own recovery drives, used when MRPT's reactive navigator stalls (a
 * measured weakness of CHolonomicND in 1.1 m corridors, see StopAndScanDriver.h). */
#include <mrpt/core/format.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "drive_log.h"

namespace voxplore::navigation
{
using mrpt::poses::CPose2D;
using namespace detail;

DriveResult StopAndScanDriver::driveStraight(const Eigen::Vector2d& waypoint)
{
  const double r = params_.robotRadius();
  // Is the straight segment (0,0)-(tx,ty) free for the robot's circle?
  const WayCheck circle_way = [r](const std::vector<Eigen::Vector2d>& points, double tx, double ty,
                                  const CPose2D&) -> Ending
  {
    const double d2 = tx * tx + ty * ty;
    double closest = std::numeric_limits<double>::infinity();
    for (const auto& q : points)
    {
      const double u = std::clamp((q.x() * tx + q.y() * ty) / d2, 0.0, 1.0);
      closest = std::min(closest, std::hypot(q.x() - u * tx, q.y() - u * ty));
    }
    if (closest >= r) return std::nullopt;
    return {{DriveOutcome::Blocked,
             mrpt::format("an obstacle lies %.3f m from the straight way (robot radius %.3f m)",
                          closest, r)}};
  };
  return straightDrive(waypoint, std::nullopt, circle_way);
}

DriveResult StopAndScanDriver::straightDrive(const Eigen::Vector2d& waypoint,
                                             std::optional<double> hold_yaw, const WayCheck& way,
                                             double tolerance_m, bool pass, bool turn_on_way,
                                             double corner_speed_mps)
{
  const double tolerance = tolerance_m >= 0 ? tolerance_m : params_.goal_tolerance_m;
  const CPose2D start = robot_.pose();
  const double way_m = distanceTo(start, waypoint);
  // turn_on_way: the yaw goes from the start's to hold_yaw in proportion to
  // the way made, fed forward, and the speed leaves the turn 20 % of max_w
  // to catch up.
  const double turn = turn_on_way && hold_yaw && way_m > tolerance
                          ? mrpt::math::wrapToPi(*hold_yaw - start.phi())
                          : 0.0;
  const double turn_per_m = turn / std::max(way_m, 1e-9);
  const double v_turn =
      turn != 0 ? 0.8 * params_.max_w / std::abs(turn_per_m) : params_.max_v_mps;
  DriveLog log(robot_, way_m);
  mrpt::maps::CSimplePointsMap pts;
  std::vector<Eigen::Vector2d> band;
  Ending end;
  while (!end)
  {
    const CPose2D p = robot_.pose();
    const double d = distanceTo(p, waypoint);
    if (d <= tolerance)
    {
      end = {{DriveOutcome::Reached, mrpt::format("reached within %.3f m", d)}};
      break;
    }
    if (!robot_.obstacles(pts))
    {
      end = {{DriveOutcome::Error, "the robot's obstacle sensors failed"}};
      break;
    }
    double tx, ty;  // the waypoint in the robot frame
    p.inverseComposePoint(waypoint.x(), waypoint.y(), tx, ty);
    bandPoints(pts, params_.min_obstacle_height_m, params_.max_obstacle_height_m, band);
    end = way(band, tx, ty, p);
    if (end) break;
    double ramp = params_.max_v_mps * d / 0.3;  // slowing down over the last 0.3 m
    if (params_.max_accel_mps2 > 0)  // ... and no harder than the base brakes (80 % of it)
      ramp = std::min(ramp, std::sqrt(1.6 * params_.max_accel_mps2 * d));
    const bool corner = pass && corner_speed_mps >= 0;
    double v = std::min(v_turn, !pass   ? std::min(params_.max_v_mps, ramp)
                                : corner ? std::min(params_.max_v_mps, std::max(corner_speed_mps, ramp))
                                         : params_.max_v_mps);
    if (corner) v = std::min(v, d / params_.dt_s);  // lands on the corner
    double w = 0;
    if (hold_yaw)
    {
      const double made = std::clamp(1.0 - d / std::max(way_m, 1e-9), 0.0, 1.0);
      const double want = turn != 0 ? start.phi() + turn * made : *hold_yaw;
      w = std::clamp(turn_per_m * v + params_.yaw_gain * mrpt::math::wrapToPi(want - p.phi()),
                     -params_.max_w, params_.max_w);
    }
    robot_.setVelocity(v * tx / d, v * ty / d, w);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
    end = checkAfterStep(robot_, params_, log, waypoint);
    if (!end) end = guardEnding();
  }
  if (pass && end->first == DriveOutcome::Reached) return passDrive(robot_, log, *end);
  return finishDrive(log, *end);
}

void StopAndScanDriver::turnAtWaypoint(DriveResult& res, std::optional<double> final_yaw_rad,
                                       double final_yaw_period_rad)
{
  if (!res.reached() || !final_yaw_rad) return;
  double yaw = *final_yaw_rad;
  if (final_yaw_period_rad > 0)
    yaw += final_yaw_period_rad *
           std::round(mrpt::math::wrapToPi(robot_.pose().phi() - yaw) / final_yaw_period_rad);
  const DriveResult rot = rotateTo(mrpt::math::wrapToPi(yaw));
  appendDrive(res, rot, "");
  // The waypoint is reached; a turn the footprint cannot make there ends
  // where the guard held it (the scan is taken in that yaw) instead of
  // failing the whole drive.
  if (!rot.guard_held) res.outcome = rot.outcome;
}

DriveResult StopAndScanDriver::escape()
{
  DriveLog log(robot_, 0.0);
  const double r_clear = params_.robotRadius() + params_.escape_clearance_m;
  const int max_esc_steps = static_cast<int>(std::ceil(params_.escape_timeout_s / params_.dt_s));
  mrpt::maps::CSimplePointsMap pts;
  std::vector<Eigen::Vector2d> band;
  std::optional<std::pair<DriveOutcome, std::string>> end;
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; !end; i++)
  {
    if (params_.escape_clearance_m <= 0)
    {
      end = {DriveOutcome::Reached, "off (escape_clearance_m = 0)"};
      break;
    }
    if (!robot_.obstacles(pts))
    {
      end = {DriveOutcome::Error, "the robot's obstacle sensors failed"};
      break;
    }
    // Repulsion of the points in the navigator's height band within r_clear.
    bandPoints(pts, params_.min_obstacle_height_m, params_.max_obstacle_height_m, band);
    double vx = 0, vy = 0;
    nearest = std::numeric_limits<double>::infinity();
    for (const auto& q : band)
    {
      const double d = q.norm();
      nearest = std::min(nearest, d);
      if (d >= r_clear || d < 1e-6) continue;
      vx -= q.x() / d * (r_clear - d);
      vy -= q.y() / d * (r_clear - d);
    }
    const double v = std::hypot(vx, vy);
    if (collisionsOf(robot_) > log.collisions0)
      end = {DriveOutcome::Error, "the robot reported a collision while backing off"};
    else if (nearest >= r_clear)
      end = {DriveOutcome::Reached, mrpt::format("clear, nearest obstacle %.3f m", nearest)};
    else if (const auto held = guardEnding())
      end = *held;
    else if (v < 1e-3)
      end = {DriveOutcome::Blocked,
             mrpt::format("pinched from both sides, nearest obstacle %.3f m", nearest)};
    else if (i >= max_esc_steps)
      end = {DriveOutcome::Blocked,
             mrpt::format("still %.3f m from an obstacle after escape_timeout_s = %.1f s", nearest,
                          params_.escape_timeout_s)};
    if (end) break;
    robot_.setVelocity(params_.escape_speed_mps * vx / v, params_.escape_speed_mps * vy / v, 0.0);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
  }
  return finishDrive(log, *end);
}

DriveResult StopAndScanDriver::backOffFootprint()
{
  DriveLog log(robot_, 0.0);
  const double hl = 0.5 * params_.footprint_length_m, hw = 0.5 * params_.footprint_width_m;
  const double target = params_.guard_margin_m + params_.footprint_backoff_m;
  const int max_steps = static_cast<int>(std::ceil(params_.escape_timeout_s / params_.dt_s));
  mrpt::maps::CSimplePointsMap pts;
  std::vector<Eigen::Vector2d> band;
  Ending end;
  for (int i = 0; !end; i++)
  {
    if (!params_.footprint_guard || params_.footprint_backoff_m <= 0)
    {
      end = {{DriveOutcome::Reached, "off"}};
      break;
    }
    if (!robot_.obstacles(pts))
    {
      end = {{DriveOutcome::Error, "the robot's obstacle sensors failed"}};
      break;
    }
    bandPoints(pts, params_.min_obstacle_height_m, params_.max_obstacle_height_m, band);
    // Each point pushes the rectangle away from it: along the vector from
    // its nearest point of the rectangle to it, or, inside, out through the
    // nearer side. The same pass gives the clearance (rectangleClearance).
    Eigen::Vector2d push(0, 0);
    double weight = 0, clearance = std::numeric_limits<double>::infinity();
    for (const auto& q : band)
    {
      const double ex = std::abs(q.x()) - hl, ey = std::abs(q.y()) - hw;
      Eigen::Vector2d out(std::copysign(std::max(ex, 0.0), q.x()),
                          std::copysign(std::max(ey, 0.0), q.y()));
      double d = out.norm();
      clearance = std::min(clearance, d);
      if (d >= target) continue;
      if (d < 1e-9)
      {
        out = ex > ey ? Eigen::Vector2d(std::copysign(1.0, q.x()), 0.0)
                      : Eigen::Vector2d(0.0, std::copysign(1.0, q.y()));
        d = 0;
      }
      push -= out.normalized() * (target - d);
      weight += target - d;
    }
    if (collisionsOf(robot_) > log.collisions0)
      end = {{DriveOutcome::Error, "the robot reported a collision while backing off"}};
    else if (clearance >= target || (i == 0 && clearance >= target - 0.5 * params_.footprint_backoff_m))
      end = {{DriveOutcome::Reached, mrpt::format("clear, footprint clearance %.3f m", clearance)}};
    else if (const auto held = guardEnding())
      end = held;
    else if (push.norm() < 0.2 * weight)
      end = {{DriveOutcome::Blocked,
              mrpt::format("pinched from both sides, footprint clearance %.3f m", clearance)}};
    else if (i >= max_steps)
      end = {{DriveOutcome::Blocked,
              mrpt::format("footprint clearance still %.3f m after escape_timeout_s = %.1f s",
                           clearance, params_.escape_timeout_s)}};
    if (end) break;
    const Eigen::Vector2d v = params_.escape_speed_mps * push.normalized();
    robot_.setVelocity(v.x(), v.y(), 0.0);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
  }
  return finishDrive(log, *end);
}

}  // namespace voxplore::navigation
