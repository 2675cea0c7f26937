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
constexpr uint8_t kTurnUp = 8, kTurnDown = 9;  // came from bin - 1 / bin + 1
constexpr double kMaxTurnPerWaypoint = kPi * 4 / 9;  // a planned turn is cut into pieces of at most 80 deg (the driver turns the short way)

/// The search over states s = cell * bins + bin.
struct SE2Search
{
  const CollisionSpace& cs;
  const FootprintSpace& fs;
  const PathParams& p;
  int nx = 0, ny = 0, bins = 0;
  double res = 0, turn_cost = 0;
  std::vector<float> g;
  std::vector<uint8_t> how;  ///< move that reached the state (0-7 translation, kTurnUp/Down) | kClosedBit

  SE2Search(const CollisionSpace& space, const FootprintSpace& fsp, const PathParams& params)
      : cs(space), fs(fsp), p(params)
  {
    nx = static_cast<int>(cs.state.getSizeX());
    ny = static_cast<int>(cs.state.getSizeY());
    bins = fs.bins;
    res = cs.state.getResolution();
    // A turn by one bin costs the arc of half the circumradius.
    turn_cost = fs.binWidth() * 0.5 * 0.5 * std::hypot(fs.length_m, fs.width_m);
    const std::size_t n = static_cast<std::size_t>(nx) * ny * bins;
    g.assign(n, std::numeric_limits<float>::infinity());
    how.assign(n, kUnseen);
  }

  double clearance(std::size_t cell) const
  {
    return std::min(cs.clearance_occ_m.data()[cell], cs.clearance_unknown_m.data()[cell]);
  }

  double factor(std::size_t cell) const { return p.costFactor(clearance(cell)); }

  bool allowed(std::size_t cell, int bin) const { return (fs.allowed(cell) >> bin) & 1u; }
  bool turnable(std::size_t cell, int bin) const { return (fs.turnable(cell) >> bin) & 1u; }
  /// Translations outside clear_turn (closer than the turn margin) cost double.
  double comfort(std::size_t cell, int bin) const
  {
    return ((fs.clear_turn.data()[cell] >> bin) & 1u) ? 1.0 : 2.0;
  }

  /// State indices start..goal cell (any bin); empty when not reached.
  std::vector<std::size_t> run(std::size_t start_cell, int start_bin, std::size_t goal_cell)
  {
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    const int gx = static_cast<int>(goal_cell % nx), gy = static_cast<int>(goal_cell / nx);
    const auto h = [&](std::size_t cell)
    { return res * std::hypot(static_cast<int>(cell % nx) - gx, static_cast<int>(cell / nx) - gy); };
    const std::size_t s0 = start_cell * bins + start_bin;
    g[s0] = 0;
    how[s0] = 0x7f;  // the start: no move
    open.push({h(start_cell), s0});
    std::size_t found = std::numeric_limits<std::size_t>::max();
    while (!open.empty())
    {
      const std::size_t s = open.top().second;
      open.pop();
      if (how[s] & kClosedBit) continue;
      how[s] |= kClosedBit;
      const std::size_t cell = s / bins;
      const int bin = static_cast<int>(s % bins);
      if (cell == goal_cell)
      {
        found = s;
        break;
      }
      const int cx = static_cast<int>(cell % nx), cy = static_cast<int>(cell / nx);
      const auto relax = [&](std::size_t t, double cost, uint8_t move, std::size_t t_cell)
      {
        if (how[t] != kUnseen && (how[t] & kClosedBit)) return;
        const double ng = g[s] + cost;
        if (ng >= g[t]) return;
        g[t] = static_cast<float>(ng);
        how[t] = move;
        open.push({ng + h(t_cell), t});
      };
      for (int k = 0; k < 8; ++k)
      {
        const int x = cx + kDx[k], y = cy + kDy[k];
        if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
        const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
        if (!allowed(j, bin)) continue;
        if (k >= 4 && (!allowed(static_cast<std::size_t>(x + cy * nx), bin) ||
                       !allowed(static_cast<std::size_t>(cx + y * nx), bin)))
          continue;
        relax(j * bins + bin, (k < 4 ? 1.0 : kSqrt2) * res * factor(j) * comfort(j, bin),
              static_cast<uint8_t>(k), j);
      }
      if (!turnable(cell, bin)) continue;
      const int up = (bin + 1) % bins, down = (bin + bins - 1) % bins;
      if (turnable(cell, up)) relax(cell * bins + up, turn_cost, kTurnUp, cell);
      if (turnable(cell, down)) relax(cell * bins + down, turn_cost, kTurnDown, cell);
    }
    std::vector<std::size_t> states;
    if (found == std::numeric_limits<std::size_t>::max()) return states;
    for (std::size_t s = found;;)
    {
      states.push_back(s);
      const uint8_t m = how[s] & ~kClosedBit;
      if (m == 0x7f) break;
      const std::size_t cell = s / bins;
      const int bin = static_cast<int>(s % bins);
      if (m == kTurnUp)
        s = cell * bins + (bin + bins - 1) % bins;
      else if (m == kTurnDown)
        s = cell * bins + (bin + 1) % bins;
      else
      {
        const int x = static_cast<int>(cell % nx) - kDx[m], y = static_cast<int>(cell / nx) - kDy[m];
        s = (static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx) * bins + bin;
      }
    }
    std::reverse(states.begin(), states.end());
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
                          return cs.clearance_occ_m.data()[i] > cs.radius_m &&
                                 cs.clearance_unknown_m.data()[i] > cs.radius_m;
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

std::optional<Path> planFootprintPath(
    const CollisionSpace& cs, const FootprintSpace& fs, const mrpt::poses::CPose2D& start,
    const Eigen::Vector2d& goal, double goal_yaw, const PathParams& p)
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
  const std::vector<std::size_t> states = search.run(s_cell, s_bin, t_cell);
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
      (YawMask(1) << arrive) | fs.turnClosure(YawMask(1) << arrive, fs.turnable(t_cell));
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
