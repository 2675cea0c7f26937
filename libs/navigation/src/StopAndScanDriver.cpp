#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/nav/reactive/CReactiveNavigationSystem.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "FootprintGuard.h"
#include "RobotNavAdapter.h"
#include "drive_log.h"

namespace voxplore::navigation
{
using mrpt::nav::CAbstractNavigator;
using mrpt::poses::CPose2D;
using namespace detail;

const char* toString(DriveOutcome o)
{
  switch (o)
  {
    case DriveOutcome::Reached:
      return "reached";
    case DriveOutcome::Blocked:
      return "blocked";
    case DriveOutcome::Timeout:
      return "timeout";
    case DriveOutcome::Error:
      return "error";
  }
  return "?";
}

namespace
{
// CReactiveNavigationSystem whose delay statistics (CAbstractNavigator's
// always-enabled m_timlog_delays) are not dumped to the console on destruction.
class QuietReactiveNavigator : public mrpt::nav::CReactiveNavigationSystem
{
 public:
  QuietReactiveNavigator(mrpt::nav::CRobot2NavInterface& robot, bool verbose)
      : CReactiveNavigationSystem(robot, verbose /*console output*/, false /*no log files*/)
  {
    m_timlog_delays.enable(verbose);
  }

  /// Opens the next free DIR/log_NNN.reactivenavlog (MRPT's naming).
  /// @return false when MRPT could not open it (it only logs the error).
  bool openNavlog(const std::string& dir)
  {
    setLogFileDirectory(dir);
    // MRPT writes the PTG descriptions (what navlog-viewer needs to draw the
    // paths) at the start of a file only when the stream pointer differs
    // from the previous file's: a new file may reuse the freed address.
    m_prev_logfile = nullptr;
    enableLogFile(true);
    return m_logFile != nullptr;
  }
  /// Closes (and so finishes the gzip stream of) the current log file.
  void closeNavlog() { enableLogFile(false); }
};

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

// Creates [navigation] navlog_dir and checks a file can be made there.
void prepareNavlogDir(const std::string& dir)
{
  if (dir.empty()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path probe = fs::path(dir) / ".voxplore_navlog_probe";
  bool writable = !ec && fs::is_directory(dir);
  if (writable)
  {
    std::ofstream f(probe);
    writable = static_cast<bool>(f << "x");
  }
  fs::remove(probe, ec);
  if (!writable)
    throw std::runtime_error("StopAndScanDriver: [navigation] navlog_dir = '" + dir +
                             "': cannot create a writable directory there");
}
}  // namespace

struct StopAndScanDriver::Impl
{
  RobotNavAdapter adapter;
  QuietReactiveNavigator nav;

  Impl(RobotInterface& robot, bool verbose) : adapter(robot), nav(adapter, verbose) {}
};

namespace
{
std::unique_ptr<FootprintGuard> makeGuard(RobotInterface& robot, const DriverParams& p)
{
  if (!p.footprint_guard) return nullptr;
  GuardParams g;
  g.length_m = p.footprint_length_m;
  g.width_m = p.footprint_width_m;
  g.margin_m = p.guard_margin_m;
  g.horizon_s = p.guard_horizon_s;
  g.z_min_m = p.min_obstacle_height_m;
  g.z_max_m = p.max_obstacle_height_m;
  return std::make_unique<FootprintGuard>(robot, g);
}
}  // namespace

StopAndScanDriver::StopAndScanDriver(RobotInterface& robot, const DriverParams& params)
    : params_(params),
      guard_(makeGuard(robot, params)),
      robot_(guard_ ? static_cast<RobotInterface&>(*guard_) : robot),
      impl_(std::make_unique<Impl>(robot_, params.verbose))
{
  prepareNavlogDir(params.navlog_dir);
  const auto level = params.verbose ? mrpt::system::LVL_INFO : mrpt::system::LVL_ERROR;
  impl_->nav.setMinLoggingLevel(level);
  impl_->adapter.setMinLoggingLevel(level);
  impl_->nav.enableRethrowNavExceptions(true);
  impl_->adapter.setObstacleFilter(params.ref_distance_m + params.robotRadius(),
                                   params.obstacle_cell_m, params.min_obstacle_height_m,
                                   params.max_obstacle_height_m);
  mrpt::config::CConfigFileMemory cfg;
  params.writeMrptConfig(cfg);
  try
  {
    impl_->nav.loadConfigFile(cfg);
    impl_->nav.initialize();
  }
  catch (const std::exception& e)
  {
    throw std::runtime_error(
        std::string("StopAndScanDriver: MRPT's reactive navigator rejected the [navigation] "
                    "settings: ") +
        e.what());
  }
}

StopAndScanDriver::~StopAndScanDriver() = default;

std::size_t StopAndScanDriver::guardScaledCommands() const
{
  return guard_ ? guard_->scaledCommands() : 0;
}

std::size_t StopAndScanDriver::guardHeldCommands() const
{
  return guard_ ? guard_->heldCommands() : 0;
}

bool StopAndScanDriver::guardHolding() const
{
  return guard_ && guard_->heldFor_s() >= params_.guard_hold_s - 1e-9;
}

DriveResult StopAndScanDriver::finishDrive(const DriveLog& log,
                                           const std::pair<DriveOutcome, std::string>& end)
{
  const bool held = guardHolding();
  DriveResult r = endDrive(robot_, log, end);  // stops the robot (and resets the guard's hold)
  r.guard_held = held && end.first == DriveOutcome::Blocked;
  return r;
}

Ending StopAndScanDriver::guardEnding() const
{
  if (!guardHolding()) return std::nullopt;
  return {{DriveOutcome::Blocked,
           mrpt::format("the footprint guard held the robot for %.1f s: going on would bring the "
                        "footprint within guard_margin_m = %.3f m of a sensed obstacle "
                        "(clearance now %.3f m)",
                        guard_->heldFor_s(), params_.guard_margin_m, guard_->lastClearance_m())}};
}

namespace
{
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

}  // namespace

namespace detail
{
Ending checkAfterStep(const RobotInterface& robot, const DriverParams& params, DriveLog& log,
                      const Eigen::Vector2d& waypoint)
{
  const CPose2D p = robot.pose();
  const double d = distanceTo(p, waypoint);
  const double t = seconds(robot);
  if (collisionsOf(robot) > log.collisions0)
    return {{DriveOutcome::Error,
             mrpt::format("the robot reported a collision at (%.3f, %.3f)", p.x(), p.y())}};
  if (d < log.best_dist_m - params.progress_min_m)
  {
    log.best_dist_m = d;
    log.t_best_s = t;
  }
  else if (t - log.t_best_s > params.blocked_timeout_s)
    return {{DriveOutcome::Blocked, mrpt::format("no progress for %.1f s; closest approach %.3f m",
                                                 params.blocked_timeout_s, log.best_dist_m)}};
  if (t - log.t0_s > params.timeout_s)
    return {{DriveOutcome::Timeout, mrpt::format("timeout_s = %.1f s elapsed", params.timeout_s)}};
  if (log.steps >= static_cast<std::size_t>(params.max_steps))
    return {{DriveOutcome::Timeout, mrpt::format("hit max_steps = %d", params.max_steps)}};
  return std::nullopt;
}
}  // namespace detail

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
  const double tolerance_m = pass ? pass_tolerance_m : params_.goal_tolerance_m;
  // A robot still moving from a pass goes on; the back-off is for a stop
  // left close to a wall (and would stop it).
  DriveResult pre;  // no steps: prependDrive() leaves the drive as it is
  pre.outcome = DriveOutcome::Reached;
  if (!isMoving(robot_)) pre = backOffFootprint();
  if (pre.outcome == DriveOutcome::Error) return pre;
  auto& nav = impl_->nav;
  auto& adapter = impl_->adapter;
  if (nav.getCurrentState() == CAbstractNavigator::NAV_ERROR) nav.resetNavError();
  adapter.resetEvents();
  adapter.clearCommand();  // the navigator's first command ramps from the robot's velocity
  // Turned to face_yaw_rad where any yaw keeps the guard's margin over its
  // horizon from every sensed point.
  adapter.setHeading(face_yaw_rad, params_.max_w,
                     params_.robotRadius() + params_.guard_margin_m +
                         params_.max_v_mps * params_.guard_horizon_s);

  CAbstractNavigator::TNavigationParams np;
  np.target.target_coords = mrpt::math::TPose2D(waypoint.x(), waypoint.y(), 0.0);
  np.target.targetAllowedDistance = static_cast<float>(params_.goal_tolerance_m);
  // Stop-and-scan: slow down and stop at the target. A pass: no slowing
  // down (the holonomic method slows down only for 0), and the drive ends
  // here within tolerance_m, before MRPT would stop the robot at
  // goal_tolerance_m. (MRPT's own pass, targetIsIntermediaryWaypoint, is
  // for its waypoint lists: CWaypointsNavigator::checkHasReachedTarget()
  // never reaches such a target given alone.)
  np.target.targetDesiredRelSpeed = pass ? 1.0 : 0.0;
  std::optional<NavlogScope> navlog;  // one .reactivenavlog per drive (navlog_dir)
  navlog.emplace(nav, params_.navlog_dir);
  nav.navigate(&np);

  DriveLog log(robot_, distanceTo(robot_.pose(), waypoint));
  Ending end;
  while (!end)
  {
    try  // 1. one navigator step: reads pose, speeds and obstacles, sends a command
    {
      nav.navigationStep();
      const double dist_m = distanceTo(robot_.pose(), waypoint);
      end = navigatorEnding(nav, adapter.events(), dist_m, params_.goal_tolerance_m);
      if (!end && pass && dist_m <= tolerance_m)
        end = {{DriveOutcome::Reached, mrpt::format("passed within %.3f m", dist_m)}};
      if (!end) end = targetBlockedEnding(adapter, params_, log, waypoint, dist_m);
    }
    catch (const std::exception& e)
    {
      end = {{DriveOutcome::Error, std::string("navigator exception: ") + e.what()}};
    }
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
  // Stop in every case: cancel the navigation, zero velocity.
  if (nav.getCurrentState() == CAbstractNavigator::NAVIGATING) nav.cancel();
  if (nav.getCurrentState() == CAbstractNavigator::NAV_ERROR) nav.resetNavError();
  adapter.clearCommand();
  adapter.setHeading(std::nullopt);
  navlog.reset();
  DriveResult res = finishDrive(log, *end);
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
  res.goal_distance_m = distanceTo(res.final_pose, waypoint);
  turnAtWaypoint(res, final_yaw_rad, final_yaw_period_rad);
  prependDrive(pre, res);
  return res;
}

DriveResult StopAndScanDriver::rotateTo(double yaw_rad)
{
  DriveLog log(robot_, 0.0);
  const int max_rot_steps = static_cast<int>(std::ceil(params_.rotate_timeout_s / params_.dt_s));
  Ending end;
  for (int i = 0; !end; i++)
  {
    const double err = mrpt::math::wrapToPi(yaw_rad - robot_.pose().phi());
    if (collisionsOf(robot_) > log.collisions0)
      end = {DriveOutcome::Error, "the robot reported a collision while turning"};
    else if (const auto held = guardEnding())
      end = *held;
    else if (std::abs(err) <= params_.yaw_tolerance)
      end = {DriveOutcome::Reached, mrpt::format("yaw error %.2f deg", mrpt::RAD2DEG(err))};
    else if (i >= max_rot_steps)
      end = {DriveOutcome::Timeout,
             mrpt::format("rotation: yaw error %.2f deg after rotate_timeout_s = %.1f s",
                          mrpt::RAD2DEG(err), params_.rotate_timeout_s)};
    if (end) break;
    const double w = std::clamp(params_.yaw_gain * err, -params_.max_w, params_.max_w);
    robot_.setVelocity(0.0, 0.0, w);
    robot_.step(params_.dt_s);
    log.afterStep(robot_);
  }
  return finishDrive(log, *end);
}

}  // namespace voxplore::navigation
