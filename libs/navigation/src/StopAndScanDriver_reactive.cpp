/* voxplore — StopAndScanDriver's drives with MRPT's reactive navigator
 * (CReactiveNavigationSystem + CPTG_Holo_Blend + CHolonomicND): driveTo,
 * passBy and the drive they share. Split from StopAndScanDriver.cpp. */
#include <mrpt/core/format.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "RobotNavAdapter.h"
#include "drive_log.h"
#include "reactive_navigator.h"

namespace voxplore::navigation
{
using mrpt::nav::CAbstractNavigator;
using namespace detail;

namespace
{
// Closes the navigation log of one drive however the drive ends.
class NavlogScope
{
 public:
  NavlogScope(QuietReactiveNavigator& nav, const std::string& dir) : nav_(nav), on_(!dir.empty())
  {
    if (on_ && !nav_.openNavlog(dir))
      throw std::runtime_error("StopAndScanDriver: [navigation] navlog_dir = '" + dir +
                               "': cannot open a new log_NNN.reactivenavlog file there");
  }
  ~NavlogScope()
  {
    if (on_) nav_.closeNavlog();
  }
  NavlogScope(const NavlogScope&) = delete;
  NavlogScope& operator=(const NavlogScope&) = delete;

 private:
  QuietReactiveNavigator& nav_;
  bool on_;
};

void checkClocks(const RobotInterface& robot)
{
  const double skew_s = mrpt::Clock::nowDouble() - seconds(robot);
  if (std::abs(skew_s) > 1.0)
    throw std::runtime_error(mrpt::format(
        "StopAndScanDriver: RobotInterface::now() and mrpt::Clock::now() differ by %.3f s; a "
        "simulated robot must call mrpt::Clock::setActiveClock(mrpt::Clock::Simulated) and "
        "advance it in step()",
        skew_s));
}

// What the navigator says after a navigationStep(); empty while it navigates.
Ending navigatorEnding(const mrpt::nav::CReactiveNavigationSystem& nav, const NavEvents& ev,
                       double dist_m, double tolerance_m)
{
  // MRPT only logs "Error while loading and sorting the obstacles. Robot will
  // be stopped." and stays NAVIGATING when senseObstacles() fails.
  if (ev.sensor_failures > 0) return {{DriveOutcome::Error, "the robot's obstacle sensors failed"}};
  switch (nav.getCurrentState())
  {
    case CAbstractNavigator::IDLE:
      if (ev.ended || dist_m <= tolerance_m)
        return {{DriveOutcome::Reached, mrpt::format("reached within %.3f m", dist_m)}};
      return {{DriveOutcome::Error, "the navigator went idle without reaching the target"}};
    case CAbstractNavigator::NAV_ERROR:
    {
      const auto& why = nav.getErrorReason();
      const bool blocked =
          why.error_code == CAbstractNavigator::ERR_CANNOT_REACH_TARGET || ev.way_blocked;
      return {{blocked ? DriveOutcome::Blocked : DriveOutcome::Error,
               "navigator error: " + why.error_msg}};
    }
    default:
      return std::nullopt;
  }
}

// The waypoint is blocked when an obstacle point of this step lies within the
// footprint's circumradius of it, kHysteresis steps in a row, while the robot is
// close enough to see round it. (Replaces MRPT's dist_check_target_is_blocked,
// see DriverParams::writeMrptConfig.)
Ending targetBlockedEnding(const RobotNavAdapter& adapter, const DriverParams& params,
                           DriveLog& log, const Eigen::Vector2d& waypoint, double dist_m)
{
  constexpr double kCheckWithin_m = 1.0;  // beyond robotRadius()
  constexpr int kHysteresis = 3;
  const double r_m = params.robotRadius() - params.shape_margin_m;
  bool hit = false;
  if (dist_m < params.robotRadius() + kCheckWithin_m)
  {
    double lx, ly;  // the waypoint in the robot frame the points were sensed in
    adapter.lastObstaclesPose().inverseComposePoint(waypoint.x(), waypoint.y(), lx, ly);
    const auto& xs = adapter.lastObstacles().getPointsBufferRef_x();
    const auto& ys = adapter.lastObstacles().getPointsBufferRef_y();
    for (std::size_t i = 0; i < xs.size() && !hit; i++)
      hit = std::hypot(xs[i] - lx, ys[i] - ly) < r_m;
  }
  log.target_blocked_steps = hit ? log.target_blocked_steps + 1 : 0;
  if (log.target_blocked_steps < kHysteresis) return std::nullopt;
  return {
      {DriveOutcome::Blocked,
       mrpt::format("the waypoint lies within %.3f m (the footprint's circumradius) of a sensed "
                    "obstacle",
                    r_m)}};
}

/// Readies the navigator and the adapter for a new drive.
void startNavigation(mrpt::nav::CReactiveNavigationSystem& nav, RobotNavAdapter& adapter,
                     const DriverParams& params, std::optional<double> face_yaw_rad)
{
  if (nav.getCurrentState() == CAbstractNavigator::NAV_ERROR) nav.resetNavError();
  adapter.resetEvents();
  adapter.clearCommand();  // the navigator's first command ramps from the robot's velocity
  // Turned to face_yaw_rad where any yaw keeps the guard's margin over its
  // horizon from every sensed point.
  adapter.setHeading(face_yaw_rad, params.max_w,
                     params.robotRadius() + params.guard_margin_m +
                         params.max_v_mps * params.guard_horizon_s);
}

/// MRPT's target for one drive to `waypoint`.
CAbstractNavigator::TNavigationParams navigationTarget(const Eigen::Vector2d& waypoint,
                                                       double goal_tolerance_m, bool pass)
{
  CAbstractNavigator::TNavigationParams np;
  np.target.target_coords = mrpt::math::TPose2D(waypoint.x(), waypoint.y(), 0.0);
  np.target.targetAllowedDistance = static_cast<float>(goal_tolerance_m);
  // Stop-and-scan: slow down and stop at the target. A pass: no slowing
  // down (the holonomic method slows down only for 0), and the drive ends
  // here within tolerance_m, before MRPT would stop the robot at
  // goal_tolerance_m. (MRPT's own pass, targetIsIntermediaryWaypoint, is
  // for its waypoint lists: CWaypointsNavigator::checkHasReachedTarget()
  // never reaches such a target given alone.)
  np.target.targetDesiredRelSpeed = pass ? 1.0 : 0.0;
  return np;
}

/// One navigator step (it reads pose, speeds and obstacles and sends a
/// command) and what ends the drive after it: the navigator's state, the
/// waypoint passed within pass_tolerance_m (> 0: a pass), or blocked.
Ending navigatorStep(mrpt::nav::CReactiveNavigationSystem& nav, const RobotNavAdapter& adapter,
                     const RobotInterface& robot, const DriverParams& params, DriveLog& log,
                     const Eigen::Vector2d& waypoint, double pass_tolerance_m)
{
  try
  {
    nav.navigationStep();
    const double dist_m = distanceTo(robot.pose(), waypoint);
    Ending end = navigatorEnding(nav, adapter.events(), dist_m, params.goal_tolerance_m);
    if (!end && pass_tolerance_m > 0 && dist_m <= pass_tolerance_m)
      end = {{DriveOutcome::Reached, mrpt::format("passed within %.3f m", dist_m)}};
    if (!end) end = targetBlockedEnding(adapter, params, log, waypoint, dist_m);
    return end;
  }
  catch (const std::exception& e)
  {
    return {{DriveOutcome::Error, std::string("navigator exception: ") + e.what()}};
  }
}

/// Stops a drive however it ended: the navigation cancelled, zero velocity.
void stopNavigation(mrpt::nav::CReactiveNavigationSystem& nav, RobotNavAdapter& adapter)
{
  if (nav.getCurrentState() == CAbstractNavigator::NAVIGATING) nav.cancel();
  if (nav.getCurrentState() == CAbstractNavigator::NAV_ERROR) nav.resetNavError();
  adapter.clearCommand();
  adapter.setHeading(std::nullopt);
}
}  // namespace

DriveResult StopAndScanDriver::driveTo(const Eigen::Vector2d& waypoint,
                                       std::optional<double> final_yaw_rad,
                                       double final_yaw_period_rad,
                                       std::optional<double> face_yaw_rad)
{
  return reactiveDrive(waypoint, final_yaw_rad, -1.0, final_yaw_period_rad, face_yaw_rad);
}

DriveResult StopAndScanDriver::passBy(const Eigen::Vector2d& waypoint, double tolerance_m,
                                      std::optional<double> face_yaw_rad)
{
  if (!(tolerance_m > 0))
    throw std::invalid_argument("StopAndScanDriver::passBy: tolerance_m must be > 0");
  return reactiveDrive(waypoint, std::nullopt, tolerance_m, 0, face_yaw_rad);
}

DriveResult StopAndScanDriver::reactiveDrive(const Eigen::Vector2d& waypoint,
                                             std::optional<double> final_yaw_rad,
                                             double pass_tolerance_m, double final_yaw_period_rad,
                                             std::optional<double> face_yaw_rad)
{
  checkClocks(robot_);
  const bool pass = pass_tolerance_m > 0;
  // A robot still moving from a pass goes on; the back-off is for a stop
  // left close to a wall (and would stop it).
  DriveResult pre;  // no steps: prependDrive() leaves the drive as it is
  pre.outcome = DriveOutcome::Reached;
  if (!isMoving(robot_)) pre = backOffFootprint();
  if (pre.outcome == DriveOutcome::Error) return pre;
  auto& nav = impl_->nav;
  auto& adapter = impl_->adapter;
  startNavigation(nav, adapter, params_, face_yaw_rad);
  const auto np = navigationTarget(waypoint, params_.goal_tolerance_m, pass);
  std::optional<NavlogScope> navlog;  // one .reactivenavlog per drive (navlog_dir)
  navlog.emplace(nav, params_.navlog_dir);
  nav.navigate(&np);

  DriveLog log(robot_, distanceTo(robot_.pose(), waypoint));
  Ending end;
  while (!end)
  {
    // 1. one navigator step: reads pose, speeds and obstacles, sends a command
    end = navigatorStep(nav, adapter, robot_, params_, log, waypoint, pass_tolerance_m);
    if (end) break;
    // 2. execute the command for dt, then check collisions, progress, time, steps
    adapter.applyCommand(params_.dt_s);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
    end = checkAfterStep(robot_, params_, log, waypoint);
    if (!end) end = guardEnding();
  }

  if (pass && end->first == DriveOutcome::Reached)
  {
    // Passed: the robot keeps the last command's velocity for the next
    // drive, whose navigate() replaces this target (cancel() would stop it).
    navlog.reset();
    adapter.setHeading(std::nullopt);
    DriveResult res = passDrive(robot_, log, *end);
    res.goal_distance_m = distanceTo(res.final_pose, waypoint);
    prependDrive(pre, res);
    return res;
  }
  stopNavigation(nav, adapter);
  navlog.reset();
  DriveResult res = finishDrive(log, *end);
  recoverBlocked(res, waypoint);
  res.goal_distance_m = distanceTo(res.final_pose, waypoint);
  turnAtWaypoint(res, final_yaw_rad, final_yaw_period_rad);
  prependDrive(pre, res);
  return res;
}

void StopAndScanDriver::recoverBlocked(DriveResult& res, const Eigen::Vector2d& waypoint)
{
  if (res.outcome == DriveOutcome::Blocked && params_.straight_fallback)
  {
    const DriveResult st = driveStraight(waypoint);
    appendDrive(res, st, "straight: ");
    res.outcome = st.outcome;
    res.guard_held = st.guard_held;
  }
  if (res.outcome == DriveOutcome::Blocked && params_.escape_clearance_m > 0)
  {
    // Leave the next attempt (a replan) a robot that can move again.
    const DriveResult esc = escape();
    appendDrive(res, esc, "back-off: ");
    if (esc.outcome == DriveOutcome::Error) res.outcome = DriveOutcome::Error;
  }
}

}  // namespace voxplore::navigation
