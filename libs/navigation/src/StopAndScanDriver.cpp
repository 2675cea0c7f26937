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
#include "reactive_navigator.h"

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

std::unique_ptr<FootprintGuard> makeGuard(RobotInterface& robot, const DriverParams& p)
{
  if (!p.footprint_guard) return nullptr;
  GuardParams g;
  g.length_m = p.footprint_length_m;
  g.width_m = p.footprint_width_m;
  g.margin_m = p.guard_margin_m;
  g.horizon_s = p.guard_horizon_s;
  g.max_accel_mps2 = p.max_accel_mps2;
  g.max_angular_accel = p.max_angular_accel;
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
