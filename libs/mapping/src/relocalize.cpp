/* voxplore — relocalisation: the planar ICP from a grid of seeds round the
 * predicted pose, accepted only when good, unambiguous and not degenerate
 * (PlanarIcp.h). */
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/mapping/PlanarIcp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "pose_diff.h"

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;

namespace
{
struct Seed
{
  CPose2D pose;
  double score = 0;
};

bool distinct(const CPose2D& a, const CPose2D& b)
{
  return detail::xyDist(a, b) > 0.2 || std::abs(detail::yawDiff(a, b)) > mrpt::DEG2RAD(5.0);
}

/// Seeds on the search grid, best first, scored by the share of `pts`
/// (robot frame) within 0.1 m of the reference.
std::vector<Seed> scoreSeeds(const mrpt::maps::CPointsMap& ref,
                             const std::vector<Eigen::Vector2f>& pts, const CPose2D& predicted,
                             const IcpParams& p)
{
  constexpr double kStepXy = 0.25, kNear2 = 0.1 * 0.1;
  const double step_yaw = mrpt::DEG2RAD(5.0);
  const int nxy = static_cast<int>(std::floor(p.relocalize_radius_m / kStepXy));
  const int nyaw = static_cast<int>(std::floor(p.relocalize_yaw / step_yaw));
  std::vector<Seed> seeds;
  for (int k = -nyaw; k <= nyaw; k++)
  {
    const double yaw = predicted.phi() + k * step_yaw;
    const double c = std::cos(yaw), s = std::sin(yaw);
    for (int i = -nxy; i <= nxy; i++)
      for (int j = -nxy; j <= nxy; j++)
      {
        const double dx = i * kStepXy, dy = j * kStepXy;
        if (std::hypot(dx, dy) > p.relocalize_radius_m + 1e-9) continue;
        const double x = predicted.x() + dx, y = predicted.y() + dy;
        std::size_t near = 0;
        for (const auto& q : pts)
          near += ref.kdTreeClosestPoint2DsqrError(static_cast<float>(x + c * q.x() - s * q.y()),
                                                   static_cast<float>(y + s * q.x() + c * q.y())) <
                  kNear2;
        seeds.push_back({CPose2D(x, y, yaw), double(near) / double(pts.size())});
      }
  }
  std::sort(seeds.begin(), seeds.end(), [](const Seed& a, const Seed& b) { return a.score > b.score; });
  return seeds;
}
}  // namespace

IcpResult relocalizePlanar(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const CPose2D& predicted, const IcpParams& p, const Viewpoints* reference_viewpoints,
    const std::function<bool(const CPose2D&)>& admissible)
{
  IcpResult none;
  none.pose = none.icp_pose = predicted;
  if (cloud_robot.size() < static_cast<std::size_t>(p.min_points) ||
      reference_map.size() < static_cast<std::size_t>(p.min_points))
  {
    none.reason = "relocalisation: too few points";
    return none;
  }
  // A subsample of the cloud for scoring (about 300 points).
  std::vector<Eigen::Vector2f> pts;
  const std::size_t stride = std::max<std::size_t>(1, cloud_robot.size() / 300);
  for (std::size_t i = 0; i < cloud_robot.size(); i += stride)
  {
    float x, y, z;
    cloud_robot.getPoint(i, x, y, z);
    pts.emplace_back(x, y);
  }
  const auto seeds = scoreSeeds(reference_map, pts, predicted, p);
  // Refine the best few distinct seeds with the full two-stage ICP.
  IcpParams wide = p;
  wide.max_correction_xy_m = p.relocalize_radius_m + p.d_max_m;
  wide.max_correction_yaw = p.relocalize_yaw + mrpt::DEG2RAD(10.0);
  wide.min_goodness = p.relocalize_min_goodness;
  wide.low_overlap_min_goodness = 0;  // relocalisation by its own goodness only
  std::vector<IcpResult> refined;
  std::vector<CPose2D> tried;
  std::size_t inadmissible = 0;
  for (const auto& seed : seeds)
  {
    if (tried.size() >= 6) break;
    if (std::any_of(tried.begin(), tried.end(), [&](const CPose2D& t) { return !distinct(t, seed.pose); }))
      continue;
    tried.push_back(seed.pose);
    auto r = alignPlanar(reference_map, cloud_robot, seed.pose, wide, reference_viewpoints);
    r.icp_pose = r.pose = r.accepted ? r.pose : r.icp_pose;
    if (admissible && !admissible(r.pose))
      ++inadmissible;
    else
      refined.push_back(r);
  }
  std::sort(refined.begin(), refined.end(),
            [](const IcpResult& a, const IcpResult& b) { return a.goodness > b.goodness; });
  std::ostringstream why;
  if (refined.empty())
    why << "relocalisation failed: no seed" << (inadmissible > 0 ? " (all inadmissible)" : "");
  else if (!refined[0].accepted)
    why << "relocalisation failed: best match (goodness " << refined[0].goodness << " at "
        << refined[0].icp_pose.x() << " " << refined[0].icp_pose.y() << " "
        << mrpt::RAD2DEG(refined[0].icp_pose.phi()) << " deg) rejected: " << refined[0].reason;
  else if (refined[0].degenerate)
    why << "relocalisation failed: degenerate scene";
  else
    for (std::size_t i = 1; i < refined.size(); i++)
      if (distinct(refined[i].pose, refined[0].pose) &&
          refined[i].goodness > refined[0].goodness - p.relocalize_margin)
      {
        why << "relocalisation ambiguous: goodness " << refined[0].goodness << " vs "
            << refined[i].goodness << " at a distinct pose";
        break;
      }
  if (!why.str().empty())
  {
    none.reason = why.str();
    if (!refined.empty()) none.goodness = refined[0].goodness;
    return none;
  }
  IcpResult r = refined[0];
  const double dxy = std::hypot(r.pose.x() - predicted.x(), r.pose.y() - predicted.y());
  const double dyaw = mrpt::math::wrapToPi(r.pose.phi() - predicted.phi());
  std::ostringstream ok;
  ok << "relocalized: correction " << dxy << " m, " << mrpt::RAD2DEG(dyaw) << " deg, goodness "
     << r.goodness;
  r.reason = ok.str();
  return r;
}

}  // namespace voxplore::mapping
