/* voxplore — SlamIcp's body check (the robot cannot stand in a mapped wall,
 * [icp] body_*) and the relocalisation after a refused registration. */
#include <mrpt/core/bits_math.h>
#include <octomap/OcTree.h>
#include <voxplore/mapping/SlamIcp.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;

namespace
{
/// The occupied voxels of `V` whose centres lie inside the body rectangle
/// at `pose` (body_length_m x body_width_m shrunk by body_margin_m on each
/// side) between body_z_min_m and body_z_max_m; 0 when the check is off.
std::size_t occupiedInBody(const octomap::OcTree& V, const CPose2D& pose, const IcpParams& p)
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
}  // namespace

std::size_t SlamIcp::occupiedUnderBody(const CPose2D& pose) const
{
  return occupiedInBody(octomap_.tree(), pose, params_.icp);
}

bool SlamIcp::bodyBlocked(const CPose2D& pose) const
{
  return occupiedUnderBody(pose) > static_cast<std::size_t>(params_.icp.body_max_voxels);
}

bool SlamIcp::refuseIfBodyBlocked(IcpResult& r, const CPose2D& predicted) const
{
  if (!r.accepted) return false;
  const std::size_t n = occupiedUnderBody(r.pose);
  if (n <= static_cast<std::size_t>(params_.icp.body_max_voxels)) return false;  // bodyBlocked()
  std::ostringstream why;
  why << "refused: the body at " << r.pose.x() << " " << r.pose.y() << " "
      << mrpt::RAD2DEG(r.pose.phi()) << " deg holds " << n
      << " occupied voxels > body_max_voxels = " << params_.icp.body_max_voxels;
  if (!r.reason.empty()) why << "; " << r.reason;
  r.reason = why.str();
  r.accepted = false;
  r.icp_pose = r.pose;
  r.pose = predicted;
  return true;
}

void SlamIcp::relocalize(StopReport& rep, const RobotCloud& cloud, bool body_refused)
{
  const std::string first_reason = rep.icp.reason;
  // Refused for the body, the scene offered a wrong minimum near the
  // prediction: the relocalisation's bar is lower, among poses whose body
  // is clear (b1 compact nbv: a 133 deg turn with odometry 0.5 m off
  // registered through a wall; the true pose paired 0.83).
  IcpParams reloc = params_.icp;
  if (body_refused)
    reloc.relocalize_min_goodness = std::min(reloc.relocalize_min_goodness, reloc.body_relocalize_min_goodness);
  rep.icp = relocalizePlanar(metaview_.footprint(), cloud.points, rep.predicted, reloc,
                             &metaview_.footprintViewpoints(),
                             [this](const CPose2D& q) { return !bodyBlocked(q); });
  rep.icp.reason = first_reason + "; " + rep.icp.reason;
  rep.relocalized = rep.icp.accepted;
}

}  // namespace voxplore::mapping
