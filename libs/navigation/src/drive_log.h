/* voxplore — bookkeeping shared by StopAndScanDriver's drives (internal). */
#pragma once

#include <mrpt/core/format.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace voxplore::navigation::detail
{
using mrpt::poses::CPose2D;
using Ending = std::optional<std::pair<DriveOutcome, std::string>>;

inline double seconds(const RobotInterface& robot)
{
  return mrpt::Clock::toDouble(robot.now());
}

inline std::size_t collisionsOf(const RobotInterface& robot)
{
  return robot.collisionCount().value_or(0);
}

inline double distanceTo(const CPose2D& p, const Eigen::Vector2d& goal)
{
  return std::hypot(goal.x() - p.x(), goal.y() - p.y());
}

/// The sensed points in the height band [z_min_m, z_max_m] (the navigator's), as XY.
inline void bandPoints(const mrpt::maps::CSimplePointsMap& pts, double z_min_m, double z_max_m,
                       std::vector<Eigen::Vector2d>& out)
{
  out.clear();
  const auto& xs = pts.getPointsBufferRef_x();
  const auto& ys = pts.getPointsBufferRef_y();
  const auto& zs = pts.getPointsBufferRef_z();
  for (std::size_t k = 0; k < xs.size(); k++)
    if (zs[k] >= z_min_m && zs[k] <= z_max_m) out.emplace_back(xs[k], ys[k]);
}

// Bookkeeping of one drive: path length, progress, collisions.
struct DriveLog
{
  double t0_s = 0, best_dist_m = 0, t_best_s = 0, path_m = 0;
  std::size_t steps = 0, collisions0 = 0;
  int target_blocked_steps = 0;  ///< consecutive steps with an obstacle at the target
  CPose2D last;

  DriveLog(const RobotInterface& robot, double dist_m)
      : t0_s(seconds(robot)),
        best_dist_m(dist_m),
        t_best_s(t0_s),
        collisions0(collisionsOf(robot)),
        last(robot.pose())
  {
  }

  void afterStep(const RobotInterface& robot)
  {
    steps++;
    const CPose2D p = robot.pose();
    path_m += std::hypot(p.x() - last.x(), p.y() - last.y());
    last = p;
  }

  void fill(DriveResult& r, const RobotInterface& robot) const
  {
    r.final_pose = robot.pose();
    r.distance_m += path_m;
    r.sim_time_s += seconds(robot) - t0_s;
    r.steps += steps;
    r.collisions += collisionsOf(robot) - collisions0;
  }
};

/// Stops the robot and returns the drive's result: `end` and the log's figures.
inline DriveResult endDrive(RobotInterface& robot, const DriveLog& log,
                            const std::pair<DriveOutcome, std::string>& end)
{
  robot.stop();
  DriveResult r;
  r.outcome = end.first;
  r.message = end.second;
  log.fill(r, robot);
  return r;
}

/// The result of a pass (StopAndScanDriver::passBy): like endDrive(), but
/// the robot keeps moving.
inline DriveResult passDrive(const RobotInterface& robot, const DriveLog& log,
                             const std::pair<DriveOutcome, std::string>& end)
{
  DriveResult r;
  r.outcome = end.first;
  r.message = end.second;
  log.fill(r, robot);
  return r;
}

/// Appends a follow-up drive (`label`: its message prefix) to `r`: its
/// figures add up, its final pose is the result's; the outcome stays r's.
inline void appendDrive(DriveResult& r, const DriveResult& next, const std::string& label)
{
  r.message += "; " + label + next.message;
  r.final_pose = next.final_pose;
  r.sim_time_s += next.sim_time_s;
  r.steps += next.steps;
  r.collisions += next.collisions;
  r.distance_m += next.distance_m;
}

/// `next` driven after `r` (appendDrive), its outcome and guard hold the
/// whole's.
inline void continueDrive(DriveResult& r, const DriveResult& next)
{
  appendDrive(r, next, "");
  r.outcome = next.outcome;
  r.guard_held = next.guard_held;
}

/// `pre` (a back-off before the drive) followed by `r`: r's outcome and
/// goal distance, both drives' time, steps and path. Nothing when pre did
/// not step.
inline void prependDrive(const DriveResult& pre, DriveResult& r)
{
  if (pre.steps == 0) return;
  DriveResult out = pre;
  out.message = "back-off: " + pre.message;
  continueDrive(out, r);
  out.goal_distance_m = r.goal_distance_m;
  out.blocking_points = std::move(r.blocking_points);
  r = out;
}

/// Collisions, progress, time and step limits after one RobotInterface::step().
Ending checkAfterStep(const RobotInterface& robot, const DriverParams& params, DriveLog& log,
                      const Eigen::Vector2d& waypoint);

}  // namespace voxplore::navigation::detail
