// voxplore-explore: ground-truth metrics of a run (coverage, clearance).
#include "ExploreApp_internal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace voxplore::apps::explore_detail
{
namespace
{
int64_t packKey(int x, int y, int z)
{
  const auto u = [](int v) { return static_cast<int64_t>(v + (1 << 20)) & ((int64_t(1) << 21) - 1); };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}

bool collidesGrown(
    const sim::CollisionChecker& checker, const sim::Footprint& fp, const mrpt::poses::CPose2D& p,
    double d)
{
  return checker.collides(p, sim::Footprint{fp.length_m + 2 * d, fp.width_m + 2 * d});
}
}  // namespace

double coverage2d(
    const exploration::GroundGrid& g, const sim::FloorGrid& free_floor_world,
    const mrpt::poses::CPose2D& T_world_map)
{
  const mrpt::poses::CPose2D T_map_world = -T_world_map;
  std::size_t total = 0, known = 0;
  for (int iy = 0; iy < free_floor_world.ny; iy++)
    for (int ix = 0; ix < free_floor_world.nx; ix++)
    {
      if (!free_floor_world.at(ix, iy)) continue;
      total++;
      const Eigen::Vector2d cw = free_floor_world.center(ix, iy);
      double mx = 0, my = 0;
      T_map_world.composePoint(cw.x(), cw.y(), mx, my);
      exploration::Cell c;
      if (!exploration::cellOf(g.state, Eigen::Vector2d(mx, my), c)) continue;
      const auto* s = g.state.cellByIndex(static_cast<unsigned>(c.cx), static_cast<unsigned>(c.cy));
      if (s && *s == exploration::GroundState::Free) known++;
    }
  return total ? double(known) / double(total) : 0.0;
}

double coverage3d(
    const std::vector<Eigen::Vector3d>& occupied_centers_map, const mrpt::poses::CPose3D& T_world_map,
    const std::vector<sim::VoxelIndex>& band, double res_m)
{
  if (band.empty()) return 0.0;
  std::unordered_set<int64_t> occ;
  occ.reserve(occupied_centers_map.size() * 2);
  for (const auto& p : occupied_centers_map)
  {
    double x, y, z;
    T_world_map.composePoint(p.x(), p.y(), p.z(), x, y, z);
    occ.insert(packKey(int(std::floor(x / res_m)), int(std::floor(y / res_m)),
                       int(std::floor(z / res_m))));
  }
  std::size_t seen = 0;
  for (const auto& v : band)
  {
    bool hit = false;
    for (int dx = -1; dx <= 1 && !hit; dx++)
      for (int dy = -1; dy <= 1 && !hit; dy++)
        for (int dz = -1; dz <= 1 && !hit; dz++)
          hit = occ.count(packKey(v.x() + dx, v.y() + dy, v.z() + dz)) > 0;
    seen += hit;
  }
  return double(seen) / double(band.size());
}

double minClearance(
    const sim::CollisionChecker& checker, const sim::Footprint& footprint,
    const std::vector<mrpt::poses::CPose2D>& trajectory_world, double cap_m)
{
  double best = cap_m;
  for (const auto& p : trajectory_world)
  {
    if (checker.collides(p, footprint)) return 0.0;
    // Only a margin below the best so far can lower the minimum.
    if (!collidesGrown(checker, footprint, p, best)) continue;
    double lo = 0, hi = best;
    while (hi - lo > 1e-3)
    {
      const double mid = 0.5 * (lo + hi);
      (collidesGrown(checker, footprint, p, mid) ? hi : lo) = mid;
    }
    best = lo;
  }
  return best;
}

}  // namespace voxplore::apps::explore_detail
