/* voxplore — a base's velocity under acceleration limits: the simulator
 * executes commands this way and the footprint guard predicts them with it. */
#pragma once
#include <mrpt/math/TTwist2D.h>

#include <algorithm>
#include <cmath>

namespace voxplore::common
{
/// @brief The velocity one step of dt_s brings `from` to on the way to `to`
///        (robot frame): the translation vector moves by at most
///        max_accel_mps2 * dt_s, the rotation rate by at most
///        max_angular_accel * dt_s [rad/s^2]; a limit of 0 reaches `to` at once.
inline mrpt::math::TTwist2D rampedVelocity(const mrpt::math::TTwist2D& from,
                                           const mrpt::math::TTwist2D& to, double max_accel_mps2,
                                           double max_angular_accel, double dt_s)
{
  mrpt::math::TTwist2D v = to;
  if (max_accel_mps2 > 0)
  {
    const double dx = to.vx - from.vx, dy = to.vy - from.vy, dv = std::hypot(dx, dy);
    const double most = max_accel_mps2 * dt_s;
    if (dv > most)
    {
      v.vx = from.vx + dx * most / dv;
      v.vy = from.vy + dy * most / dv;
    }
  }
  if (max_angular_accel > 0)
  {
    const double most = max_angular_accel * dt_s;
    v.omega = from.omega + std::clamp(to.omega - from.omega, -most, most);
  }
  return v;
}
}  // namespace voxplore::common
