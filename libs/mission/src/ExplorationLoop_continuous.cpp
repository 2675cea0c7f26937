// The exploration loop's scanning while driving ([explore] scan_mode =
// continuous, issue 15): which waypoints are passed without stopping, when
// a scan is due on the way, and whether the scans on the way have seen the
// plan's frontier (replan_on_the_way). Split from ExplorationLoop.cpp. Our
// own code: the thesis stops at every waypoint.
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace voxplore::mission
{
mrpt::poses::CPose2D ExplorationLoop::planPose() const
{
  // A robot still moving (a drive ended on the way, replan_on_the_way) is
  // where odometry took it since the last scan; a standing one at that scan.
  return navigation::isMoving(robot_) ? poseEstimate() : slam_.currentPose();
}

bool ExplorationLoop::targetSeen(const exploration::PlanResult& plan)
{
  const auto rev = slam_.octomap().revision();
  if (!plan.frontier || (rev.map == checked_at_.map && rev.rev == checked_at_.rev)) return false;
  checked_at_ = rev;
  // The frontiers only (a plan's views are rated only when it is taken).
  const auto now = exploration::planLayers(slam_.octomap().tree(), planPose(), planner_, swept_,
                                           sensed_obstacles_, slam_.octomap().lowObstacles(),
                                           projectionCache(), nullptr);
  if (!now.frontiers) return false;
  const double r = planner_.sampling.blacklist_radius_m;
  return std::none_of(now.frontiers->frontiers.begin(), now.frontiers->frontiers.end(),
                      [&](const exploration::Frontier& f)
                      { return (f.center - plan.frontier->center).norm() <= r; });
}

std::optional<double> ExplorationLoop::passTolerance(const exploration::PlanResult& plan,
                                                     std::size_t i) const
{
  const auto& wps = plan.waypoints;
  if (i + 1 >= wps.size()) return std::nullopt;
  auto narrowAt = [&](std::size_t k)
  { return k < plan.waypoint_narrow.size() && plan.waypoint_narrow[k]; };
  // Circle to circle: MRPT's reactive drive goes on from anywhere near.
  if (!narrowAt(i)) return narrowAt(i + 1) ? std::nullopt : std::optional(params_.pass_tolerance_m);
  // From a footprint waypoint (in or at a passage the circle does not fit):
  // to another, the same yaw or a turn on the way there (no turn in place);
  // and a way that bends little, so
  // that the pass cuts the corner by at most tolerance x sin(bend) (a door
  // leaves the body 2-5 cm a side).
  constexpr double kPassBendDeg = 20;
  const auto& p = driver_->params();
  const bool turn_next = i + 1 < plan.waypoint_turn_on_way.size() && plan.waypoint_turn_on_way[i + 1];
  if (narrowAt(i + 1) && !turn_next &&
      (i + 1 >= plan.waypoint_yaws.size() ||
       std::abs(mrpt::math::wrapToPi(plan.waypoint_yaws[i + 1] - plan.waypoint_yaws[i])) >
           p.yaw_tolerance))
    return std::nullopt;
  const Eigen::Vector2d from = i > 0 ? wps[i - 1] : Eigen::Vector2d(pose_at_stop_.x(), pose_at_stop_.y());
  const Eigen::Vector2d a = wps[i] - from, b = wps[i + 1] - wps[i];
  if (a.norm() < 1e-6 || b.norm() < 1e-6) return std::nullopt;
  const double bend = std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0));
  if (bend > mrpt::DEG2RAD(kPassBendDeg)) return std::nullopt;
  // One navigation period's travel at most: the drive checks once a period.
  return std::min(params_.pass_tolerance_m, p.max_v_mps * p.dt_s);
}

bool ExplorationLoop::scanDue() const
{
  if (mrpt::Clock::toDouble(robot_.now()) - t_last_scan_s_ < 1.0 / params_.scan_rate_hz - 1e-9)
    return false;
  const mrpt::poses::CPose2D d = robot_.odometry() - odo_at_stop_;
  return std::hypot(d.x(), d.y()) >= params_.scan_every_m ||
         std::abs(d.phi()) >= mrpt::DEG2RAD(params_.scan_every_deg);
}

}  // namespace voxplore::mission
