/* voxplore — procedural buildings: walls from the region outlines, cut at the
 * doors, and the free floor they leave. */

#include <algorithm>

#include "worldgen_internal.h"

namespace voxplore::sim::worldgen_detail
{
/// Walls: the edges between cells of different regions (or a region and the
/// outside) on the lattice, merged into runs, cut at the doors. A run's own
/// ends reach half a wall thickness past the corner so that walls close;
/// door jambs end exactly at the opening.
void buildWalls(GeneratedBuilding& b, double t)
{
  Rect2 bb{1e9, 1e9, -1e9, -1e9};
  for (const GenRegion& r : b.regions)
    for (const Rect2& q : r.rects)
      bb = {std::min(bb.x0, q.x0), std::min(bb.y0, q.y0), std::max(bb.x1, q.x1), std::max(bb.y1, q.y1)};
  b.bounds = bb;
  const int nx = static_cast<int>(std::lround(bb.width() / kLattice));
  const int ny = static_cast<int>(std::lround(bb.height() / kLattice));
  std::vector<int> label(static_cast<std::size_t>(nx) * ny, 0);
  for (const GenRegion& r : b.regions)
    for (const Rect2& q : r.rects)
      for (int iy = static_cast<int>(std::lround((q.y0 - bb.y0) / kLattice));
           iy < static_cast<int>(std::lround((q.y1 - bb.y0) / kLattice)); iy++)
        for (int ix = static_cast<int>(std::lround((q.x0 - bb.x0) / kLattice));
             ix < static_cast<int>(std::lround((q.x1 - bb.x0) / kLattice)); ix++)
          label[static_cast<std::size_t>(iy) * nx + ix] = r.id;
  const auto at = [&](int ix, int iy)
  { return (ix < 0 || iy < 0 || ix >= nx || iy >= ny) ? 0 : label[static_cast<std::size_t>(iy) * nx + ix]; };

  // One pass per orientation: `line` indexes the lattice lines, `s` the cells along them.
  for (const bool along_x : {true, false})
  {
    const int n_lines = along_x ? ny : nx, n_cells = along_x ? nx : ny;
    for (int line = 0; line <= n_lines; line++)
    {
      const double c = along_x ? bb.y0 + line * kLattice : bb.x0 + line * kLattice;
      std::vector<const GenDoor*> doors_here;
      for (const GenDoor& d : b.doors)
        if (d.along_x == along_x && std::abs((along_x ? d.center.y() : d.center.x()) - c) < 1e-6)
          doors_here.push_back(&d);
      const auto wall = [&](int k)
      { return along_x ? at(k, line - 1) != at(k, line) : at(line - 1, k) != at(line, k); };
      const double base = along_x ? bb.x0 : bb.y0;
      for (int s = 0; s < n_cells;)
      {
        if (!wall(s))
        {
          s++;
          continue;
        }
        int e = s;
        while (e < n_cells && wall(e)) e++;
        // The run [s, e) minus its door gaps; only the run's own two ends are extended.
        std::vector<std::pair<double, double>> gaps;
        for (const GenDoor* d : doors_here)
        {
          const double m = along_x ? d->center.x() : d->center.y();
          if (m > base + s * kLattice && m < base + e * kLattice)
            gaps.emplace_back(m - 0.5 * d->width_m, m + 0.5 * d->width_m);
        }
        std::sort(gaps.begin(), gaps.end());
        double lo = base + s * kLattice;
        bool lo_ext = true;
        const auto emit = [&](double a, bool ext_a, double z, bool ext_z)
        {
          a -= ext_a ? 0.5 * t : 0.0;
          z += ext_z ? 0.5 * t : 0.0;
          if (z - a < 1e-6) return;
          GenWall w;
          w.from = along_x ? Eigen::Vector2d(a, c) : Eigen::Vector2d(c, a);
          w.to = along_x ? Eigen::Vector2d(z, c) : Eigen::Vector2d(c, z);
          b.walls.push_back(w);
        };
        for (const auto& [g0, g1] : gaps)
        {
          emit(lo, lo_ext, g0, false);
          lo = g1;
          lo_ext = false;
        }
        emit(lo, lo_ext, base + e * kLattice, true);
        s = e;
      }
    }
  }
}

/// Free floor: region cells (on a lattice of half the layout's) outside every wall.
double floorArea(const GeneratedBuilding& b, double t)
{
  const double res = 0.5 * kLattice;
  const Rect2& bb = b.bounds;
  const int nx = static_cast<int>(std::lround(bb.width() / res)) + 1;
  const int ny = static_cast<int>(std::lround(bb.height() / res)) + 1;
  std::vector<uint8_t> cell(static_cast<std::size_t>(nx) * ny, 0);  // 1 floor, 2 wall
  const auto paint = [&](const Rect2& q, uint8_t v, bool only_floor)
  {
    // cells whose centre lies inside q
    const int ix0 = std::max(0, static_cast<int>(std::ceil((q.x0 - bb.x0) / res - 0.5)));
    const int ix1 = std::min(nx - 1, static_cast<int>(std::floor((q.x1 - bb.x0) / res - 0.5)));
    const int iy0 = std::max(0, static_cast<int>(std::ceil((q.y0 - bb.y0) / res - 0.5)));
    const int iy1 = std::min(ny - 1, static_cast<int>(std::floor((q.y1 - bb.y0) / res - 0.5)));
    for (int iy = iy0; iy <= iy1; iy++)
      for (int ix = ix0; ix <= ix1; ix++)
      {
        uint8_t& c = cell[static_cast<std::size_t>(iy) * nx + ix];
        if (!only_floor || c == 1) c = v;
      }
  };
  for (const GenRegion& r : b.regions)
    for (const Rect2& q : r.rects) paint(q, 1, false);
  for (const GenWall& w : b.walls)
  {
    const bool ax = std::abs(w.from.y() - w.to.y()) < 1e-9;
    const double x0 = std::min(w.from.x(), w.to.x()), x1 = std::max(w.from.x(), w.to.x());
    const double y0 = std::min(w.from.y(), w.to.y()), y1 = std::max(w.from.y(), w.to.y());
    paint(ax ? Rect2{x0, y0 - 0.5 * t, x1, y1 + 0.5 * t} : Rect2{x0 - 0.5 * t, y0, x1 + 0.5 * t, y1},
          2, true);
  }
  return res * res * static_cast<double>(std::count(cell.begin(), cell.end(), uint8_t{1}));
}

}  // namespace voxplore::sim::worldgen_detail
