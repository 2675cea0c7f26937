/* voxplore — A* over (cell, yaw bin) for the robot's rectangle (issue 13):
 * the thesis' clearance-keeping path (4.5.5) with the yaw to hold. */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/footprint.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <tuple>
#include <vector>

namespace voxplore::exploration
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kSqrt2 = 1.4142135623730951;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
constexpr uint8_t kUnseen = 0xff, kClosedBit = 0x80;
constexpr uint8_t kTurnUp = 8, kTurnDown = 9;  // to bin + 1 / bin - 1
constexpr double kMaxTurnPerWaypoint = kPi * 4 / 9;  // a planned turn is cut into pieces of at most 80 deg (the driver turns the short way)

/// Per-state search data, allocated per touched cell (a block of `bins`):
/// the search touches a corridor round the path, not the grid's
/// cells x bins states (9.6 M on a 500 m^2 map, 48 MB cleared per call).
struct Node
{
  float g = std::numeric_limits<float>::infinity();
  uint8_t how = kUnseen;  ///< move towards the goal (0-7 translation, kTurnUp/Down) | kClosedBit
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
    forget();
  }

  /// No state touched yet (before a search, or before searching again).
  void forget()
  {
    block.assign(static_cast<std::size_t>(nx) * ny, -1);
    nodes.clear();
  }

  Node& node(std::size_t s)
  {
    const std::size_t cell = s / bins;
    if (block[cell] < 0)
    {
      block[cell] = static_cast<int32_t>(nodes.size() / bins);
      nodes.resize(nodes.size() + bins);
    }
    return nodes[static_cast<std::size_t>(block[cell]) * bins + s % bins];
  }

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
  bool mayTranslate(int cx, int cy, int k, int bin) const
  {
    const int x = cx + kDx[k], y = cy + kDy[k];
    if (x < 0 || y < 0 || x >= nx || y >= ny) return false;
    if (!allowed(static_cast<std::size_t>(x + y * nx), bin)) return false;
    return k < 4 || (allowed(static_cast<std::size_t>(x + cy * nx), bin) &&
                     allowed(static_cast<std::size_t>(cx + y * nx), bin));
  }

  /// State indices start..goal cell (any bin); empty when not reached.
  /// `from_start`: a lower bound of the cost from the start to each cell
  /// (+infinity where the start cannot get).
  std::vector<std::size_t> run(std::size_t start_cell, int start_bin, std::size_t goal_cell,
                               const std::vector<float>& from_start)
  {
    // (f, -g, state): among equal f the deeper state first.
    using Item = std::tuple<double, double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    const std::size_t s0 = start_cell * bins + start_bin;
    const YawMask seeds = fs.allowed(goal_cell) & fs.reach.data()[goal_cell];
    for (int b = 0; b < bins; ++b)
    {
      if (!((seeds >> b) & 1u)) continue;
      const std::size_t t = goal_cell * bins + b;
      node(t) = Node{0.0f, 0x7f};  // the goal: no move
      open.push({p.footprint_heuristic_weight * from_start[goal_cell], 0.0, t});
    }
    bool found = false;
    while (!open.empty())
    {
      const std::size_t u = std::get<2>(open.top());
      open.pop();
      Node& nu = node(u);
      if (nu.how & kClosedBit) continue;
      nu.how |= kClosedBit;
      if (u == s0)
      {
        found = true;
        break;
      }
      const double gu = nu.g;
      const std::size_t cell = u / bins;
      const int bin = static_cast<int>(u % bins);
      const int cx = static_cast<int>(cell % nx), cy = static_cast<int>(cell / nx);
      // Predecessor s reaches u by `move` at forward cost `cost`.
      const auto relax = [&](std::size_t s, std::size_t s_cell, double cost, uint8_t move)
      {
        const float h = from_start[s_cell];
        if (!std::isfinite(h)) return;
        Node& ns = node(s);
        if (ns.how != kUnseen && (ns.how & kClosedBit)) return;
        const double ng = gu + cost;
        if (ng >= ns.g) return;
        ns.g = static_cast<float>(ng);
        ns.how = move;
        open.push({ng + p.footprint_heuristic_weight * h, -ng, s});
      };
      // Translations into u: from the cell one step back, in the same bin.
      const double into = res * factor(cell) * comfort(cell, bin);
      for (int k = 0; k < 8; ++k)
      {
        const int x = cx - kDx[k], y = cy - kDy[k];
        if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
        const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
        const std::size_t s = j * bins + bin;
        if (s != s0 && !allowed(j, bin)) continue;
        if (!mayTranslate(x, y, k, bin)) continue;
        relax(s, j, (k < 4 ? 1.0 : kSqrt2) * into, static_cast<uint8_t>(k));
      }
      // Turns into u: from the next bin either way, both turnable here.
      if (!turnable(cell, bin)) continue;
      const int up = (bin + 1) % bins, down = (bin + bins - 1) % bins;
      // Forward kTurnUp goes bin-1 -> bin: its source is `down`.
      if (turnable(cell, down)) relax(cell * bins + down, cell, turn_cost, kTurnUp);
      if (turnable(cell, up)) relax(cell * bins + up, cell, turn_cost, kTurnDown);
    }
    std::vector<std::size_t> states;
    if (!found) return states;
    for (std::size_t s = s0;;)
    {
      states.push_back(s);
      const uint8_t m = node(s).how & ~kClosedBit;
      if (m == 0x7f) break;
      const std::size_t cell = s / bins;
      const int bin = static_cast<int>(s % bins);
      if (m == kTurnUp)
        s = cell * bins + (bin + 1) % bins;
      else if (m == kTurnDown)
        s = cell * bins + (bin + bins - 1) % bins;
      else
      {
        const int x = static_cast<int>(cell % nx) + kDx[m], y = static_cast<int>(cell / nx) + kDy[m];
        s = (static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx) * bins + bin;
      }
    }
    return states;
  }

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

/// Appends waypoints to `path`: from the last one to `to` holding `yaw`,
/// in pieces of at most max_m.
void appendTranslation(Path& path, const SE2Search& s, const Eigen::Vector2d& to, double yaw,
                       double max_m)
{
  const Eigen::Vector2d from = path.waypoints.back();
  const double len = (to - from).norm();
  if (len < 1e-9) return;
  const bool narrow = s.narrowSegment(from, to);
  const int pieces = std::max(1, static_cast<int>(std::ceil(len / max_m - 1e-9)));
  for (int k = 1; k <= pieces; ++k)
  {
    path.waypoints.push_back(from + (to - from) * (static_cast<double>(k) / pieces));
    path.yaws.push_back(yaw);
    path.narrow.push_back(narrow ? 1 : 0);
    path.length_m += len / pieces;
  }
}

/// Appends a turn in place from path.yaws.back() to `yaw` (unwrapped: the
/// planned way round), in pieces of at most kMaxTurnPerWaypoint.
void appendTurn(Path& path, const SE2Search& s, double yaw)
{
  const double from = path.yaws.back();
  const int pieces = static_cast<int>(std::ceil(std::abs(yaw - from) / kMaxTurnPerWaypoint - 1e-9));
  const Eigen::Vector2d at = path.waypoints.back();
  const bool narrow = s.narrowSegment(at, at);
  for (int k = 1; k <= pieces; ++k)
  {
    path.waypoints.push_back(at);
    path.yaws.push_back(from + (yaw - from) * (static_cast<double>(k) / pieces));
    path.narrow.push_back(narrow ? 1 : 0);
  }
}

/// The half turn of yaw `y` nearest `ref`.
double nearestRepresentative(double y, double ref)
{
  return ref + mrpt::math::wrapToPi(2.0 * (y - ref)) / 2.0;
}
}  // namespace

namespace
{
/// footprintCostFromStart from the cell `start` (not necessarily fs.robot's).
std::vector<float> costFromCell(const CollisionSpace& cs, const FootprintSpace& fs,
                                const PathParams& p, const Cell& start)
{
  // Dijkstra over the cells holding a reached or escape state, from
  // `start`; a step costs its length times the clearance factor of the
  // cell entered (what the SE(2) translation into it costs at least; turns
  // cost more than nothing). Diagonals skip the corner test: a relaxation.
  const int nx = static_cast<int>(cs.state.getSizeX()), ny = static_cast<int>(cs.state.getSizeY());
  const double res = cs.state.getResolution();
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  std::vector<float> d(n, std::numeric_limits<float>::infinity());
  const auto& reach = fs.reach.data();
  const auto& escape = fs.escape.data();
  std::vector<float> step_cost(n, 0.0f);
  const auto& clear_turn = fs.clear_turn.data();
  for (std::size_t i = 0; i < n; ++i)
    if (reach[i] | escape[i])
      step_cost[i] = static_cast<float>(
          res * p.costFactor(cs.clearance(i)) *
          // SE2Search::comfort: double where no reached bin keeps the turn margin.
          ((clear_turn[i] & (reach[i] | escape[i])) ? 1.0 : 2.0));
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const int r0 = start.cx + start.cy * nx;
  if (start.cx < 0 || start.cy < 0 || start.cx >= nx || start.cy >= ny) return d;
  d[static_cast<std::size_t>(r0)] = 0;
  open.push({0.0f, r0});
  while (!open.empty())
  {
    const auto [du, u] = open.top();
    open.pop();
    if (du > d[static_cast<std::size_t>(u)]) continue;
    const int cx = u % nx, cy = u / nx;
    for (int k = 0; k < 8; ++k)
    {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
      const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
      if (!(reach[j] | escape[j])) continue;
      const float nd = du + static_cast<float>(k < 4 ? 1.0 : kSqrt2) * step_cost[j];
      if (nd >= d[j]) continue;
      d[j] = nd;
      open.push({nd, static_cast<int>(j)});
    }
  }
  // Float sums may round a bound above a double-precision path cost by an
  // ulp: shave it off (a bound, not a distance).
  for (float& v : d)
    if (std::isfinite(v)) v *= 0.9999f;
  return d;
}
}  // namespace

std::vector<float> footprintCostFromStart(
    const CollisionSpace& cs, const FootprintSpace& fs, const PathParams& p)
{
  return costFromCell(cs, fs, p, fs.robot);
}

std::optional<Path> planFootprintPath(
    const CollisionSpace& cs, const FootprintSpace& fs, const mrpt::poses::CPose2D& start,
    const Eigen::Vector2d& goal, double goal_yaw, const PathParams& p,
    const std::vector<float>* cost_from_start)
{
  ASSERTMSG_(p.max_segment_m > 0, "planFootprintPath: max_segment_m must be > 0");
  Cell sc, tc;
  const Eigen::Vector2d start_xy(start.x(), start.y());
  if (!cellOf(cs.state, start_xy, sc) || !cellOf(cs.state, goal, tc)) return std::nullopt;
  SE2Search search(cs, fs, p);
  const std::size_t s_cell = static_cast<std::size_t>(sc.cx) + static_cast<std::size_t>(sc.cy) * search.nx;
  const std::size_t t_cell = static_cast<std::size_t>(tc.cx) + static_cast<std::size_t>(tc.cy) * search.nx;
  if (!(fs.reach.data()[t_cell] & fs.clear.data()[t_cell])) return std::nullopt;
  // The robot's own state is where the search starts even when the map
  // does not allow it (FootprintSpace's escape starts there too).
  const int s_bin = fs.binOf(start.phi());
  std::vector<float> own;
  const bool fits = cost_from_start && cost_from_start->size() == search.block.size() &&
                    s_cell == static_cast<std::size_t>(fs.robot.cx) +
                                  static_cast<std::size_t>(fs.robot.cy) * search.nx;
  if (!fits)
  {
    // The bound is from fs.robot: for another start, Dijkstra from there.
    own = costFromCell(cs, fs, p, sc);
  }
  const std::vector<float>& from_start = fits ? *cost_from_start : own;
  std::vector<std::size_t> states = search.run(s_cell, s_bin, t_cell, from_start);
  if (states.empty())
  {
    // The reach holds the goal (tested above) through the escape's turns:
    // search again with them (and turn at the goal by them too, below).
    search.escape_turns = true;
    search.forget();
    states = search.run(s_cell, s_bin, t_cell, from_start);
  }
  if (states.empty()) return std::nullopt;

  // Runs of one bin (split at the turns), shortcut by line of sight.
  Path path;
  for (const std::size_t s : states) path.cells_path.push_back(search.center(s / fs.bins));
  path.waypoints.push_back(start_xy);
  // Unwrapped yaw: the bin's yaw nearest the robot's.
  double yaw = nearestRepresentative(fs.binYaw(s_bin), start.phi());
  path.yaws.push_back(yaw);
  path.narrow.push_back(0);
  std::size_t i = 0;
  while (i < states.size())
  {
    const int bin = static_cast<int>(states[i] % fs.bins);
    std::size_t j = i;
    while (j + 1 < states.size() && static_cast<int>(states[j + 1] % fs.bins) == bin) ++j;
    // States i..j: translations in `bin`. Their points; the exact goal ends the last run.
    std::vector<Eigen::Vector2d> pts;
    for (std::size_t k = i; k <= j; ++k) pts.push_back(search.center(states[k] / fs.bins));
    if (j + 1 == states.size()) pts.back() = goal;
    if (i == 0) pts.front() = start_xy;
    for (std::size_t a = 0; a + 1 < pts.size();)
    {
      std::size_t b = pts.size() - 1;
      while (b > a + 1 && !search.segmentAllowed(pts[a], pts[b], bin)) --b;
      appendTranslation(path, search, pts[b], yaw, p.max_segment_m);
      a = b;
    }
    if (j + 1 < states.size())
    {
      // A turn in place to the next run's bin: follow the planned direction.
      std::size_t k = j + 1;
      double turn = 0;
      int b = bin;
      while (k < states.size() && states[k] / fs.bins == states[j] / fs.bins)
      {
        const int nb = static_cast<int>(states[k] % fs.bins);
        turn += nb == (b + 1) % fs.bins ? fs.binWidth() : -fs.binWidth();
        b = nb;
        ++k;
      }
      yaw += turn;
      appendTurn(path, search, yaw);
      i = k - 1;  // the state after the turn starts the next run
      if (k == states.size()) break;
      continue;
    }
    break;
  }

  // The final yaw: the goal's bin when turning in place reaches it, else the
  // reachable bin nearest it; turned to the planned way round.
  const std::size_t last = states.back();
  const int arrive = static_cast<int>(last % fs.bins);
  const YawMask at_goal =
      (YawMask(1) << arrive) | fs.turnClosure(YawMask(1) << arrive, search.turnMask(t_cell));
  const int want = fs.binOf(goal_yaw);
  int best_bin = arrive, best_steps = 0, best_dist = fs.bins;
  for (const int dir : {+1, -1})
    for (int steps = 0, b = arrive; steps < fs.bins; ++steps, b = (b + dir + fs.bins) % fs.bins)
    {
      if (!((at_goal >> b) & 1u)) break;
      const int d = std::min(std::abs(b - want), fs.bins - std::abs(b - want));
      if (d < best_dist || (d == best_dist && steps < std::abs(best_steps)))
      {
        best_dist = d;
        best_bin = b;
        best_steps = dir * steps;
      }
    }
  yaw += best_steps * fs.binWidth();
  appendTurn(path, search, yaw);
  // Within the goal's bin any yaw is free: end at goal_yaw (or its half turn) then.
  path.final_yaw = best_bin == want ? nearestRepresentative(goal_yaw, yaw) : yaw;
  if (path.waypoints.size() == 1)
  {
    // Already there: one waypoint at the goal.
    path.waypoints.push_back(goal);
    path.yaws.push_back(yaw);
    path.narrow.push_back(search.narrowSegment(start_xy, goal) ? 1 : 0);
  }
  double m = std::numeric_limits<double>::infinity();
  for (const auto& c : path.cells_path)
  {
    Cell cc;
    if (cellOf(cs.state, c, cc))
      m = std::min(m, search.clearance(static_cast<std::size_t>(cc.cx) +
                                       static_cast<std::size_t>(cc.cy) * search.nx));
  }
  path.min_clearance_m = m;
  return path;
}

}  // namespace voxplore::exploration
