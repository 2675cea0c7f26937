/* voxplore — MRPT's robot interface (CRobot2NavInterface) over our RobotInterface. */
#pragma once

#include <mrpt/nav/reactive/CRobot2NavInterface.h>
#include <voxplore/navigation/RobotInterface.h>
#include <voxplore/navigation/holo_ramp.h>

#include <optional>
#include <string>

namespace voxplore::navigation
{
/// @brief What the navigator reported through its event callbacks during one navigation.
struct NavEvents
{
  bool ended = false;                   ///< sendNavigationEndEvent: target reached
  bool ended_by_error = false;          ///< sendNavigationEndDueToErrorEvent
  bool way_blocked = false;             ///< sendWaySeemsBlockedEvent
  bool target_blocked = false;          ///< sendCannotGetCloserToBlockedTargetEvent
  std::size_t apparent_collisions = 0;  ///< sendApparentCollisionEvent (points inside the shape)
  std::size_t sensor_failures = 0;      ///< RobotInterface::obstacles() returned false
};

/// @brief Answers MRPT's reactive navigator from a RobotInterface. Velocity
///        commands are CVehicleVelCmd_Holo (CPTG_Holo_Blend); the adapter
///        keeps the command being executed and turns it into a robot-frame
///        twist each step (applyCommand()).
class RobotNavAdapter : public mrpt::nav::CRobot2NavInterface
{
 public:
  explicit RobotNavAdapter(RobotInterface& robot) : robot_(robot) {}

  /// @brief How senseObstacles() thins the robot's points before MRPT sees
  ///        them (MRPT's CPTG_Holo_Blend costs a few polynomial solves per
  ///        point and path): keep points with z in [z_min_m, z_max_m] and
  ///        within max_range_m of the robot, one per cell_m x cell_m XY cell.
  void setObstacleFilter(double max_range_m, double cell_m, double z_min_m, double z_max_m);

  /// @brief Sends the twist of the command being executed over the next
  ///        dt_s to the robot (call right before RobotInterface::step()).
  void applyCommand(double dt_s);

  /// @brief Forgets the command being executed (the robot stands still).
  void clearCommand();

  /// @brief While set, the heading turns to `yaw_rad` (map frame) at up to
  ///        `rot_speed_radps` instead of to the command's direction of
  ///        travel; the translation (map frame) is the command's. For a
  ///        robot MRPT plans as a circle, any heading is the same to it.
  ///        Only while every sensed obstacle point (senseObstacles()) is
  ///        farther than `clear_m` from the robot's centre; nearer, MRPT's
  ///        heading (a rectangle turned across a corridor brings its corners
  ///        near the walls, and the footprint guard would slow the whole
  ///        command down).
  void setHeading(std::optional<double> yaw_rad, double rot_speed_radps = 0, double clear_m = 0);

  /// @brief The obstacle points MRPT got in the last senseObstacles() (after
  ///        thinning), in the robot frame at lastObstaclesPose().
  const mrpt::maps::CSimplePointsMap& lastObstacles() const { return last_obstacles_; }
  const mrpt::poses::CPose2D& lastObstaclesPose() const { return last_obstacles_pose_; }

  const NavEvents& events() const { return events_; }
  void resetEvents() { events_ = {}; }

  // --- mrpt::nav::CRobot2NavInterface ---
  bool getCurrentPoseAndSpeeds(mrpt::math::TPose2D& pose, mrpt::math::TTwist2D& vel_global,
                               mrpt::system::TTimeStamp& timestamp, mrpt::math::TPose2D& odometry,
                               std::string& frame_id) override;
  bool changeSpeeds(const mrpt::kinematics::CVehicleVelCmd& cmd) override;
  bool changeSpeedsNOP() override { return true; }  // keep executing the last command
  bool stop(bool is_emergency_stop) override;
  mrpt::kinematics::CVehicleVelCmd::Ptr getEmergencyStopCmd() override;
  mrpt::kinematics::CVehicleVelCmd::Ptr getStopCmd() override;
  bool senseObstacles(mrpt::maps::CSimplePointsMap& obstacles,
                      mrpt::system::TTimeStamp& timestamp) override;
  double getNavigationTime() override;
  void resetNavigationTimer() override;

  void sendNavigationEndEvent() override { events_.ended = true; }
  void sendNavigationEndDueToErrorEvent() override { events_.ended_by_error = true; }
  void sendWaySeemsBlockedEvent() override { events_.way_blocked = true; }
  void sendApparentCollisionEvent() override { events_.apparent_collisions++; }
  void sendCannotGetCloserToBlockedTargetEvent() override { events_.target_blocked = true; }

 private:
  double nowSeconds() const;

  RobotInterface& robot_;
  /// Distance from the robot's centre to the nearest point of the last
  /// senseObstacles() [m]; +infinity without any.
  double nearestObstacleM() const;
  HoloRamp ramp_;
  bool moving_ = false;
  std::optional<double> heading_;  ///< setHeading()
  double heading_radps_ = 0, heading_clear_m_ = 0;
  double nav_timer_start_s_ = 0;
  NavEvents events_;
  double max_range_m_ = 1e9, cell_m_ = 0, z_min_m_ = -1e9, z_max_m_ = 1e9;
  mrpt::maps::CSimplePointsMap raw_, last_obstacles_;
  mrpt::poses::CPose2D last_obstacles_pose_;
};

}  // namespace voxplore::navigation
