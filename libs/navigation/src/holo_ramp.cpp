#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/navigation/holo_ramp.h>

#include <algorithm>
#include <cmath>

namespace voxplore::navigation
{
HoloRamp startHoloRamp(const mrpt::kinematics::CVehicleVelCmd_Holo& cmd, double t_s, double yaw_rad,
                       const mrpt::math::TTwist2D& vel_robot)
{
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  HoloRamp r;
  r.t0_s = t_s;
  r.vx0_mps = c * vel_robot.vx - s * vel_robot.vy;
  r.vy0_mps = s * vel_robot.vx + c * vel_robot.vy;
  r.w0_radps = vel_robot.omega;
  r.dir_rad = mrpt::math::wrapToPi(yaw_rad + cmd.dir_local);
  r.vxf_mps = cmd.vel * std::cos(r.dir_rad);
  r.vyf_mps = cmd.vel * std::sin(r.dir_rad);
  r.ramp_s = std::max(0.0, cmd.ramp_time);
  r.rot_speed_radps = std::abs(cmd.rot_speed);
  return r;
}

HoloRamp stoppedHoloRamp(double t_s)
{
  HoloRamp r;
  r.t0_s = t_s;
  return r;
}

mrpt::math::TTwist2D holoTwistAt(const HoloRamp& ramp, double t_s, double dt_s, double yaw_rad)
{
  // Blend factor at the middle of the interval (CVehicleSimul_Holo: linear in time).
  const double t_mid = (t_s - ramp.t0_s) + 0.5 * dt_s;
  const double f = ramp.ramp_s > 0 ? std::clamp(t_mid / ramp.ramp_s, 0.0, 1.0) : 1.0;
  const double vx_map = ramp.vx0_mps + f * (ramp.vxf_mps - ramp.vx0_mps);
  const double vy_map = ramp.vy0_mps + f * (ramp.vyf_mps - ramp.vy0_mps);

  // Heading: turn towards dir_rad; stop within 1 deg, never overshoot in one step.
  const double err = mrpt::math::wrapToPi(ramp.dir_rad - yaw_rad);
  double w = 0;
  if (std::abs(err) >= mrpt::DEG2RAD(1.0))
  {
    const double wf = (err > 0 ? 1.0 : -1.0) * ramp.rot_speed_radps;
    w = ramp.w0_radps + f * (wf - ramp.w0_radps);
    if (dt_s > 0 && w * err > 0 && std::abs(w) * dt_s > std::abs(err)) w = err / dt_s;
  }

  // Map-frame velocity into the robot frame at the heading of mid-interval.
  const double yaw_mid = yaw_rad + 0.5 * w * dt_s;
  const double c = std::cos(yaw_mid), s = std::sin(yaw_mid);
  return {c * vx_map + s * vy_map, -s * vx_map + c * vy_map, w};
}

}  // namespace voxplore::navigation
