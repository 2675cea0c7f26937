/* voxplore — clearance-keeping path generation on the collision space
 * (thesis 4.5.5): A* with a clearance cost, line-of-sight shortcutting,
 * segments for stop-and-scan. */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/path.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

namespace voxplore::exploration
{
namespace
{
constexpr double kSqrt2 = 1.4142135623730951;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
using OpenItem = std::pair<double, int>;  ///< (f = g + h, cell index)
using OpenSet = std::priority_queue<OpenItem, std::vector<OpenItem>, std::greater<>>;

/// A* over the collision space. Free cells expand into Free cells only. A
/// start that is not Free "escapes": it and the cells reached from it
/// through non-Free cells may enter any non-Occupied cell, until the first
/// Free cell is closed; from then on only Free cells are entered.
struct AStar
{
  const CollisionSpace& cs;
  const PathParams& p;
  int nx = 0, ny = 0;
  double res = 0;
  std::vector<double> g;         ///< cost from the start; < 0: unseen
  std::vector<int> parent;
  std::vector<uint8_t> escape, closed;
  bool free_closed = false;

  AStar(const CollisionSpace& space, const PathParams& params) : cs(space), p(params)
  {
    nx = static_cast<int>(cs.state.getSizeX());
    ny = static_cast<int>(cs.state.getSizeY());
    res = cs.state.getResolution();
    const std::size_t n = cs.state.data().size();
    g.assign(n, -1.0);
    parent.assign(n, -1);
    escape.assign(n, 0);
    closed.assign(n, 0);
  }

  SpaceState state(int i) const { return cs.state.data()[i]; }

  bool mayEnter(int from, int to) const
  {
    if (escape[from] && !free_closed) return state(to) != SpaceState::Occupied;
    return state(to) == SpaceState::Free;
  }

  /// min(clearance_occ, clearance_unknown) at cell i [m].
  float clearance(int i) const { return cs.clearance(static_cast<std::size_t>(i)); }

  double factor(int i) const { return p.costFactor(clearance(i)); }

  /// Admissible heuristic: straight-line metres (every factor is >= 1).
  double heuristic(int i, int goal) const
  {
    return res * std::hypot(i % nx - goal % nx, i / nx - goal / nx);
  }

  void expand(int i, int goal, OpenSet& open)
  {
    const int cx = i % nx, cy = i / nx;
    for (int k = 0; k < 8; ++k)
    {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
      const int j = x + y * nx;
      if (closed[j] || !mayEnter(i, j)) continue;
      if (k >= 4 && (!mayEnter(i, x + cy * nx) || !mayEnter(i, cx + y * nx)))
        continue;  // no corner cutting
      const double ng = g[i] + (k < 4 ? 1.0 : kSqrt2) * res * factor(j);
      if (g[j] >= 0 && g[j] <= ng) continue;
      g[j] = ng;
      parent[j] = i;
      escape[j] = escape[i] && !free_closed && state(j) != SpaceState::Free;
      open.push({ng + heuristic(j, goal), j});
    }
  }

  /// Cell indices start..goal; empty when the goal cannot be reached.
  std::vector<int> run(int start, int goal)
  {
    OpenSet open;
    g[start] = 0;
    escape[start] = state(start) != SpaceState::Free;
    open.push({heuristic(start, goal), start});
    while (!open.empty())
    {
      const int i = open.top().second;
      open.pop();
      if (closed[i]) continue;
      closed[i] = 1;
      if (state(i) == SpaceState::Free) free_closed = true;
      if (i == goal) break;
      expand(i, goal, open);
    }
    std::vector<int> cells;
    if (!closed[goal]) return cells;
    for (int i = goal; i >= 0; i = parent[i]) cells.push_back(i);
    std::reverse(cells.begin(), cells.end());
    return cells;
  }
};

/// Straight segment a-b sampled every res/2: all samples in Free cells with
/// clearance >= min_clearance (any clearance when min_clearance is -inf).
bool segmentClear(const AStar& a, const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                  double min_clearance)
{
  const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / (0.5 * a.res))));
  for (int k = 0; k <= n; ++k)
  {
    Cell c;
    if (!cellOf(a.cs.state, from + (to - from) * (static_cast<double>(k) / n), c)) return false;
    const int i = c.cx + c.cy * a.nx;
    if (a.state(i) != SpaceState::Free || a.clearance(i) < min_clearance) return false;
  }
  return true;
}

/// Smallest clearance along a polyline sampled every res/2.
double polylineClearance(const AStar& a, const std::vector<Eigen::Vector2d>& pts)
{
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t s = 0; s + 1 < pts.size(); ++s)
  {
    const int n =
        std::max(1, static_cast<int>(std::ceil((pts[s + 1] - pts[s]).norm() / (0.5 * a.res))));
    for (int k = 0; k <= n; ++k)
    {
      Cell c;
      if (cellOf(a.cs.state, pts[s] + (pts[s + 1] - pts[s]) * (static_cast<double>(k) / n), c))
        m = std::min(m, static_cast<double>(a.clearance(c.cx + c.cy * a.nx)));
    }
  }
  return m;
}

/// Greedy shortcutting: from each kept point, jump to the farthest later point
/// whose segment stays clear. The escape prefix (non-Free cells) is kept as is.
std::vector<Eigen::Vector2d> shortcut(const AStar& a, const std::vector<Eigen::Vector2d>& pts,
                                      const std::vector<int>& cells)
{
  std::size_t first_free = 0;
  while (first_free < cells.size() && a.state(cells[first_free]) != SpaceState::Free) ++first_free;
  double min_c = std::numeric_limits<double>::infinity();
  for (std::size_t k = first_free; k < cells.size(); ++k)
    min_c = std::min(min_c, static_cast<double>(a.clearance(cells[k])));
  const double keep = min_c - a.p.shortcut_margin_m;

  std::vector<Eigen::Vector2d> out(pts.begin(), pts.begin() + std::min(first_free + 1, pts.size()));
  for (std::size_t i = first_free; i + 1 < pts.size();)
  {
    std::size_t j = pts.size() - 1;
    while (j > i + 1 && !segmentClear(a, pts[i], pts[j], keep)) --j;
    out.push_back(pts[j]);
    i = j;
  }
  return out;
}

/// Splits every segment longer than max_m into equal pieces.
std::vector<Eigen::Vector2d> splitSegments(const std::vector<Eigen::Vector2d>& pts, double max_m)
{
  std::vector<Eigen::Vector2d> out;
  if (pts.empty()) return out;
  out.push_back(pts.front());
  for (std::size_t s = 0; s + 1 < pts.size(); ++s)
  {
    const double len = (pts[s + 1] - pts[s]).norm();
    if (len < 1e-9) continue;  // start and goal in one spot
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / max_m - 1e-9)));
    for (int k = 1; k <= pieces; ++k)
      out.push_back(pts[s] + (pts[s + 1] - pts[s]) * (static_cast<double>(k) / pieces));
  }
  return out;
}
}  // namespace

double PathParams::costFactor(double clearance_m) const
{
  if (clearance_ref_m <= 0) return 1.0;
  const double short_by = std::max(0.0, clearance_ref_m - clearance_m);
  return 1.0 + clearance_weight * short_by / clearance_ref_m;
}

void PathParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(clearance_weight, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clearance_ref_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(shortcut_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_segment_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_heuristic_weight, double, c, s);
  turn_on_the_way_deg =
      common::readNumberOrWord(c, s, "turn_on_the_way_deg", turn_on_the_way_deg, "auto", -1.0);
  using common::requireValid;
  requireValid(clearance_weight >= 0, c, s, "clearance_weight", "must be >= 0");
  requireValid(clearance_ref_m > 0, c, s, "clearance_ref_m", "must be > 0");
  requireValid(shortcut_margin_m >= 0, c, s, "shortcut_margin_m", "must be >= 0");
  requireValid(max_segment_m > 0, c, s, "max_segment_m", "must be > 0");
  requireValid(footprint_heuristic_weight >= 1, c, s, "footprint_heuristic_weight", "must be >= 1");
  requireValid(turn_on_the_way_deg == -1.0 || (turn_on_the_way_deg >= 0 && turn_on_the_way_deg <= 180),
               c, s, "turn_on_the_way_deg", "must be auto or in [0, 180]");
}

void PathParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(clearance_weight, c, s);
  MRPT_SAVE_CONFIG_VAR(clearance_ref_m, c, s);
  MRPT_SAVE_CONFIG_VAR(shortcut_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_segment_m, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_heuristic_weight, c, s);
  c.write(s, "turn_on_the_way_deg", common::numberOrWord(turn_on_the_way_deg, "auto", -1.0));
}

std::optional<Path> planPath(const CollisionSpace& cs, const Eigen::Vector2d& start,
                             const Eigen::Vector2d& goal, const PathParams& p)
{
  ASSERTMSG_(p.max_segment_m > 0, "planPath: max_segment_m must be > 0");
  Cell s, t;
  if (!cellOf(cs.state, start, s) || !cellOf(cs.state, goal, t)) return std::nullopt;
  AStar astar(cs, p);
  const int goal_i = t.cx + t.cy * astar.nx;
  if (astar.state(goal_i) != SpaceState::Free) return std::nullopt;
  const std::vector<int> cells = astar.run(s.cx + s.cy * astar.nx, goal_i);
  if (cells.empty()) return std::nullopt;

  Path path;
  for (const int i : cells)
    path.cells_path.push_back(cellCenter(cs.state, Cell{i % astar.nx, i / astar.nx}));
  // The exact start and goal replace their cell centres.
  std::vector<Eigen::Vector2d> pts = path.cells_path;
  pts.front() = start;
  if (pts.size() == 1)
    pts.push_back(goal);
  else
    pts.back() = goal;
  std::vector<int> pt_cells = cells;
  if (pt_cells.size() < pts.size()) pt_cells.push_back(cells.back());

  path.waypoints = splitSegments(shortcut(astar, pts, pt_cells), p.max_segment_m);
  for (std::size_t k = 0; k + 1 < path.waypoints.size(); ++k)
    path.length_m += (path.waypoints[k + 1] - path.waypoints[k]).norm();
  path.min_clearance_m = polylineClearance(astar, path.waypoints);
  return path;
}

}  // namespace voxplore::exploration
