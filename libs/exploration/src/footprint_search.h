/* voxplore — the A* over (cell, yaw bin) for the robot's rectangle and its
 * heuristic (issue 13). Internal to libs/exploration (footprint_search.cpp,
 * footprint_path.cpp). */
#pragma once

#include <voxplore/exploration/footprint.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace voxplore::exploration::detail
{
inline constexpr uint8_t kUnseen = 0xff, kClosedBit = 0x80;
inline constexpr uint8_t kTurnUp = 8, kTurnDown = 9;  // to bin + 1 / bin - 1

/// Per-state search data, allocated per touched cell (a block of `bins`):
/// the search touches a corridor round the path, not the grid's
/// cells x bins states (9.6 M on a 500 m^2 map, 48 MB cleared per call).
struct Node
{
  float g = std::numeric_limits<float>::infinity();
  uint8_t how = kUnseen;  ///< move towards the goal (0-7 translation, kTurnUp/Down) | kClosedBit
  int32_t pos = -1;       ///< where the state is in the open list, -1 when not there
};

/// The search over states s = cell * bins + bin. It runs backwards, from the
/// goal cell's bins to the robot's state, guided by the cost from the start
/// (footprintCostFromStart, one per FootprintSpace): every candidate goal of
/// a planning step shares that heuristic.
struct SE2Search
{
  const CollisionSpace& cs;
  const FootprintSpace& fs;
  const PathParams& p;
  int nx = 0, ny = 0, bins = 0;
  double res = 0, turn_cost = 0;
  std::vector<int32_t> block;  ///< per cell: its block in `nodes`, or -1
  std::vector<Node> nodes;

  SE2Search(const CollisionSpace& space, const FootprintSpace& fsp, const PathParams& params)
      : cs(space), fs(fsp), p(params)
  {
    nx = static_cast<int>(cs.state.getSizeX());
    ny = static_cast<int>(cs.state.getSizeY());
    bins = fs.bins;
    res = cs.state.getResolution();
    // A turn by one bin costs the arc of half the circumradius.
    turn_cost = fs.binWidth() * 0.5 * 0.5 * std::hypot(fs.length_m, fs.width_m);
    takeScratch();
    forget();
  }
  ~SE2Search() { giveScratch(); }
  SE2Search(const SE2Search&) = delete;
  SE2Search& operator=(const SE2Search&) = delete;

  /// `block` and `nodes` keep their memory from the last search on this
  /// thread: a fresh 1 MB block per path faulted its pages in (a tenth of
  /// the path's time on b10, perf, twenty-seventh session).
  void takeScratch();
  void giveScratch();

  /// No state touched yet (before a search, or before searching again).
  void forget()
  {
    block.assign(static_cast<std::size_t>(nx) * ny, -1);
    nodes.clear();
  }

  /// The index of state s's Node in `nodes` (a new block for a new cell).
  std::size_t nodeIndex(std::size_t s)
  {
    const std::size_t cell = s / bins;
    if (block[cell] < 0)
    {
      block[cell] = static_cast<int32_t>(nodes.size() / bins);
      nodes.resize(nodes.size() + bins);
    }
    return static_cast<std::size_t>(block[cell]) * bins + s % bins;
  }
  Node& node(std::size_t s) { return nodes[nodeIndex(s)]; }

  double clearance(std::size_t cell) const
  {
    return cs.clearance(cell);
  }

  double factor(std::size_t cell) const { return p.costFactor(clearance(cell)); }

  /// Turn at clear states of the escape that are not clear_turn too (what
  /// the escape did). Off for the first search: those turns keep less than
  /// the turn margin, and planning them whenever they shorten a path took
  /// the omniRob into turns the guard held (b5, b6 nbv: 0.949 / 0.967 ->
  /// 0.918 / 0.838); on only when the search without them finds nothing.
  bool escape_turns = false;

  bool allowed(std::size_t cell, int bin) const { return (fs.allowed(cell) >> bin) & 1u; }
  /// The bins this search may turn between at `cell`.
  YawMask turnMask(std::size_t cell) const
  {
    if (escape_turns) return fs.turnable(cell);
    return fs.clear_turn.data()[cell] | (fs.escape.data()[cell] & ~fs.clear.data()[cell]);
  }
  bool turnable(std::size_t cell, int bin) const { return (turnMask(cell) >> bin) & 1u; }
  /// Translations outside clear_turn (closer than the turn margin) cost double.
  double comfort(std::size_t cell, int bin) const
  {
    return ((fs.clear_turn.data()[cell] >> bin) & 1u) ? 1.0 : 2.0;
  }

  /// The forward moves: translation k (0-7) from cell (cx, cy) in `bin`
  /// into cell j: j allows the bin and, diagonally, both cells beside it do.
  bool mayTranslate(int cx, int cy, int k, int bin) const;

  /// State indices start..goal cell (in a bin of goal_bins); empty when not
  /// reached. `from_start`: a lower bound of the cost from the start to each
  /// cell (+infinity where the start cannot get).
  std::vector<std::size_t> run(std::size_t start_cell, int start_bin, std::size_t goal_cell,
                               const std::vector<float>& from_start,
                               YawMask goal_bins = ~YawMask(0));

  Eigen::Vector2d center(std::size_t cell) const
  {
    return cellCenter(cs.state, Cell{static_cast<int>(cell % nx), static_cast<int>(cell / nx)});
  }

  /// Does `pred` hold at the cell of every sample (res/2 apart) of a-b? False
  /// when a sample lies off the grid.
  template <typename Pred>
  bool everySample(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Pred pred) const
  {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * res))));
    for (int k = 0; k <= n; ++k)
    {
      Cell c;
      if (!cellOf(cs.state, a + (b - a) * (static_cast<double>(k) / n), c)) return false;
      if (!pred(static_cast<std::size_t>(c.cx) + static_cast<std::size_t>(c.cy) * nx)) return false;
    }
    return true;
  }

  /// Every sample of a-b lies in a cell that allows `bin`.
  bool segmentAllowed(const Eigen::Vector2d& a, const Eigen::Vector2d& b, int bin) const
  {
    return everySample(a, b, [&](std::size_t i) { return allowed(i, bin); });
  }

  /// Does the planner's circle not fit somewhere on a-b (or a-b leave the grid)?
  bool narrowSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const
  {
    return !everySample(a, b,
                        [&](std::size_t i)
                        {
                          return cs.clearance(i) > cs.radius_m;
                        });
  }
};

/// footprintCostFromStart from the cell `start` (not necessarily fs.robot's).
std::vector<float> costFromCell(const CollisionSpace& cs, const FootprintSpace& fs,
                                const PathParams& p, const Cell& start);

}  // namespace voxplore::exploration::detail
