/* voxplore — executing MRPT's holonomic velocity command (CVehicleVelCmd_Holo) on a robot
 * that takes plain robot-frame twists.
 *
 * MRPT's model (CPTG_Holo_Blend predicts it, CVehicleSimul_Holo executes it):
 * from the moment the command is issued, the translation velocity blends
 * linearly, in the map frame, from the velocity at issue time to
 * vel * (cos dir, sin dir) over ramp_time, and the heading turns at
 * |rot_speed| (also blended over ramp_time) until it faces dir, where dir is
 * dir_local plus the heading at issue time. */
#pragma once

#include <mrpt/kinematics/CVehicleVelCmd_Holo.h>
#include <mrpt/math/TTwist2D.h>

namespace voxplore::navigation
{
/// @brief A holonomic command being executed, in the map frame.
struct HoloRamp
{
  double t0_s = 0;             ///< issue time [s]
  double vx0_mps = 0;          ///< map-frame velocity at issue time [m/s]
  double vy0_mps = 0;          ///< (y component) [m/s]
  double w0_radps = 0;         ///< turn rate at issue time [rad/s]
  double vxf_mps = 0;          ///< map-frame target velocity [m/s]
  double vyf_mps = 0;          ///< (y component) [m/s]
  double dir_rad = 0;          ///< map-frame travel direction the heading turns to [rad]
  double ramp_s = 0;           ///< blending time (0: jump to the target) [s]
  double rot_speed_radps = 0;  ///< |turn rate| towards dir_rad [rad/s]
};

/// @brief Starts executing `cmd` at time `t_s`.
/// @param yaw_rad robot heading in the map frame at issue time
/// @param vel_robot current velocity in the robot frame (vx, vy, omega)
HoloRamp startHoloRamp(const mrpt::kinematics::CVehicleVelCmd_Holo& cmd, double t_s, double yaw_rad,
                       const mrpt::math::TTwist2D& vel_robot);

/// @brief A ramp that stands still (the stop command).
HoloRamp stoppedHoloRamp(double t_s);

/// @brief The robot-frame twist that executes `ramp` over [t_s, t_s + dt_s].
///        Velocities are evaluated at the middle of the interval; the turn
///        rate is cut so the heading does not overshoot dir_rad within dt_s
///        (MRPT's simulator stops turning within 1 deg of dir_rad).
/// @param yaw_rad current heading in the map frame
mrpt::math::TTwist2D holoTwistAt(const HoloRamp& ramp, double t_s, double dt_s, double yaw_rad);

}  // namespace voxplore::navigation
