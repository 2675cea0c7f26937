/* voxplore — the robot's rectangle's path (issue 13): the SE(2) search's
 * states (footprint_search.h) turned into waypoints with the yaw to hold,
 * the thesis' clearance-keeping path (4.5.5). */
#include <mrpt/core/exceptions.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/footprint.h>

#include "footprint_search.h"
#include "footprint_turns.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace voxplore::exploration
{
using namespace detail;

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxTurnPerWaypoint = kPi * 4 / 9;  // a planned turn is cut into pieces of at most 80 deg (the driver turns the short way)

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
    path.turn_on_way.push_back(0);
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
    path.turn_on_way.push_back(0);
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
    const Eigen::Vector2d& goal, double goal_yaw, const PathParams& p,
    const std::vector<float>* cost_from_start, bool end_in_goal_bin)
{
  ASSERTMSG_(p.max_segment_m > 0, "planFootprintPath: max_segment_m must be > 0");
  Cell sc, tc;
  const Eigen::Vector2d start_xy(start.x(), start.y());
  if (!cellOf(cs.state, start_xy, sc) || !cellOf(cs.state, goal, tc)) return std::nullopt;
  {
    // The FootprintSpace's robot cell is the octomap key of the robot's
    // position (projectToGround), and cellOf may round a coordinate on a
    // cell border the other way: a start at that position starts there,
    // and shares the heuristic computed from it (else every candidate of the
    // step ran its own Dijkstra: 26 % of the path's time on b10).
    const Eigen::Vector2d rc = cellCenter(cs.state, fs.robot);
    const double half = 0.5 * cs.state.getResolution() + 1e-9;
    if (std::abs(start_xy.x() - rc.x()) <= half && std::abs(start_xy.y() - rc.y()) <= half)
      sc = fs.robot;
  }
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
  std::vector<std::size_t> states;
  if (end_in_goal_bin)
  {
    states = search.run(s_cell, s_bin, t_cell, from_start, YawMask(1) << fs.binOf(goal_yaw));
    if (states.empty()) search.forget();
  }
  if (states.empty()) states = search.run(s_cell, s_bin, t_cell, from_start);
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
  path.turn_on_way.push_back(0);
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
    path.turn_on_way.push_back(0);
  }
  if (p.turn_on_the_way_deg > 0 && path.waypoints.size() > 2)
    turnOnTheWay(path, search, fs, mrpt::DEG2RAD(p.turn_on_the_way_deg));
  if (p.turn_on_the_way_deg > 0) leadInTurns(path, search, fs);
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
