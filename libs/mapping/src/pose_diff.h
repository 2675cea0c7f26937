/* voxplore — differences of planar poses (private header): the loop
 * closer's and relocalisation's distances and yaw differences. */
#pragma once

#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>

namespace voxplore::mapping::detail
{
/// a's yaw minus b's, wrapped to (-pi, pi] [rad]
inline double yawDiff(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b)
{
  return mrpt::math::wrapToPi(a.phi() - b.phi());
}
/// distance between the positions of a and b [m]
inline double xyDist(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b)
{
  return std::hypot(a.x() - b.x(), a.y() - b.y());
}
/// how far b is from a, a yaw difference counted as the shift it gives 3 m
/// away (graph shifts, rebuild_min_shift_m, implicit_min_m) [m]
inline double shiftDist(const mrpt::poses::CPose2D& a, const mrpt::poses::CPose2D& b)
{
  return xyDist(a, b) + 3.0 * std::abs(yawDiff(a, b));
}
}  // namespace voxplore::mapping::detail
