#include "body_check.h"

#include <octomap/OcTree.h>
#include <voxplore/mapping/PlanarIcp.h>

#include <algorithm>
#include <cmath>

namespace voxplore::mapping::detail
{
std::size_t occupiedUnderBody(const octomap::OcTree& V, const mrpt::poses::CPose2D& pose,
                              const IcpParams& p)
{
  const double hl = 0.5 * p.body_length_m - p.body_margin_m;
  const double hw = 0.5 * p.body_width_m - p.body_margin_m;
  if (p.body_length_m <= 0 || p.body_width_m <= 0 || hl <= 0 || hw <= 0) return 0;
  if (p.body_z_max_m <= p.body_z_min_m) return 0;
  // The rectangle's axis-aligned bounds in the map, then each leaf's centre
  // in the body frame. A pruned leaf larger than a voxel counts when its
  // centre is within its extra half-size of the rectangle.
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  const double ex = std::abs(c) * hl + std::abs(s) * hw;
  const double ey = std::abs(s) * hl + std::abs(c) * hw;
  const double res = V.getResolution();
  const octomap::point3d lo(static_cast<float>(pose.x() - ex - res), static_cast<float>(pose.y() - ey - res),
                            static_cast<float>(p.body_z_min_m));
  const octomap::point3d hi(static_cast<float>(pose.x() + ex + res), static_cast<float>(pose.y() + ey + res),
                            static_cast<float>(p.body_z_max_m));
  std::size_t n = 0;
  for (auto it = V.begin_leafs_bbx(lo, hi), end = V.end_leafs_bbx(); it != end; ++it)
  {
    if (!V.isNodeOccupied(*it)) continue;
    const double grow = 0.5 * (it.getSize() - res);
    const double z = it.getZ();
    if (z + grow < p.body_z_min_m || z - grow > p.body_z_max_m) continue;
    const double dx = it.getX() - pose.x(), dy = it.getY() - pose.y();
    const double along = c * dx + s * dy, across = -s * dx + c * dy;
    if (std::abs(along) <= hl + grow && std::abs(across) <= hw + grow) ++n;
  }
  return n;
}
}  // namespace voxplore::mapping::detail
