/* voxplore — projection of the voxel space V to the ground grid G
 * (thesis 4.5.1, algorithm 2). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <octomap/OcTree.h>
#include <voxplore/common/config.h>
#include <voxplore/common/polygon.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <vector>

#include "projection_columns.h"

namespace voxplore::exploration
{
namespace
{
using detail::ColumnTally;
using KeyBox = mapping::KeyBox;

/// Algorithm 2, lines 2-17: 4-neighbour flood fill over the column states.
/// A cell is marked when queued rather than when taken (same result as the
/// "already processed" test of line 5, and each cell is queued once).
void floodFill(const ColumnTally& tally, int levels, const std::vector<uint8_t>& outside,
               const std::vector<uint8_t>& swept, GroundGrid& G)
{
  const int nx = static_cast<int>(G.state.getSizeX());
  const int ny = static_cast<int>(G.state.getSizeY());
  std::vector<uint8_t> queued(static_cast<std::size_t>(nx) * ny, 0);
  std::vector<int> queue(queued.size());
  auto* state = &*G.state.begin();
  std::size_t tail = 0;
  const auto push = [&](int i)
  {
    if (queued[i]) return;
    queued[i] = 1;
    queue[tail++] = i;
  };
  const int robot_i = G.robot.cx + G.robot.cy * nx;
  push(robot_i);
  for (std::size_t head = 0; head < tail; ++head)
  {
    const int i = queue[head];
    // The robot stands on its own column: free whatever the map says (the
    // cameras are blind within ~1 m; an occupied voxel there is noise or a
    // pose error), so the fill always starts. An occupied robot column used
    // to leave G all unknown and end the exploration (willowgarage, step 36).
    if (i != robot_i && (tally.occupied[i] || (!outside.empty() && outside[i])))
      state[i] = GroundState::Occupied;
    else if (tally.free_count[i] < levels && i != robot_i && (swept.empty() || !swept[i]))
      state[i] = GroundState::Unknown;
    else
    {
      state[i] = GroundState::Free;
      const int cx = i % nx, cy = i / nx;
      if (cx + 1 < nx) push(i + 1);
      if (cx > 0) push(i - 1);
      if (cy + 1 < ny) push(i + nx);
      if (cy > 0) push(i - nx);
    }
  }
}
/// 1 for every cell of G within swept_radius_m of a swept pose, or (with
/// swept_footprint) whose centre lies under the footprint rectangle shrunk by
/// swept_footprint_margin_m at a swept pose (empty: none). Our own: the
/// thesis marks no swept floor; see ProjectionParams::swept_footprint.
std::vector<uint8_t> sweptMask(const GroundGrid& G, const SweptPath& swept,
                               const ProjectionParams& p)
{
  const double half_l = 0.5 * p.footprint_length_m - p.swept_footprint_margin_m;
  const double half_w = 0.5 * p.footprint_width_m - p.swept_footprint_margin_m;
  const bool rect = p.swept_footprint && half_l > 0 && half_w > 0;
  const double radius = p.swept_radius_m;
  if (swept.empty() || (radius <= 0 && !rect)) return {};
  const int nx = static_cast<int>(G.state.getSizeX());
  const int ny = static_cast<int>(G.state.getSizeY());
  const double res = G.state.getResolution();
  const double x0 = G.state.getXMin(), y0 = G.state.getYMin();
  const double reach = std::max(radius, rect ? std::hypot(half_l, half_w) : 0.0);
  std::vector<uint8_t> out(static_cast<std::size_t>(nx) * ny, 0);
  // Marks the cells of row y whose centre's dx from the pose lies in [lo, hi].
  auto markRow = [&](int y, double qx, double lo, double hi) {
    const int a = std::max(0, static_cast<int>(std::ceil((qx + lo - x0) / res - 0.5 - 1e-9)));
    const int b = std::min(nx - 1, static_cast<int>(std::floor((qx + hi - x0) / res - 0.5 + 1e-9)));
    if (a <= b) std::fill(out.begin() + static_cast<std::ptrdiff_t>(y) * nx + a,
                          out.begin() + static_cast<std::ptrdiff_t>(y) * nx + b + 1, uint8_t{1});
  };
  // Narrows [lo, hi] to the dx with |k * dx + m| <= h.
  auto slab = [](double k, double m, double h, double& lo, double& hi) {
    if (std::abs(k) < 1e-12)
    {
      if (std::abs(m) > h) hi = lo - 1;  // empty
      return;
    }
    const double u = (-h - m) / k, v = (h - m) / k;
    lo = std::max(lo, std::min(u, v));
    hi = std::min(hi, std::max(u, v));
  };
  // Row by row, the disc's and the rectangle's span of cell centres (the
  // rectangle as two slabs in its own axes): the same cells as testing each
  // centre, without testing the cells in between.
  for (const auto& q : swept)
  {
    const double c = std::cos(q.z()), s = std::sin(q.z());
    const int ya = std::max(0, static_cast<int>(std::ceil((q.y() - reach - y0) / res - 0.5 - 1e-9)));
    const int yb = std::min(ny - 1, static_cast<int>(std::floor((q.y() + reach - y0) / res - 0.5 + 1e-9)));
    for (int y = ya; y <= yb; ++y)
    {
      const double dy = G.state.idx2y(y) - q.y();
      if (radius > 0 && std::abs(dy) <= radius)
      {
        const double h = std::sqrt(radius * radius - dy * dy);
        markRow(y, q.x(), -h, h);
      }
      if (rect)
      {
        double lo = -reach, hi = reach;
        slab(c, s * dy, half_l, lo, hi);   // |c dx + s dy| <= half_l
        slab(-s, c * dy, half_w, lo, hi);  // |-s dx + c dy| <= half_w
        if (lo <= hi) markRow(y, q.x(), lo, hi);
      }
    }
  }
  return out;
}

/// 1 for every cell of G whose centre lies outside the region (empty: none).
std::vector<uint8_t> outsideMask(const GroundGrid& G, const std::vector<Eigen::Vector2d>& region)
{
  if (region.empty()) return {};
  const int nx = static_cast<int>(G.state.getSizeX());
  const int ny = static_cast<int>(G.state.getSizeY());
  std::vector<uint8_t> out(static_cast<std::size_t>(nx) * ny, 0);
  for (int cy = 0; cy < ny; ++cy)
  {
    const double y = G.state.idx2y(cy);
    for (int cx = 0; cx < nx; ++cx)
      out[static_cast<std::size_t>(cy) * nx + cx] =
          common::pointInPolygon(region, G.state.idx2x(cx), y) ? 0 : 1;
  }
  return out;
}
}  // namespace

void ProjectionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                          const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(z_max_m, double, c, s);
  obstacle_z_max_m = common::readNumberOrWord(c, s, "obstacle_z_max_m", obstacle_z_max_m, "auto",
                                              kAuto);
  MRPT_LOAD_CONFIG_VAR(auto_obstacle_z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(th_free, int, c, s);
  MRPT_LOAD_CONFIG_VAR(th_occ, int, c, s);
  MRPT_LOAD_CONFIG_VAR(margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(swept_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(swept_footprint, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(swept_footprint_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(incremental, bool, c, s);
  using common::requireValid;
  requireValid(obstacle_z_max_m == kAuto || obstacle_z_max_m >= 0, c, s, "obstacle_z_max_m",
               "must be auto or >= 0");
  requireValid(auto_obstacle_z_max_m >= 0, c, s, "auto_obstacle_z_max_m", "must be >= 0");
  requireValid(swept_radius_m >= 0, c, s, "swept_radius_m", "must be >= 0");
  requireValid(swept_footprint_margin_m >= 0, c, s, "swept_footprint_margin_m", "must be >= 0");
  region.clear();
  const std::string region_text = c.read_string(s, "region", "");
  std::vector<double> v;
  try
  {
    v = common::parseNumberList(region_text, "polygon vertices");
  }
  catch (const std::exception& e)
  {
    requireValid(false, c, s, "region", e.what());
  }
  requireValid(v.empty() || (v.size() >= 6 && v.size() % 2 == 0), c, s, "region",
               "need x y pairs of at least 3 polygon vertices, or nothing");
  for (std::size_t i = 0; i + 1 < v.size(); i += 2) region.emplace_back(v[i], v[i + 1]);
  requireValid(z_max_m > z_min_m, c, s, "z_max_m", "need z_max_m > z_min_m");
  requireValid(th_free >= 0 && th_free <= 255, c, s, "th_free", "need 0 <= th_free <= 255");
  requireValid(th_occ > th_free && th_occ <= 255, c, s, "th_occ", "need th_free < th_occ <= 255");
  requireValid(margin_m >= 0, c, s, "margin_m", "must be >= 0");
}

void ProjectionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                        const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(z_max_m, c, s);
  c.write(s, "obstacle_z_max_m", common::numberOrWord(obstacle_z_max_m, "auto", kAuto));
  MRPT_SAVE_CONFIG_VAR(auto_obstacle_z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(th_free, c, s);
  MRPT_SAVE_CONFIG_VAR(th_occ, c, s);
  MRPT_SAVE_CONFIG_VAR(margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(swept_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(swept_footprint, c, s);
  MRPT_SAVE_CONFIG_VAR(swept_footprint_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(incremental, c, s);
  std::string region_text;
  for (const auto& q : region) region_text += mrpt::format("%s%.4f %.4f", region_text.empty() ? "" : " ", q.x(), q.y());
  c.write(s, "region", region_text);
}

GroundGrid projectToGround(const octomap::OcTree& V, const mrpt::poses::CPose2D& robot,
                           const ProjectionParams& p, const SweptPath& swept,
                           ProjectionCache* cache)
{
  const double res = V.getResolution();
  octomap::OcTreeKey robot_key;
  ASSERTMSG_(V.coordToKeyChecked(octomap::point3d(robot.x(), robot.y(), 0.0), robot_key),
             "projectToGround: the robot lies outside the OcTree's addressable volume");
  // Voxels whose centre z = (k - k0 + 0.5) res lies in [z_min, z_max].
  const int k0 = V.coordToKey(0.0);
  const int kz_lo = k0 + static_cast<int>(std::ceil(p.z_min_m / res - 0.5 - 1e-9));
  // The key of the highest voxel whose centre lies at or below z.
  const auto topKey = [&](double z)
  { return k0 + static_cast<int>(std::floor(z / res - 0.5 + 1e-9)); };
  const int kz_hi = topKey(p.z_max_m);
  ASSERTMSG_(
      kz_hi >= kz_lo && kz_hi - kz_lo < 65535,
      mrpt::format("projectToGround: no voxel centre lies in [z_min_m, z_max_m] = [%g, %g] at "
                   "resolution %g",
                   p.z_min_m, p.z_max_m, res));
  KeyBox box = detail::gridKeyBox(V, robot_key, p.margin_m);
  box.lo[2] = kz_lo;
  box.hi[2] = kz_hi + 1;

  GroundGrid G;
  const GroundState unknown = GroundState::Unknown;
  // Cell (cx, cy) is exactly the voxel column with keys (box.lo + (cx, cy)).
  G.state.setSize((box.lo[0] - k0) * res, (box.hi[0] - k0) * res, (box.lo[1] - k0) * res,
                  (box.hi[1] - k0) * res, res, &unknown);
  ASSERT_EQUAL_(G.state.getSizeX(), static_cast<std::size_t>(box.hi[0] - box.lo[0]));
  ASSERT_EQUAL_(G.state.getSizeY(), static_cast<std::size_t>(box.hi[1] - box.lo[1]));
  G.robot = {robot_key[0] - box.lo[0], robot_key[1] - box.lo[1]};

  // Only the occupied voxels of the band above [z_max, obstacle_z_max] count:
  // its free / unknown voxels count for nothing.
  const int above_hi = std::max(kz_hi, topKey(p.obstacle_z_max_m)) + 1;
  ColumnTally local;
  const ColumnTally& tally =
      detail::tallyColumns(V, box, above_hi, p.th_free / 255.0, p.th_occ / 255.0,
                   cache && p.incremental ? cache->s_.get() : nullptr, local);
  floodFill(tally, kz_hi - kz_lo + 1, outsideMask(G, p.region),
            sweptMask(G, swept, p), G);
  return G;
}

bool lowObstacleStamps(const GroundGrid& g, const Cell& c, const Cell& robot, bool low_on_unknown)
{
  const GroundState was = *g.state.cellByIndex(c.cx, c.cy);
  if (was != GroundState::Free && !(was == GroundState::Unknown && low_on_unknown)) return false;
  const std::size_t nx = g.state.getSizeX();
  for (int dy = -1; dy <= 1; dy++)
    for (int dx = -1; dx <= 1; dx++)
    {
      const int x = c.cx + dx, y = c.cy + dy;
      if (x == robot.cx && y == robot.cy) return false;
      if (!inGrid(g.state, x, y) || *g.state.cellByIndex(x, y) != GroundState::Occupied) continue;
      const bool low_stamp =
          !g.low_was.empty() && g.low_was[static_cast<std::size_t>(y) * nx + x] != 0;
      if (!low_stamp) return false;
    }
  return true;
}

void stampObstacles(GroundGrid& g, const std::vector<Eigen::Vector2d>& sensed,
                    const std::vector<Eigen::Vector2d>& low, bool low_on_unknown)
{
  std::vector<Cell> low_cells;  // judged on V's columns alone, stamped after the sensed points
  for (const Eigen::Vector2d& q : low)
  {
    Cell c;
    if (cellOf(g.state, q, c) && lowObstacleStamps(g, c, g.robot, low_on_unknown))
      low_cells.push_back(c);
  }
  for (const Eigen::Vector2d& q : sensed)
  {
    Cell c;
    if (!cellOf(g.state, q, c) || (c.cx == g.robot.cx && c.cy == g.robot.cy)) continue;
    *g.state.cellByIndex(c.cx, c.cy) = GroundState::Occupied;
  }
  if (!low_cells.empty())
  {
    const std::size_t nx = g.state.getSizeX();
    g.low_was.assign(g.state.data().size(), 0);
    for (const Cell& c : low_cells)
    {
      GroundState* cell = g.state.cellByIndex(c.cx, c.cy);
      if (*cell == GroundState::Occupied) continue;  // a sensed point there
      g.low_was[static_cast<std::size_t>(c.cy) * nx + c.cx] = *cell == GroundState::Free ? 1 : 2;
      *cell = GroundState::Occupied;
    }
  }
}

}  // namespace voxplore::exploration
