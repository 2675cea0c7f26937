/* voxplore — the floor a rectangular robot can reach (position x yaw) and see (issue 10).
 *
 * Configuration space: 128-bit masks of yaw bins per floor cell (bin k =
 * yaw k * pi / bins), one for translation (the rectangle at the bin's yaw)
 * and one for turning (the rectangle grown to hold it over the bin's yaw
 * range). A state is blocked when the cell centre lies in the Minkowski sum
 * of an obstacle polygon and the rectangle (touching counts, as in
 * CollisionChecker): each sum is a convex polygon, scan-converted at the cell
 * centres of its rows, so the per-state answer is exact; nothing is sampled
 * but the robot's centre and yaw. Then a flood fill over the masks: a cell's
 * reachable bins spread to its 8 neighbours' free bins (translation) and,
 * inside a cell, between neighbouring turn-free bins (turning in place).
 * The floor the body covers and the cameras see: footprint_floor.cpp.
 *
 * Cost: two scan conversions per (polygon, bin) into one bit plane per bin
 * (whole words per span), then a gather into per-cell masks. On generated
 * 1000-1420 m^2 buildings (5-10 k polygons in the robot's slab, 5 cm cells,
 * 72 bins) the whole function takes 0.5-1.3 s on one core, on willowgarage
 * (2,450 m^2) 1.1-1.6 s (BENCHMARKS.md, "coverage_2d definition"). */

#include <mrpt/core/exceptions.h>
#include <voxplore/sim/footprint_reach.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "footprint_floor.h"

namespace voxplore::sim
{
namespace
{
using Vec2 = Eigen::Vector2d;

/// Yaw bins as bits: bit k of w[k / 64].
struct Mask
{
  uint64_t w[2] = {0, 0};
  bool any() const { return (w[0] | w[1]) != 0; }
  bool test(int k) const { return (w[k >> 6] >> (k & 63)) & 1u; }
  void set(int k) { w[k >> 6] |= uint64_t{1} << (k & 63); }
  Mask operator&(const Mask& o) const { return {{w[0] & o.w[0], w[1] & o.w[1]}}; }
  Mask operator|(const Mask& o) const { return {{w[0] | o.w[0], w[1] | o.w[1]}}; }
  Mask operator~() const { return {{~w[0], ~w[1]}}; }
  bool operator==(const Mask& o) const { return w[0] == o.w[0] && w[1] == o.w[1]; }
};

Mask fullMask(int bins)
{
  Mask m;
  for (int k = 0; k < bins; ++k) m.set(k);
  return m;
}

/// The bins one turn step (one bin either way, circular over [0, pi)) from `m`.
Mask turnOnce(const Mask& m, const Mask& full, int bins)
{
  Mask up{{m.w[0] << 1, (m.w[1] << 1) | (m.w[0] >> 63)}};
  Mask down{{(m.w[0] >> 1) | (m.w[1] << 63), m.w[1] >> 1}};
  if (m.test(bins - 1)) up.set(0);
  if (m.test(0)) down.set(bins - 1);
  return (m | up | down) & full;
}

/// The bins reachable from the bins `m` by turning in place: one bin at a
/// time, from a bin whose whole turn range is free (`turn`) to the next such bin.
Mask turnClosure(Mask m, const Mask& turn, const Mask& full, int bins)
{
  if (!(m & turn).any()) return m;
  if (turn == full) return full;
  for (;;)
  {
    const Mask next = m | (turnOnce(m & turn, full, bins) & turn);
    if (next == m) return m;
    m = next;
  }
}

double cross(const Vec2& o, const Vec2& a, const Vec2& b)
{
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Andrew's monotone chain (counter-clockwise, collinear points dropped).
std::vector<Vec2> convexHull(std::vector<Vec2> pts)
{
  std::sort(pts.begin(), pts.end(),
            [](const Vec2& a, const Vec2& b)
            { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  if (pts.size() <= 2) return pts;
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
  {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;)
  {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);
  return hull;
}

/// Cells of a window of the floor grid: [x0, x0 + nx) x [y0, y0 + ny).
struct Window
{
  int x0 = 0, y0 = 0, nx = 0, ny = 0;
  std::size_t index(int gx, int gy) const
  {
    return static_cast<std::size_t>(gy - y0) * nx + static_cast<std::size_t>(gx - x0);
  }
  bool inside(int gx, int gy) const { return gx >= x0 && gy >= y0 && gx < x0 + nx && gy < y0 + ny; }
};

/// The grid, or with a region only its cells within one cell of the region.
Window workWindow(const FloorGrid& g, const Eigen::AlignedBox2d* region)
{
  Window w{0, 0, g.nx, g.ny};
  if (!region || region->isEmpty()) return w;
  const auto idx = [&](double v, double o, int n)
  { return std::clamp(static_cast<int>(std::floor((v - o) / g.res_m)), 0, n - 1); };
  w.x0 = std::max(idx(region->min().x(), g.origin.x(), g.nx) - 1, 0);
  w.y0 = std::max(idx(region->min().y(), g.origin.y(), g.ny) - 1, 0);
  w.nx = std::min(idx(region->max().x(), g.origin.x(), g.nx) + 2, g.nx) - w.x0;
  w.ny = std::min(idx(region->max().y(), g.origin.y(), g.ny) + 2, g.ny) - w.y0;
  return w;
}

/// The checker's obstacle polygons that can touch the robot in the window
/// (exact duplicates, e.g. coincident faces, dropped), plus the outside of
/// the region as four strips.
std::vector<std::vector<Vec2>> obstaclePolygons(const CollisionChecker& checker, const FloorGrid& g,
                                                const Window& w, double reach_m,
                                                const Eigen::AlignedBox2d* region)
{
  const Vec2 lo = g.origin + g.res_m * Vec2(w.x0, w.y0) - Vec2::Constant(reach_m);
  const Vec2 hi = g.origin + g.res_m * Vec2(w.x0 + w.nx, w.y0 + w.ny) + Vec2::Constant(reach_m);
  std::vector<std::vector<Vec2>> out;
  for (const ConvexPolygon2D& p : checker.obstacles())
    if (!p.vertices.empty() && (p.max.array() >= lo.array()).all() &&
        (p.min.array() <= hi.array()).all())
      out.push_back(p.vertices);
  const auto less = [](const std::vector<Vec2>& a, const std::vector<Vec2>& b)
  {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(),
                                        [](const Vec2& u, const Vec2& v) {
                                          return u.x() < v.x() || (u.x() == v.x() && u.y() < v.y());
                                        });
  };
  std::sort(out.begin(), out.end(), less);
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (region && !region->isEmpty())
  {
    const Vec2 a = region->min(), b = region->max();
    const auto box = [&](double x0, double y0, double x1, double y1) {
      out.push_back({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
    };
    box(lo.x(), lo.y(), a.x(), hi.y());  // outside, left of the region
    box(b.x(), lo.y(), hi.x(), hi.y());  // right
    box(a.x(), lo.y(), b.x(), a.y());    // below
    box(a.x(), b.y(), b.x(), hi.y());    // above
  }
  return out;
}

/// Sets bits [c0, c1] of a row of bits.
void setSpan(uint64_t* row, int c0, int c1)
{
  const int w0 = c0 >> 6, w1 = c1 >> 6;
  const uint64_t m0 = ~uint64_t{0} << (c0 & 63), m1 = ~uint64_t{0} >> (63 - (c1 & 63));
  if (w0 == w1)
  {
    row[w0] |= m0 & m1;
    return;
  }
  row[w0] |= m0;
  for (int i = w0 + 1; i < w1; ++i) row[i] = ~uint64_t{0};
  row[w1] |= m1;
}

/// Scan-converts the convex counter-clockwise polygon `hull` at the cell
/// centres of the window: calls span(row, c0, c1) (window cell indices) for
/// every row with the cells whose centre lies in the closed polygon. The
/// edges going up bound it on the right, those going down on the left.
template <typename Span>
void scanConvert(const std::vector<Vec2>& hull, const FloorGrid& g, const Window& w,
                 std::vector<double>& xl, std::vector<double>& xr, Span span)
{
  const double res = g.res_m;
  const auto rowOf = [&](double y) { return (y - g.origin.y()) / res - 0.5; };  // fractional
  double ymin = hull.front().y(), ymax = ymin;
  for (const Vec2& v : hull)
  {
    ymin = std::min(ymin, v.y());
    ymax = std::max(ymax, v.y());
  }
  const int r0 = std::max(static_cast<int>(std::ceil(rowOf(ymin))), w.y0);
  const int r1 = std::min(static_cast<int>(std::floor(rowOf(ymax))), w.y0 + w.ny - 1);
  if (r0 > r1) return;
  xl.assign(r1 - r0 + 1, std::numeric_limits<double>::infinity());
  xr.assign(r1 - r0 + 1, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0, n = hull.size(); i < n; ++i)
  {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % n];
    if (a.y() == b.y()) continue;  // its ends belong to the neighbouring edges
    const bool right = b.y() > a.y();
    const double lo = std::min(a.y(), b.y()), hi = std::max(a.y(), b.y());
    const int e0 = std::max(static_cast<int>(std::ceil(rowOf(lo))), r0);
    const int e1 = std::min(static_cast<int>(std::floor(rowOf(hi))), r1);
    const double dxdy = (b.x() - a.x()) / (b.y() - a.y());
    for (int iy = e0; iy <= e1; ++iy)
    {
      const double y = g.origin.y() + (iy + 0.5) * res;
      const double x = y == a.y() ? a.x() : y == b.y() ? b.x() : a.x() + (y - a.y()) * dxdy;
      double& side = right ? xr[iy - r0] : xl[iy - r0];
      side = right ? std::max(side, x) : std::min(side, x);
    }
  }
  for (int iy = r0; iy <= r1; ++iy)
  {
    const double lx = xl[iy - r0], rx = xr[iy - r0];
    if (!(lx <= rx)) continue;
    const int c0 = std::max(static_cast<int>(std::ceil((lx - g.origin.x()) / res - 0.5)), w.x0);
    const int c1 =
        std::min(static_cast<int>(std::floor((rx - g.origin.x()) / res - 0.5)), w.x0 + w.nx - 1);
    if (c0 <= c1) span(iy - w.y0, c0 - w.x0, c1 - w.x0);
  }
}

/// Blocked bins per window cell: bin k where the centre lies in (polygon +
/// rectangle (half sizes hl, hw) at yaw k) for some polygon. Rasterised into
/// one bit plane per bin (whole words per span), then gathered per cell.
std::vector<Mask> blockedBins(const std::vector<std::vector<Vec2>>& polys, const FloorGrid& g,
                              const Window& w, int bins, double hl, double hw)
{
  const std::size_t words = (static_cast<std::size_t>(w.nx) + 63) / 64;
  const std::size_t plane = words * w.ny;
  std::vector<uint64_t> planes(plane * bins, 0);
  std::vector<std::array<Vec2, 4>> rect(bins);
  for (int k = 0; k < bins; ++k)
  {
    const auto corners = Footprint{2 * hl, 2 * hw}.at(mrpt::poses::CPose2D(0, 0, k * M_PI / bins));
    std::copy(corners.vertices.begin(), corners.vertices.end(), rect[k].begin());
  }
  std::vector<Vec2> sums;
  std::vector<double> xl, xr;
  for (const auto& p : polys)
    for (int k = 0; k < bins; ++k)
    {
      sums.clear();
      for (const Vec2& v : p)
        for (const Vec2& c : rect[k]) sums.push_back(v + c);
      uint64_t* bits = &planes[plane * k];
      scanConvert(convexHull(sums), g, w, xl, xr,
                  [&](int row, int c0, int c1) { setSpan(bits + row * words, c0, c1); });
    }
  std::vector<Mask> blocked(static_cast<std::size_t>(w.nx) * w.ny);
  for (int k = 0; k < bins; ++k)
    for (int y = 0; y < w.ny; ++y)
      for (std::size_t i = 0; i < words; ++i)
        for (uint64_t b = planes[plane * k + y * words + i]; b; b &= b - 1)
          blocked[static_cast<std::size_t>(y) * w.nx + i * 64 + __builtin_ctzll(b)].set(k);
  return blocked;
}

/// The start state: the start cell with the start yaw's bin, or when that is
/// blocked the free bins next to it. Empty mask when none is free.
Mask startBins(const Mask& free, double yaw, int bins)
{
  const double t = std::fmod(yaw, M_PI) + (std::fmod(yaw, M_PI) < 0 ? M_PI : 0);
  const int k = static_cast<int>(std::lround(t / (M_PI / bins))) % bins;
  Mask m;
  m.set(k);
  if ((m & free).any()) return m;
  m.set((k + 1) % bins);
  m.set((k + bins - 1) % bins);
  return m & free;
}

/// The start state: the start yaw's bin at the start cell, or when that is
/// blocked the free bins next to it; when neither fits there, the same at
/// the 8-neighbour cell nearest to the true start (a start pose with less
/// clearance than its offset from the cell centre). Sets (sx, sy) to the
/// cell; an empty mask when none fits.
Mask startState(const std::vector<Mask>& at_yaw, const Window& w, const FloorGrid& g,
                const mrpt::poses::CPose2D& start, const Mask& full, int bins, int& sx, int& sy)
{
  const int cx = static_cast<int>(std::floor((start.x() - g.origin.x()) / g.res_m));
  const int cy = static_cast<int>(std::floor((start.y() - g.origin.y()) / g.res_m));
  Mask best;
  double best_d = std::numeric_limits<double>::infinity();
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
    {
      const int x = cx + dx, y = cy + dy;
      if (!w.inside(x, y)) continue;
      const Mask bins_here = startBins(~at_yaw[w.index(x, y)] & full, start.phi(), bins);
      const double d =
          dx == 0 && dy == 0 ? -1.0 : (g.center(x, y) - Vec2(start.x(), start.y())).norm();
      if (!bins_here.any() || d >= best_d) continue;
      best = bins_here;
      best_d = d;
      sx = x;
      sy = y;
    }
  return best;
}

/// Blocked bins per window cell for translation (the rectangle at the bin's
/// yaw) and for turning (the rectangle grown to cover the bin's yaw range).
struct BlockedBins
{
  std::vector<Mask> at_yaw, turning;
};

/// The flood fill over (cell, bin): translation keeps the bin, turning in
/// place moves between neighbouring bins. Returns the reachable bins per window cell.
std::vector<Mask> floodFill(const BlockedBins& blocked, const Window& w, int sx, int sy,
                            const Mask& seed, const Mask& full, int bins)
{
  const std::size_t n = blocked.at_yaw.size();
  std::vector<Mask> reach(n);
  std::vector<uint8_t> queued(n, 0);
  const auto turnAt = [&](std::size_t i) { return ~blocked.turning[i] & full; };
  const std::size_t s = w.index(sx, sy);
  reach[s] = turnClosure(seed, turnAt(s), full, bins);
  std::vector<std::pair<int, int>> stack{{sx, sy}};
  queued[s] = 1;
  while (!stack.empty())
  {
    const auto [x, y] = stack.back();
    stack.pop_back();
    const std::size_t i = w.index(x, y);
    queued[i] = 0;
    const Mask m = reach[i];
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
      {
        if ((dx == 0 && dy == 0) || !w.inside(x + dx, y + dy)) continue;
        const std::size_t j = w.index(x + dx, y + dy);
        const Mask add = m & ~blocked.at_yaw[j] & ~reach[j];
        if (!add.any()) continue;
        reach[j] = turnClosure(reach[j] | add, turnAt(j), full, bins);
        if (!queued[j])
        {
          queued[j] = 1;
          stack.emplace_back(x + dx, y + dy);
        }
      }
  }
  return reach;
}

/// Keeps the reachable bins (window) and the reachable centres (grid) in `r`.
void storeReachable(const std::vector<Mask>& reach, const Window& w, FootprintReach& r)
{
  r.bins_x0 = w.x0;
  r.bins_y0 = w.y0;
  r.bins_nx = w.nx;
  r.bins_ny = w.ny;
  r.bins.resize(reach.size());
  for (std::size_t i = 0; i < reach.size(); ++i) r.bins[i] = {reach[i].w[0], reach[i].w[1]};
  for (int gy = w.y0; gy < w.y0 + w.ny; ++gy)
    for (int gx = w.x0; gx < w.x0 + w.nx; ++gx)
      r.reachable.at(gx, gy) = reach[w.index(gx, gy)].any() ? 1 : 0;
}


}  // namespace

double FootprintReach::binYaw(int bin) const
{
  return yaw_bins > 0 ? bin * M_PI / yaw_bins : 0.0;
}

bool FootprintReach::reachableAt(int ix, int iy, int bin) const
{
  if (bin < 0 || bin >= yaw_bins) return false;
  if (ix < bins_x0 || iy < bins_y0 || ix >= bins_x0 + bins_nx || iy >= bins_y0 + bins_ny)
    return false;
  const auto& m = bins[static_cast<std::size_t>(iy - bins_y0) * bins_nx + (ix - bins_x0)];
  return (m[bin >> 6] >> (bin & 63)) & 1u;
}

FootprintReach footprintReachableFloor(const World& world, const CollisionChecker& checker,
                                       const mrpt::poses::CPose2D& start,
                                       const Footprint& footprint,
                                       const FootprintReachParams& params,
                                       const Eigen::AlignedBox2d* region)
{
  ASSERTMSG_(params.res_m > 0, mrpt::format("footprintReachableFloor: resolution must be > 0, "
                                            "got %g",
                                            params.res_m));
  ASSERTMSG_(
      params.yaw_bins >= 2 && params.yaw_bins <= 128,
      mrpt::format("footprintReachableFloor: yaw_bins must be in 2..128, got %d", params.yaw_bins));
  ASSERTMSG_(params.view_range_m >= 0, "footprintReachableFloor: view range must be >= 0");
  FootprintReach r;
  r.yaw_bins = params.yaw_bins;
  r.obstacle = obstacleFloorGrid(world, checker, start, params.res_m, region);
  r.reachable = r.obstacle.emptyLike();
  r.swept = r.visible = r.free_floor = r.reachable;
  const FloorGrid& g = r.obstacle;
  const int bins = params.yaw_bins;
  const double delta = M_PI / bins, R = footprint.circumradius();
  r.sweep_margin_m = 2 * R * std::sin(delta / 4);  // chord of a half-bin turn at radius R
  const double hl = 0.5 * footprint.length_m, hw = 0.5 * footprint.width_m;
  const double m = r.sweep_margin_m;

  const Window w = workWindow(g, region);
  const auto polys = obstaclePolygons(checker, g, w, std::hypot(hl + m, hw + m) + g.res_m, region);
  BlockedBins blocked;
  blocked.at_yaw = blockedBins(polys, g, w, bins, hl, hw);
  blocked.turning = blockedBins(polys, g, w, bins, hl + m, hw + m);
  const Mask full = fullMask(bins);
  int sx = 0, sy = 0;
  const Mask seed = startState(blocked.at_yaw, w, g, start, full, bins, sx, sy);
  if (!seed.any()) return r;
  r.start_free = true;
  storeReachable(floodFill(blocked, w, sx, sy, seed, full, bins), w, r);
  blocked = {};

  detail::sweepFloor(r, footprint);
  detail::seeFloor(r, params.view_range_m);
  for (std::size_t i = 0; i < g.cells.size(); ++i)
  {
    r.swept.cells[i] &= g.cells[i] == 0 ? 1 : 0;
    r.free_floor.cells[i] =
        g.cells[i] == 0 && (r.reachable.cells[i] | r.swept.cells[i] | r.visible.cells[i]) ? 1 : 0;
  }
  r.reachable_area_m2 = r.reachable.areaM2();
  r.free_floor_area_m2 = r.free_floor.areaM2();
  return r;
}

}  // namespace voxplore::sim
