/* voxplore — the floor a footprint-reachable robot covers with its body and
 * sees with its cameras (issue 10; the configuration space is in
 * footprint_reach.cpp). */

#include "footprint_floor.h"

#include <voxplore/common/distance_transform.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace voxplore::sim::detail
{
namespace
{
using Vec2 = Eigen::Vector2d;
using BinMask = std::array<uint64_t, 2>;

/// x range [xl, xr] of the convex polygon on the line at height y; false when it misses.
bool rowSpan(const std::vector<Vec2>& poly, double y, double& xl, double& xr)
{
  xl = std::numeric_limits<double>::infinity();
  xr = -xl;
  for (std::size_t i = 0, n = poly.size(); i < n; ++i)
  {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % n];
    if (y < std::min(a.y(), b.y()) || y > std::max(a.y(), b.y())) continue;
    if (a.y() == b.y())
    {
      xl = std::min({xl, a.x(), b.x()});
      xr = std::max({xr, a.x(), b.x()});
      continue;
    }
    const double x = a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
    xl = std::min(xl, x);
    xr = std::max(xr, x);
  }
  return xl <= xr;
}

/// The rectangle at each bin's yaw as rows {dy, dx0, dx1} of the cell
/// offsets whose centres it covers when centred on a cell centre.
std::vector<std::vector<std::array<int, 3>>> rectangleStamps(const Footprint& fp,
                                                             const FootprintReach& r, double res)
{
  const int span = static_cast<int>(std::ceil(fp.circumradius() / res)) + 1;
  std::vector<std::vector<std::array<int, 3>>> stamps(r.yaw_bins);
  for (int k = 0; k < r.yaw_bins; ++k)
  {
    const std::vector<Vec2> rect = fp.at(mrpt::poses::CPose2D(0, 0, r.binYaw(k))).vertices;
    for (int dy = -span; dy <= span; ++dy)
    {
      double xl = 0, xr = 0;
      if (rowSpan(rect, dy * res, xl, xr))
        stamps[k].push_back(
            {dy, static_cast<int>(std::ceil(xl / res)), static_cast<int>(std::floor(xr / res))});
    }
  }
  return stamps;
}

/// Reachable bins of grid cell (gx, gy); none outside the masks' window.
BinMask binsAt(const FootprintReach& r, int gx, int gy)
{
  if (gx < r.bins_x0 || gy < r.bins_y0 || gx >= r.bins_x0 + r.bins_nx ||
      gy >= r.bins_y0 + r.bins_ny)
    return {0, 0};
  return r.bins[static_cast<std::size_t>(gy - r.bins_y0) * r.bins_nx + (gx - r.bins_x0)];
}

/// Casts one ray (direction th) from the centre of cell (sx, sy) with
/// Amanatides & Woo's grid traversal, marking r.visible up to `range`
/// cells, until an obstacle cell, a reachable cell or the grid's edge.
void castRay(FootprintReach& r, int sx, int sy, double th, double range)
{
  const FloorGrid& R = r.reachable;
  const double c = std::cos(th), s = std::sin(th);
  const int step_x = c > 0 ? 1 : -1, step_y = s > 0 ? 1 : -1;
  const double dtx = c != 0 ? 1.0 / std::abs(c) : 1e30, dty = s != 0 ? 1.0 / std::abs(s) : 1e30;
  double tx = 0.5 * dtx, ty = 0.5 * dty;
  int x = sx, y = sy;
  for (;;)
  {
    double t = 0;
    if (tx < ty)
    {
      t = tx;
      tx += dtx;
      x += step_x;
    }
    else
    {
      t = ty;
      ty += dty;
      y += step_y;
    }
    if (t > range || !R.inside(x, y) || r.obstacle.at(x, y) || R.at(x, y)) return;
    r.visible.at(x, y) = 1;
  }
}
}  // namespace

/// All cells within half the width of a reachable centre (the inscribed
/// disc), plus the rectangle stamped, per bin, at the cells of that bin's
/// reachable set that border on cells outside it. The union of the rectangle
/// over a region is the region plus the union over its border (the rectangle
/// is star-shaped about its centre), so the stamps miss nothing but the
/// discretisation of the border (about a cell). A border cell deeper than
/// R - w/2 inside the reachable set stamps nothing the inscribed discs do
/// not already cover, and is skipped.
void sweepFloor(FootprintReach& r, const Footprint& fp)
{
  const FloorGrid& R = r.reachable;
  const double res = R.res_m, hw = 0.5 * fp.width_m;
  const std::vector<double> d_reach = R.squaredCellDistance(true);
  const std::vector<double> d_out = R.squaredCellDistance(false);
  for (std::size_t i = 0; i < d_reach.size(); ++i)
    if (d_reach[i] <= std::pow(hw / res, 2) * (1 + 1e-9)) r.swept.cells[i] = 1;
  const auto stamps = rectangleStamps(fp, r, res);
  const double deep2 = std::pow((fp.circumradius() - hw) / res + 1.0, 2);
  for (int gy = r.bins_y0; gy < r.bins_y0 + r.bins_ny; ++gy)
    for (int gx = r.bins_x0; gx < r.bins_x0 + r.bins_nx; ++gx)
    {
      const BinMask m = binsAt(r, gx, gy);
      if (!(m[0] | m[1]) || d_out[static_cast<std::size_t>(gy) * R.nx + gx] > deep2) continue;
      BinMask interior = m;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
        {
          const BinMask n = binsAt(r, gx + dx, gy + dy);
          interior = {interior[0] & n[0], interior[1] & n[1]};
        }
      for (int k = 0; k < r.yaw_bins; ++k)
      {
        if (!(((m[k >> 6] & ~interior[k >> 6]) >> (k & 63)) & 1u)) continue;  // not a border bin
        for (const auto& [dy, dx0, dx1] : stamps[k])
        {
          const int y = gy + dy, x0 = std::max(gx + dx0, 0), x1 = std::min(gx + dx1, R.nx - 1);
          if (y < 0 || y >= R.ny || x0 > x1) continue;
          std::fill_n(&r.swept.at(x0, y), x1 - x0 + 1, uint8_t{1});
        }
      }
    }
}

/// A cell outside the reachable set seen from a reachable centre is seen
/// from the last reachable cell on the way, which is nearer: rays start only
/// at reachable cells with a 4-neighbour outside the set, only into the
/// quadrants of those neighbours (a ray from a cell centre first enters the
/// 4-neighbour of its quadrant), and stop at an obstacle or on re-entering
/// the set. Rays are 2 pi range / res apart in angle (one cell apart at the
/// range); a cell is counted when a ray enters it within the range.
void seeFloor(FootprintReach& r, double range_m)
{
  const FloorGrid& R = r.reachable;
  const double range = range_m / R.res_m;  // in cells
  if (!(range > 0)) return;
  const int n_rays = 8 * static_cast<int>(std::ceil(2 * M_PI * range / 8));
  const int nbr[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};  // quadrant q: (q -+ 1/2) * 90 deg
  for (int sy = 0; sy < R.ny; ++sy)
    for (int sx = 0; sx < R.nx; ++sx)
    {
      if (!R.at(sx, sy)) continue;
      for (int q = 0; q < 4; ++q)
      {
        const int fx = sx + nbr[q][0], fy = sy + nbr[q][1];
        if (!R.inside(fx, fy) || R.at(fx, fy)) continue;
        for (int a = (2 * q - 1) * n_rays / 8; a <= (2 * q + 1) * n_rays / 8; ++a)
          castRay(r, sx, sy, 2 * M_PI * a / n_rays, range);
      }
    }
}

}  // namespace voxplore::sim::detail
