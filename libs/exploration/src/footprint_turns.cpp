/* voxplore — turns on the way (issue 15): turnOnTheWay() and leadInTurns()
 * (footprint_turns.h) and the public checks they rest on (footprint.h:
 * turnClearAlong, holdClearAlong, turnFirstSplit, nextTranslation,
 * makeLeadIn). Split from footprint_path.cpp. Our own: the SE(2) search
 * plans turns in place only. */
#include <mrpt/math/wrap2pi.h>

#include "footprint_turns.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace voxplore::exploration
{
using namespace detail;

namespace
{
constexpr double kPi = 3.14159265358979323846;

/// Samples a-b half a cell apart, k = 0..n: ok(k, n, i) at each (i: its
/// row-major cell of cs.state). False where a sample leaves the grid or ok
/// does not hold.
template <class Ok>
bool everySampleAlong(const CollisionSpace& cs, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      Ok ok)
{
  const auto nx = static_cast<std::size_t>(cs.state.getSizeX());
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * cs.state.getResolution()))));
  for (int k = 0; k <= n; ++k)
  {
    Cell c;
    if (!cellOf(cs.state, a + (b - a) * (static_cast<double>(k) / n), c)) return false;
    if (!ok(k, n, static_cast<std::size_t>(c.cx) + static_cast<std::size_t>(c.cy) * nx)) return false;
  }
  return true;
}

/// The pieces of a way a turn is made on next to its corner, longest first,
/// at most half the way [m]. A bin's turn over 0.1 m keeps the driver's full
/// speed (its turn rate cap, 0.8 max_w, allows 0.5 m/s for 5.6 deg over 8 cm).
constexpr double kShortTurns[] = {0.6, 0.3, 0.15, 0.1};

struct Split
{
  Eigen::Vector2d point;
  bool before = false;      ///< on the translation before the corner (else after it)
  bool turn_first = false;  ///< after it: turned from the corner to the split, held on from there
};

/// A turn in place from y0 to y1 at the corner `out`.waypoints.back()
/// between two footprint translations (the one before ends there, `next` is
/// the end of the one after) made in proportion on a part of one of them:
/// from a split point to `next` (holding y0 from the corner to it), or from
/// a split point of the translation before to the corner (holding y0 up to
/// it); the longest part turnClearAlong() holds, at quarters of the way.
/// Else on a short piece next to the corner (kShortTurns, longest first),
/// where the turn layer holds round the corner (the planner turned there)
/// but not a quarter of a long way off it (a door the way in starts from):
/// up to the corner, or from it and held on from there (turnFirstSplit).
/// Our own, as turnOnTheWay().
std::optional<Split> partialTurn(const CollisionSpace& cs, const FootprintSpace& fs, const Path& out,
                                 const Eigen::Vector2d& next, double y0, double y1)
{
  const std::size_t o = out.waypoints.size();
  const Eigen::Vector2d corner = out.waypoints.back();
  for (const double f : {0.25, 0.5, 0.75})
  {
    const Eigen::Vector2d s = corner + f * (next - corner);
    if (holdClearAlong(cs, fs, corner, s, y0) && turnClearAlong(cs, fs, s, next, y0, y1, true))
      return Split{s, false, false};
  }
  if (o >= 2 && !out.turn_on_way.back() && (corner - out.waypoints[o - 2]).norm() > 1e-9)
  {
    const Eigen::Vector2d prev = out.waypoints[o - 2];
    for (const double f : {0.25, 0.5, 0.75})
    {
      const Eigen::Vector2d s = prev + f * (corner - prev);
      if (turnClearAlong(cs, fs, s, corner, y0, y1, true)) return Split{s, true, false};
    }
    const double in = (corner - prev).norm();
    for (const double d : kShortTurns)
    {
      const Eigen::Vector2d s = corner + (prev - corner) * (d / in);
      if (d <= 0.5 * in && turnClearAlong(cs, fs, s, corner, y0, y1, true)) return Split{s, true, false};
    }
  }
  if (const auto s = turnFirstSplit(cs, fs, corner, next, y0, y1)) return Split{*s, false, true};
  return std::nullopt;
}

/// Erases waypoints [first, last) from the four parallel vectors.
void eraseWaypoints(std::vector<Eigen::Vector2d>& w, std::vector<double>& yaws,
                    std::vector<uint8_t>& narrow, std::vector<uint8_t>& turn_on_way,
                    std::size_t first, std::size_t last)
{
  const auto f = static_cast<std::ptrdiff_t>(first), l = static_cast<std::ptrdiff_t>(last);
  w.erase(w.begin() + f, w.begin() + l);
  yaws.erase(yaws.begin() + f, yaws.begin() + l);
  narrow.erase(narrow.begin() + f, narrow.begin() + l);
  turn_on_way.erase(turn_on_way.begin() + f, turn_on_way.begin() + l);
}

}  // namespace

namespace detail
{
/// Turns in place of at most max_rad followed by a translation in a narrow
/// passage (a footprint drive) are made on that translation instead, where
/// turnClearAlong() holds for a turn in proportion to the way (the driver's),
/// or else on the footprint translation before them, or else on a part of
/// either (partialTurn):
/// the drive turns while it translates and does not stop
/// (PathParams::turn_on_the_way_deg). Our own: the SE(2) search plans turns
/// in place only.
void turnOnTheWay(Path& path, const SE2Search& s, const FootprintSpace& fs, double max_rad)
{
  Path out = path;
  out.waypoints.assign(1, path.waypoints[0]);
  out.yaws.assign(1, path.yaws[0]);
  out.narrow.assign(1, path.narrow[0]);
  out.turn_on_way.assign(1, 0);
  const auto& w = path.waypoints;
  std::size_t k = 1;
  while (k < w.size())
  {
    // Waypoints k..m-1 turn in place at w[k - 1]; m translates from there.
    const std::size_t m = nextTranslation(w, k - 1);
    const bool merge = m > k && m < w.size() && path.narrow[m] &&
                       path.yaws[m] == path.yaws[m - 1] &&
                       std::abs(path.yaws[m - 1] - path.yaws[k - 1]) <= max_rad &&
                       turnClearAlong(s.cs, fs, w[k - 1], w[m], path.yaws[k - 1], path.yaws[m - 1], true);
    // Else onto the footprint translation before (with its own turn on the
    // way, if it has one), where the turn layer holds the yaws of a turn in
    // proportion to the way: the robot arrives turned.
    const std::size_t o = out.waypoints.size();
    const double y0 = o >= 2 && out.turn_on_way.back() ? out.yaws[o - 2] : out.yaws.back();
    const bool back = !merge && m > k && o >= 2 && path.narrow[k - 1] &&
                      (out.waypoints[o - 1] - out.waypoints[o - 2]).norm() > 1e-9 &&
                      std::abs(path.yaws[m - 1] - y0) <= max_rad &&
                      turnClearAlong(s.cs, fs, out.waypoints[o - 2], out.waypoints[o - 1], y0, path.yaws[m - 1], true);
    if (back)
    {
      out.yaws.back() = path.yaws[m - 1];
      out.turn_on_way.back() = Path::kTurnFromPrevious;
      k = m;  // drop the turns; w[m] translates on from there
      continue;
    }
    const double yc = out.yaws.back();  // the yaw at the corner
    bool turn_next = merge;  // w[m] turns on its way (instead of the turns in place)
    if (!merge && m > k && m < w.size() && path.narrow[m] && path.narrow[k - 1] &&
        path.yaws[m] == path.yaws[m - 1] && std::abs(path.yaws[m - 1] - yc) <= max_rad)
    {
      // Else on a part of either translation: the turn layer round the
      // passage's mouth often holds no turn, a little way off it does.
      if (const auto split = partialTurn(s.cs, fs, out, w[m], yc, path.yaws[m - 1]))
      {
        if (split->before)
        {
          // Hold the yaw to the split, turn from there to the corner.
          insertWaypoint(out.waypoints, out.yaws, out.narrow, out.turn_on_way, o - 1, split->point, yc, 0);
          out.yaws.back() = path.yaws[m - 1];
          out.turn_on_way.back() = Path::kTurnFromPrevious;
          k = m;
          continue;
        }
        // Hold the yaw from the corner to the split, w[m] turns on from
        // there; or turn to the split, w[m] holds on from there.
        out.waypoints.push_back(split->point);
        out.yaws.push_back(split->turn_first ? path.yaws[m - 1] : yc);
        out.narrow.push_back(1);
        out.turn_on_way.push_back(split->turn_first ? Path::kTurnFromPrevious : 0);
        turn_next = !split->turn_first;
        if (split->turn_first) k = m;  // drop the turns
      }
    }
    if (turn_next) k = m;  // drop the turns; w[m] turns on the way
    out.waypoints.push_back(w[k]);
    out.yaws.push_back(path.yaws[k]);
    out.narrow.push_back(path.narrow[k]);
    out.turn_on_way.push_back(turn_next ? Path::kTurnFromPrevious : 0);
    ++k;
  }
  path = std::move(out);
}

/// A translation along which the turn layer holds every yaw (a wide way:
/// MRPT's reactive drive, whose holonomic PTG faces the way it goes, or a
/// wide piece of a narrow shortcut), followed by a narrow translation (after
/// turns in place or not) or ending at the goal, is made a footprint drive
/// that turns to the yaw needed there on the way, from whatever yaw it
/// starts in (Path::kTurnFromAnyYaw); turns in place before and after it
/// are dropped. The robot then neither stops before the passage nor turns
/// in place at its end (b10, compact, continuous: 26 turns in place of 74
/// deg on average after a reactive drive, 9 % of the run's time). Our own,
/// as turnOnTheWay().
void leadInTurns(Path& path, const SE2Search& s, const FootprintSpace& fs)
{
  auto& w = path.waypoints;
  for (std::size_t k = 1; k < w.size(); ++k)
  {
    const std::size_t m = nextTranslation(w, k);
    // A piece of a narrow translation may be wide too (its flag is the
    // whole shortcut's): the turn layer decides.
    if (!((w[k] - w[k - 1]).norm() > 1e-9 && (m == w.size() || path.narrow[m]) &&
          turnClearAlong(s.cs, fs, w[k - 1], w[k], 0.0, 2.0 * kPi)))
      continue;
    // The yaw of the next translation (the turn it made on its way, too),
    // or the goal's.
    const double yaw = m < w.size() ? path.yaws[m] : path.final_yaw.value_or(path.yaws.back());
    makeLeadIn(w, path.yaws, path.narrow, path.turn_on_way, k, m, yaw);
    // The turns in place before it are made on it too.
    std::size_t j = k - 1;  // the first waypoint at its start
    while (j > 0 && (w[j] - w[j - 1]).norm() < 1e-9) --j;
    eraseWaypoints(w, path.yaws, path.narrow, path.turn_on_way, j + 1, k);
    k = j + 1;
  }
}
}  // namespace detail

std::size_t nextTranslation(const std::vector<Eigen::Vector2d>& w, std::size_t k)
{
  std::size_t m = k + 1;
  while (m < w.size() && (w[m] - w[k]).norm() < 1e-9) ++m;
  return m;
}

void makeLeadIn(std::vector<Eigen::Vector2d>& w, std::vector<double>& yaws,
                std::vector<uint8_t>& narrow, std::vector<uint8_t>& turn_on_way, std::size_t k,
                std::size_t m, double yaw)
{
  narrow[k] = 1;
  turn_on_way[k] = Path::kTurnFromAnyYaw;
  yaws[k] = yaw;
  if (m < w.size() && turn_on_way[m] == Path::kTurnFromPrevious) turn_on_way[m] = 0;
  eraseWaypoints(w, yaws, narrow, turn_on_way, k + 1, m);
}

void insertWaypoint(std::vector<Eigen::Vector2d>& w, std::vector<double>& yaws,
                    std::vector<uint8_t>& narrow, std::vector<uint8_t>& turn_on_way, std::size_t at,
                    const Eigen::Vector2d& point, double yaw, uint8_t turn_on_way_at)
{
  const auto k = static_cast<std::ptrdiff_t>(at);
  w.insert(w.begin() + k, point);
  yaws.insert(yaws.begin() + k, yaw);
  narrow.insert(narrow.begin() + k, uint8_t(1));
  turn_on_way.insert(turn_on_way.begin() + k, turn_on_way_at);
}

bool holdClearAlong(const CollisionSpace& cs, const FootprintSpace& fs, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b, double yaw)
{
  const YawMask bit = YawMask(1) << fs.binOf(yaw);
  return everySampleAlong(cs, a, b, [&](int, int, std::size_t i) { return (fs.clear.data()[i] & bit) != 0; });
}

std::optional<Eigen::Vector2d> turnFirstSplit(const CollisionSpace& cs, const FootprintSpace& fs,
                                              const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                              double yaw0, double yaw1)
{
  const double way = (to - from).norm();
  for (const double d : kShortTurns)
  {
    const Eigen::Vector2d s = from + (to - from) * (d / std::max(way, 1e-9));
    if (d <= 0.5 * way && turnClearAlong(cs, fs, from, s, yaw0, yaw1, true) &&
        holdClearAlong(cs, fs, s, to, yaw1))
      return s;
  }
  return std::nullopt;
}

bool turnClearAlong(const CollisionSpace& cs, const FootprintSpace& fs, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b, double yaw0, double yaw1, bool in_proportion)
{
  // The bins of the yaws from y0 to y1 (unwrapped: that way round).
  const auto binsBetween = [&](double y0, double y1)
  {
    const int steps = static_cast<int>(std::ceil(std::abs(y1 - y0) / fs.binWidth() - 1e-9));
    const int dir = y1 >= y0 ? 1 : -1;
    const int b0 = fs.binOf(y0);
    YawMask m = YawMask(1) << fs.binOf(y1);
    for (int k = 0; k <= steps && k < fs.bins; ++k)
      m |= YawMask(1) << (((b0 + dir * k) % fs.bins + fs.bins) % fs.bins);
    return m;
  };
  const YawMask all = binsBetween(yaw0, yaw1);
  return everySampleAlong(cs, a, b,
                          [&](int k, int n, std::size_t i)
                          {
                            // In proportion: the yaws within one sample either side of this one's.
                            const YawMask need =
                                !in_proportion ? all
                                               : binsBetween(yaw0 + (yaw1 - yaw0) * std::max(0, k - 1) / n,
                                                             yaw0 + (yaw1 - yaw0) * std::min(n, k + 1) / n);
                            return (fs.clear_turn.data()[i] & need) == need;
                          });
}

}  // namespace voxplore::exploration
