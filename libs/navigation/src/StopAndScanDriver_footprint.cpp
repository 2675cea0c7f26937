/* voxplore — StopAndScanDriver's footprint drive (issue 13): through a
 * passage narrower than the circle MRPT's PTGs know, turn to the planned yaw,
 * then translate (the base is holonomic) holding it. Our own code: MRPT's
 * CPTG_Holo_Blend models the robot as a circle. */
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <mrpt/maps/CSimplePointsMap.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "FootprintGuard.h"
#include "drive_log.h"

namespace voxplore::navigation
{
using mrpt::poses::CPose2D;
using namespace detail;

namespace
{
/// The obstacle points the robot senses in the navigator's height band
/// (robot frame); nullopt when its sensors fail.
std::optional<std::vector<Eigen::Vector2d>> sensedBand(RobotInterface& robot, const DriverParams& p)
{
  mrpt::maps::CSimplePointsMap pts;
  if (!robot.obstacles(pts)) return std::nullopt;
  std::vector<Eigen::Vector2d> band;
  bandPoints(pts, p.min_obstacle_height_m, p.max_obstacle_height_m, band);
  return band;
}

/// The least sideways offset, a multiple of 5 mm up to max_m, either way
/// (+ first), for which ok(offset) holds.
template <typename Ok>
std::optional<double> leastSideways(double max_m, const Ok& ok)
{
  constexpr double kStep = 0.005;
  const int steps = static_cast<int>(std::floor(max_m / kStep + 1e-9));
  for (int k = 1; k <= steps; ++k)
    for (const double sign : {1.0, -1.0})
      if (ok(sign * k * kStep)) return sign * k * kStep;
  return std::nullopt;
}
}  // namespace

DriveResult StopAndScanDriver::driveFootprint(const Eigen::Vector2d& waypoint, double yaw_rad,
                                              std::optional<double> final_yaw_rad,
                                              bool turn_on_way)
{
  return footprintDrive(waypoint, yaw_rad, final_yaw_rad, -1.0, turn_on_way);
}

DriveResult StopAndScanDriver::passFootprint(const Eigen::Vector2d& waypoint, double yaw_rad,
                                             double tolerance_m, bool turn_on_way,
                                             double corner_speed_mps)
{
  if (!(tolerance_m > 0))
    throw std::invalid_argument("StopAndScanDriver::passFootprint: tolerance_m must be > 0");
  return footprintDrive(waypoint, yaw_rad, std::nullopt, tolerance_m, turn_on_way,
                        corner_speed_mps);
}

DriveResult StopAndScanDriver::footprintDrive(const Eigen::Vector2d& waypoint, double yaw_rad,
                                              std::optional<double> final_yaw_rad,
                                              double pass_tolerance_m, bool turn_on_way,
                                              double corner_speed_mps)
{
  const bool pass = pass_tolerance_m > 0;
  DriveResult pre;  // no steps: prependDrive() leaves the drive as it is
  pre.outcome = DriveOutcome::Reached;
  if (!isMoving(robot_)) pre = backOffFootprint();  // a stop left close to a wall; a pass goes on
  if (pre.outcome == DriveOutcome::Error) return pre;
  DriveResult res;
  bool turned = false;
  // A turn the planner checked along the way is made there, unless the
  // robot is (about) at the waypoint already.
  turn_on_way = turn_on_way && distanceTo(robot_.pose(), waypoint) >
                                   (pass ? pass_tolerance_m : params_.goal_tolerance_m);
  if (!turn_on_way &&
      std::abs(mrpt::math::wrapToPi(yaw_rad - robot_.pose().phi())) > params_.yaw_tolerance)
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
  DriveResult tr = straightDrive(waypoint, yaw_rad, rectangle_at_goal,
                                 pass ? pass_tolerance_m : -1.0, pass, turn_on_way,
                                 pass ? corner_speed_mps : -1.0);
  // Blocked at the waypoint by points inside the rectangle there: the map
  // (and the plan on it) may be off by a few centimetres where the body has
  // centimetres to spare, in a door. Centre the waypoint on what the sensors
  // see: move it sideways by the least amount up to footprint_centring_m that
  // keeps the guard's margin from every sensed point, and drive once more
  // (b13, omniRob, nbv: in a door with 4 cm a side, every plan's first
  // waypoint lay on the swept path 5 cm towards a jamb, registered before a
  // correction; 110 plans were blocked there and the run ended at 0.59).
  if (tr.outcome == DriveOutcome::Blocked && !blocking.empty() && params_.footprint_centring_m > 0)
  {
    if (const auto centred = centredWaypoint(waypoint, yaw_rad))
    {
      std::vector<Eigen::Vector2d> first = std::move(blocking);
      blocking.clear();
      blocked_steps = 0;
      DriveResult again = straightDrive(*centred, yaw_rad, rectangle_at_goal);
      again.message = mrpt::format("waypoint centred by %.3f m: ", (*centred - waypoint).norm()) +
                      again.message;
      continueDrive(tr, again);
      if (again.outcome != DriveOutcome::Blocked)
        blocking.clear();
      else if (blocking.empty())
        blocking = std::move(first);
    }
  }
  // Held by the guard on the way (not at the waypoint): the straight line
  // passes a door post closer than the guard's margin, where a line a few
  // centimetres to one side keeps it. The planner's states lie on cell
  // centres, up to half a cell off a door's middle ([collision]
  // footprint_lateral_m); the waypoint was never blocked, so the centring
  // above does not apply. Move sideways, then along the parallel line to the
  // waypoint moved as far (b1, omniRob, nbv: a 0.87 m door, every drive
  // held 3 cm from a post and the room behind it blacklisted).
  if (tr.outcome == DriveOutcome::Blocked && tr.guard_held && blocking.empty() &&
      params_.footprint_centring_m > 0)
  {
    if (const auto side = laneOffset(waypoint, yaw_rad))
    {
      const CPose2D from = robot_.pose();
      const Eigen::Vector2d n(-std::sin(yaw_rad), std::cos(yaw_rad));
      const Eigen::Vector2d beside = Eigen::Vector2d(from.x(), from.y()) + *side * n;
      // The move sideways is a few centimetres, under goal_tolerance_m.
      DriveResult again = straightDrive(
          beside, yaw_rad, [](auto&&...) -> Ending { return std::nullopt; }, 0.003);
      if (again.reached())
      {
        blocked_steps = 0;
        continueDrive(again, straightDrive(waypoint + *side * n, yaw_rad, rectangle_at_goal));
      }
      again.message = mrpt::format("lane moved %.3f m sideways: ", *side) + again.message;
      continueDrive(tr, again);
    }
  }
  tr.blocking_points = std::move(blocking);
  if (turned)
  {
    continueDrive(res, tr);
    res.blocking_points = tr.blocking_points;
  }
  else
    res = tr;
  res.goal_distance_m = distanceTo(res.final_pose, waypoint);
  turnAtWaypoint(res, final_yaw_rad);
  prependDrive(pre, res);
  return res;
}

std::optional<Eigen::Vector2d> StopAndScanDriver::centredWaypoint(const Eigen::Vector2d& waypoint,
                                                                   double yaw_rad)
{
  const auto band = sensedBand(robot_, params_);
  if (!band) return std::nullopt;
  const CPose2D p = robot_.pose();
  const double hl = 0.5 * params_.footprint_length_m, hw = 0.5 * params_.footprint_width_m;
  const Eigen::Vector2d side(-std::sin(yaw_rad), std::cos(yaw_rad));
  const auto s = leastSideways(params_.footprint_centring_m, [&](double s) {
    const Eigen::Vector2d w = waypoint + s * side;
    double tx, ty;
    p.inverseComposePoint(w.x(), w.y(), tx, ty);
    const CPose2D at(tx, ty, mrpt::math::wrapToPi(yaw_rad - p.phi()));
    return rectangleClearance(*band, hl, hw, at) >= params_.guard_margin_m;
  });
  if (!s) return std::nullopt;
  return Eigen::Vector2d(waypoint + *s * side);
}

std::optional<double> StopAndScanDriver::laneOffset(const Eigen::Vector2d& waypoint, double yaw_rad)
{
  const auto sensed = sensedBand(robot_, params_);
  if (!sensed) return std::nullopt;
  const std::vector<Eigen::Vector2d>& band = *sensed;
  const CPose2D p = robot_.pose();
  const double hl = 0.5 * params_.footprint_length_m, hw = 0.5 * params_.footprint_width_m;
  const Eigen::Vector2d n(-std::sin(yaw_rad), std::cos(yaw_rad));
  const Eigen::Vector2d here(p.x(), p.y());
  // The rectangle at the held yaw and at the yaw the robot has now (it may
  // not get to turn in a door), every 1 cm along both legs, keeps the
  // guard's margin, or where the robot stands nearer (the guard held it at
  // its margin) no less than it has there.
  const double now = rectangleClearance(band, hl, hw, CPose2D(0, 0, 0));
  const double need = std::min(params_.guard_margin_m, now - 1e-3);
  // The line itself keeps a few millimetres more than the guard's margin
  // (the guard holds a command that would come nearer within its horizon).
  constexpr double kSpare = 0.005;
  const auto keeps = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double min_m) {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.01)));
    for (int i = 0; i <= steps; ++i)
    {
      const Eigen::Vector2d q = a + (b - a) * (static_cast<double>(i) / steps);
      double tx, ty;
      p.inverseComposePoint(q.x(), q.y(), tx, ty);
      for (const double dyaw : {mrpt::math::wrapToPi(yaw_rad - p.phi()), 0.0})
        if (rectangleClearance(band, hl, hw, CPose2D(tx, ty, dyaw)) < min_m) return false;
    }
    return true;
  };
  return leastSideways(params_.footprint_centring_m, [&](double s) {
    return keeps(here, here + s * n, need) &&
           keeps(here + s * n, waypoint + s * n, params_.guard_margin_m + kSpare);
  });
}

}  // namespace voxplore::navigation
