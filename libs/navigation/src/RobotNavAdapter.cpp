#include "RobotNavAdapter.h"

#include <mrpt/kinematics/CVehicleVelCmd_Holo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <unordered_set>

namespace voxplore::navigation
{
double RobotNavAdapter::nowSeconds() const
{
  return mrpt::Clock::toDouble(robot_.now());
}

void RobotNavAdapter::applyCommand(double dt_s)
{
  if (!moving_)
  {
    robot_.stop();
    return;
  }
  HoloRamp ramp = ramp_;
  if (heading_ && nearestObstacleM() > heading_clear_m_)
  {
    ramp.dir_rad = *heading_;
    ramp.rot_speed_radps = heading_radps_;
  }
  const auto twist = holoTwistAt(ramp, nowSeconds(), dt_s, robot_.pose().phi());
  robot_.setVelocity(twist.vx, twist.vy, twist.omega);
}

void RobotNavAdapter::clearCommand()
{
  moving_ = false;
  ramp_ = stoppedHoloRamp(nowSeconds());
}

void RobotNavAdapter::setHeading(std::optional<double> yaw_rad, double rot_speed_radps,
                                 double clear_m)
{
  heading_ = yaw_rad;
  heading_radps_ = rot_speed_radps;
  heading_clear_m_ = clear_m;
}

double RobotNavAdapter::nearestObstacleM() const
{
  const auto& xs = last_obstacles_.getPointsBufferRef_x();
  const auto& ys = last_obstacles_.getPointsBufferRef_y();
  double d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < xs.size(); i++)
    d2 = std::min(d2, static_cast<double>(xs[i]) * xs[i] + static_cast<double>(ys[i]) * ys[i]);
  return std::sqrt(d2);
}

bool RobotNavAdapter::getCurrentPoseAndSpeeds(mrpt::math::TPose2D& pose,
                                              mrpt::math::TTwist2D& vel_global,
                                              mrpt::system::TTimeStamp& timestamp,
                                              mrpt::math::TPose2D& odometry, std::string& frame_id)
{
  pose = robot_.pose().asTPose();
  vel_global = robot_.velocity();
  vel_global.rotate(pose.phi);  // robot frame -> map frame
  timestamp = robot_.now();
  odometry = robot_.odometry().asTPose();
  frame_id = "map";
  return true;
}

bool RobotNavAdapter::changeSpeeds(const mrpt::kinematics::CVehicleVelCmd& cmd)
{
  const auto* holo = dynamic_cast<const mrpt::kinematics::CVehicleVelCmd_Holo*>(&cmd);
  if (!holo)
  {
    MRPT_LOG_ERROR_STREAM("changeSpeeds: expected a CVehicleVelCmd_Holo (holonomic PTG), got "
                          << cmd.GetRuntimeClass()->className);
    return false;
  }
  if (holo->isStopCmd())
  {
    clearCommand();
    return true;
  }
  ramp_ = startHoloRamp(*holo, nowSeconds(), robot_.pose().phi(), robot_.velocity());
  moving_ = true;
  return true;
}

bool RobotNavAdapter::stop([[maybe_unused]] bool is_emergency_stop)
{
  // Our platforms stop within one step; a ramped (non-emergency) stop would
  // only delay the scan.
  clearCommand();
  robot_.stop();
  return true;
}

mrpt::kinematics::CVehicleVelCmd::Ptr RobotNavAdapter::getEmergencyStopCmd()
{
  return std::make_shared<mrpt::kinematics::CVehicleVelCmd_Holo>(0.0, 0.0, 0.1, 0.0);
}

mrpt::kinematics::CVehicleVelCmd::Ptr RobotNavAdapter::getStopCmd()
{
  return std::make_shared<mrpt::kinematics::CVehicleVelCmd_Holo>(0.0, 0.0, 1.0, 0.0);
}

void RobotNavAdapter::setObstacleFilter(double max_range_m, double cell_m, double z_min_m,
                                        double z_max_m)
{
  max_range_m_ = max_range_m;
  cell_m_ = cell_m;
  z_min_m_ = z_min_m;
  z_max_m_ = z_max_m;
}

bool RobotNavAdapter::senseObstacles(mrpt::maps::CSimplePointsMap& obstacles,
                                     mrpt::system::TTimeStamp& timestamp)
{
  timestamp = robot_.now();
  obstacles.clear();
  last_obstacles_.clear();
  if (!robot_.obstacles(raw_))
  {
    events_.sensor_failures++;
    return false;
  }
  // Thin out: height band, range, one point per XY cell (first come, first kept).
  std::unordered_set<std::uint64_t> cells;
  const auto& xs = raw_.getPointsBufferRef_x();
  const auto& ys = raw_.getPointsBufferRef_y();
  const auto& zs = raw_.getPointsBufferRef_z();
  const double r2 = max_range_m_ * max_range_m_;
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    const double x = xs[i], y = ys[i], z = zs[i];
    if (z < z_min_m_ || z > z_max_m_ || x * x + y * y > r2) continue;
    if (cell_m_ > 0)
    {
      const auto cx = static_cast<std::int64_t>(std::floor(x / cell_m_));
      const auto cy = static_cast<std::int64_t>(std::floor(y / cell_m_));
      // Unsigned shift: shifting a negative signed value left is UB (UBSan).
      const std::uint64_t key =
          (static_cast<std::uint64_t>(cx) << 32) ^ (static_cast<std::uint64_t>(cy) & 0xffffffffu);
      if (!cells.insert(key).second) continue;
    }
    obstacles.insertPoint(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  }
  last_obstacles_ = obstacles;
  last_obstacles_pose_ = robot_.pose();
  return true;
}

double RobotNavAdapter::getNavigationTime()
{
  return nowSeconds() - nav_timer_start_s_;
}

void RobotNavAdapter::resetNavigationTimer()
{
  nav_timer_start_s_ = nowSeconds();
}

}  // namespace voxplore::navigation
