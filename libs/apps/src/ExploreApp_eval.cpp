// voxplore-explore: ground-truth metrics of a run (coverage, clearance).
#include "ExploreApp_internal.h"

#include <mrpt/img/CImage.h>

#include <algorithm>
#include <stdexcept>
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
  if (d <= 0) return checker.collides(p, fp);
  // The rectangle's d-offset (corners rounded), circumscribed by a polygon of
  // four tangents per quarter arc: it holds the true shape and exceeds it by
  // at most d (1 / cos(11.25 deg) - 1) = 0.02 d at the arcs. A plain grown
  // rectangle exceeded it by up to 0.41 d at the corners, which made a
  // corner 3 cm from a door jamb read 2.1 cm.
  constexpr int kPerQuarter = 4;
  const double step = M_PI / 2 / kPerQuarter, r = d / std::cos(0.5 * step);
  const double hl = 0.5 * fp.length_m, hw = 0.5 * fp.width_m;
  const double corners[4][2] = {{hl, hw}, {-hl, hw}, {-hl, -hw}, {hl, -hw}};
  sim::ConvexPolygon2D poly;
  for (int k = 0; k < 4; k++)
    for (int j = 0; j < kPerQuarter; j++)
    {
      const double a = k * M_PI / 2 + (j + 0.5) * step;
      double wx = 0, wy = 0;
      p.composePoint(corners[k][0] + r * std::cos(a), corners[k][1] + r * std::sin(a), wx, wy);
      poly.vertices.emplace_back(wx, wy);
    }
  return checker.overlapsObstacle(poly);
}

/// Is the world-frame point `w` a Free cell of the map-frame grid `g`?
bool knownFree(const exploration::GroundGrid& g, const mrpt::poses::CPose2D& T_map_world,
               const Eigen::Vector2d& w)
{
  double mx = 0, my = 0;
  T_map_world.composePoint(w.x(), w.y(), mx, my);
  exploration::Cell c;
  if (!exploration::cellOf(g.state, Eigen::Vector2d(mx, my), c)) return false;
  const auto* s = g.state.cellByIndex(static_cast<unsigned>(c.cx), static_cast<unsigned>(c.cy));
  return s && *s == exploration::GroundState::Free;
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
      known += knownFree(g, T_map_world, free_floor_world.center(ix, iy));
    }
  return total ? double(known) / double(total) : 0.0;
}

void writeCoverageMap(
    const exploration::GroundGrid& g, const sim::FootprintReach& gt,
    const sim::ReachableFloor& planner, const sim::ReachableFloor& body,
    const mrpt::poses::CPose2D& T_world_map,
    const std::vector<mrpt::poses::CPose2D>& trajectory_world, const std::string& png_path,
    int scale)
{
  using mrpt::img::TColor;
  const sim::FloorGrid& f = gt.free_floor;
  const auto sameGrid = [&](const sim::FloorGrid& o) { return o.nx == f.nx && o.ny == f.ny; };
  const auto in = [&](const sim::FloorGrid& o, int ix, int iy)
  { return sameGrid(o) && o.at(ix, iy) != 0; };
  const mrpt::poses::CPose2D T_map_world = -T_world_map;
  mrpt::img::CImage img(f.nx * scale, f.ny * scale, mrpt::img::CH_RGB);
  const auto known = [&](int ix, int iy) { return knownFree(g, T_map_world, f.center(ix, iy)); };
  for (int iy = 0; iy < f.ny; iy++)
    for (int ix = 0; ix < f.nx; ix++)
    {
      TColor col(225, 225, 225);
      if (gt.obstacle.at(ix, iy))
        col = TColor(0, 0, 0);
      else if (f.at(ix, iy) && in(planner.free_floor, ix, iy))
        col = known(ix, iy) ? TColor(120, 160, 255) : TColor(220, 40, 40);
      else if (f.at(ix, iy))  // the footprint's floor beyond the planner's circle
        col = known(ix, iy) ? TColor(60, 190, 170) : TColor(150, 60, 200);
      else if (in(planner.free_floor, ix, iy) || in(body.free_floor, ix, iy))
        col = known(ix, iy) ? TColor(255, 210, 150) : TColor(255, 140, 0);
      const int x0 = ix * scale, y0 = (f.ny - 1 - iy) * scale;
      img.filledRectangle(x0, y0, x0 + scale - 1, y0 + scale - 1, col);
    }
  const auto px = [&](const mrpt::poses::CPose2D& p)
  {
    return std::make_pair(static_cast<int>((p.x() - f.origin.x()) / f.res_m * scale),
                          static_cast<int>((f.ny - (p.y() - f.origin.y()) / f.res_m) * scale));
  };
  for (std::size_t i = 1; i < trajectory_world.size(); i++)
  {
    const auto [x0, y0] = px(trajectory_world[i - 1]);
    const auto [x1, y1] = px(trajectory_world[i]);
    img.line(x0, y0, x1, y1, mrpt::img::TColor(120, 20, 20), 1);
  }
  if (!img.saveToFile(png_path)) throw std::runtime_error("cannot write image '" + png_path + "'");
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

ClearanceMin minClearance(
    const sim::CollisionChecker& checker, const sim::Footprint& footprint,
    const std::vector<mrpt::poses::CPose2D>& trajectory_world, double cap_m)
{
  ClearanceMin best;
  best.clearance_m = cap_m;
  if (!trajectory_world.empty()) best.pose_world = trajectory_world.front();
  for (std::size_t i = 0; i < trajectory_world.size(); i++)
  {
    const auto& p = trajectory_world[i];
    if (checker.collides(p, footprint)) return {0.0, i, p};
    // Only a margin below the best so far can lower the minimum.
    if (!collidesGrown(checker, footprint, p, best.clearance_m)) continue;
    double lo = 0, hi = best.clearance_m;
    while (hi - lo > 1e-3)
    {
      const double mid = 0.5 * (lo + hi);
      (collidesGrown(checker, footprint, p, mid) ? hi : lo) = mid;
    }
    best = {lo, i, p};
  }
  return best;
}

}  // namespace voxplore::apps::explore_detail
