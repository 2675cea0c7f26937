/* voxplore — the rectangle's collision space per yaw bin and its reachability
 * over (x, y, yaw) (issue 13). */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/footprint.h>

#include "footprint_stamp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <vector>

namespace voxplore::exploration
{
using namespace detail;

namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

template <typename T>
void sizeLike(Grid<T>& out, const Grid<SpaceState>& like, T value)
{
  out.setSize(like.getXMin(), like.getXMax(), like.getYMin(), like.getYMax(), like.getResolution(),
              &value);
}

/// Flood over (cell, bin) from the masks already in `reach` (the cells in
/// `queue`) through the states of `allowed`, turning in place only between
/// bins of `turn` (a subset of allowed); with `stop_at`, cells whose reached
/// bins hold a bit of stop_at are not expanded further.
void flood(const FootprintSpace& fs, YawMask* reach, const YawMask* allowed, const YawMask* turn,
           std::deque<int>& queue, int nx, int ny, const YawMask* stop_at = nullptr)
{
  std::vector<uint8_t> queued(static_cast<std::size_t>(nx) * ny, 0);
  for (const int i : queue) queued[static_cast<std::size_t>(i)] = 1;
  while (!queue.empty())
  {
    const int i = queue.front();
    queue.pop_front();
    queued[static_cast<std::size_t>(i)] = 0;
    const YawMask m = reach[static_cast<std::size_t>(i)];
    if (stop_at && (m & stop_at[static_cast<std::size_t>(i)])) continue;
    const int x = i % nx, y = i / nx;
    for (int k = 0; k < 8; ++k)
    {
      const int u = x + kDx[k], v = y + kDy[k];
      if (u < 0 || v < 0 || u >= nx || v >= ny) continue;
      const int j = u + v * nx;
      YawMask move = m & allowed[static_cast<std::size_t>(j)];
      if (k >= 4)  // no corner cutting: both cells beside the diagonal allow the bin too
        move &= allowed[static_cast<std::size_t>(u + y * nx)] &
                allowed[static_cast<std::size_t>(x + v * nx)];
      if (!move) continue;
      const YawMask t = turn[static_cast<std::size_t>(j)];
      const YawMask grown = move | fs.turnClosure(move & t, t);
      const YawMask fresh = grown & ~reach[static_cast<std::size_t>(j)];
      if (!fresh) continue;
      reach[static_cast<std::size_t>(j)] |= fresh;
      if (!queued[static_cast<std::size_t>(j)])
      {
        queued[static_cast<std::size_t>(j)] = 1;
        queue.push_back(j);
      }
    }
  }
}
}  // namespace

double FootprintSpace::binWidth() const { return kPi / bins; }

double FootprintSpace::binYaw(int k) const { return k * binWidth(); }

int FootprintSpace::binOf(double yaw_rad) const
{
  double t = std::fmod(yaw_rad, kPi);
  if (t < 0) t += kPi;
  return static_cast<int>(std::lround(t / binWidth())) % bins;
}

YawMask FootprintSpace::allBins() const
{
  return bins >= 64 ? ~YawMask(0) : (YawMask(1) << bins) - 1;
}

YawMask FootprintSpace::neighbourBins(YawMask m) const
{
  // Circular shift by one bin either way (bin bins-1 borders bin 0: yaw pi is yaw 0).
  const YawMask all = allBins();
  return (((m << 1) | (m >> (bins - 1))) | ((m >> 1) | (m << (bins - 1)))) & all;
}

YawMask FootprintSpace::turnClosure(YawMask seed, YawMask allowed) const
{
  YawMask m = seed & allowed;
  for (;;)
  {
    const YawMask next = m | (neighbourBins(m) & allowed);
    if (next == m) return m;
    m = next;
  }
}

FootprintSpace computeFootprintSpace(
    const GroundGrid& g, const CollisionSpace& cs, const CollisionParams& p,
    const mrpt::poses::CPose2D& robot, const SweptPath& swept)
{
  ASSERTMSG_(p.yaw_bins >= 2 && p.yaw_bins <= 64, "computeFootprintSpace: yaw_bins must be in 2..64");
  ASSERTMSG_(p.footprint_length_m > 0 && p.footprint_width_m > 0,
             "computeFootprintSpace: the footprint must be > 0");
  FootprintSpace fs;
  fs.bins = p.yaw_bins;
  fs.length_m = p.footprint_length_m;
  fs.width_m = p.footprint_width_m;
  fs.margin_m = p.footprint_margin_m;
  const auto& like = cs.state;
  const int nx = static_cast<int>(like.getSizeX()), ny = static_cast<int>(like.getSizeY());
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  const double res = like.getResolution();

  fs.turn_margin_m = std::max(p.footprint_turn_margin_m, p.footprint_margin_m);
  const double share = p.footprint_square_share;
  const double span = p.footprint_bin_span;
  const auto stamp =
      makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, fs.margin_m, res, fs.bins, share, span);
  const auto stamp_turn = makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, fs.turn_margin_m, res,
                                    fs.bins, p.footprint_turn_square_share);
  std::vector<uint8_t> occ(n);
  const auto& ground = g.state.data();
  for (std::size_t i = 0; i < n; ++i) occ[i] = ground[i] == GroundState::Occupied;
  const std::vector<int> occ_border = borderCells(occ, nx, ny);
  const std::vector<int> unk_border = borderCells(cs.open_unknown, nx, ny);
  const YawMask all = fs.allBins();
  // Written in place into the grids returned (no copies of 2 MB layers), and
  // the stamps go into them too: every fresh 2 MB layer costs its page
  // faults (half the time of this function with ten of them, perf on the
  // b10 map). The bins the occupied squares block at the cell centre
  // (needed by the swept path and the escape) are kept in the upper half of
  // clear_occ up to 32 bins (cleared before the reachability), else in a
  // layer of their own.
  for (Grid<YawMask>* layer : {&fs.clear_occ, &fs.clear, &fs.clear_turn, &fs.reach, &fs.escape})
    sizeLike(*layer, like, YawMask(0));
  YawMask* clear_occ = &*fs.clear_occ.begin();
  YawMask* clear = &*fs.clear.begin();
  YawMask* clear_turn = &*fs.clear_turn.begin();
  YawMask* reach = &*fs.reach.begin();
  YawMask* escape = &*fs.escape.begin();
  // One pass per border list stamps both margins. Up to 32 bins, both go
  // into one 64-bit mask per cell (the turn margin's in the upper half);
  // else the turn margin's into clear_turn. The occupied squares' blocked
  // bins go into clear_occ first (or blocked_occ), the open unknown's into
  // clear.
  const bool pack = fs.bins <= 32;
  const YawMask low = pack ? (YawMask(1) << 32) - 1 : ~YawMask(0);
  const StampRows both = toRows(stamp, &stamp_turn, pack);
  std::vector<YawMask> blocked_occ(pack ? 0 : n, 0);
  stampAt(pack ? clear_occ : blocked_occ.data(), pack ? nullptr : clear_turn, occ_border, nx, ny,
          both);
  stampAt(clear, pack ? nullptr : clear_turn, unk_border, nx, ny, both);
  for (std::size_t i = 0; i < n; ++i)
  {
    const YawMask occ_stamped = pack ? clear_occ[i] : blocked_occ[i];
    const YawMask blocked_turn = pack ? (occ_stamped | clear[i]) >> 32 : clear_turn[i];
    const YawMask blocked_unk = clear[i] & low;
    const YawMask blocked = occ_stamped & low;
    const bool free = ground[i] == GroundState::Free;
    const YawMask co = free ? all & ~blocked : 0;
    clear_occ[i] = pack ? co | (blocked << 32) : co;
    clear[i] = co & ~blocked_unk;
    clear_turn[i] = clear[i] & ~blocked_turn;
  }
  /// The bins the occupied squares block at cell i's centre (the margin).
  const auto blockedOcc = [&](std::size_t i) -> YawMask {
    return pack ? clear_occ[i] >> 32 : blocked_occ[i];
  };
  // The rectangle moved sideways by footprint_lateral_m either way: a state
  // is clear for translation when it fits at one of the three places (each
  // tested against both occupied and open unknown cells at that place).
  // Turning stays at the cell centre.
  if (p.footprint_lateral_m > 0)
  {
    const double a = 0.5 * fs.length_m, b = 0.5 * fs.width_m;
    const auto left = makeStamp(a, b, fs.margin_m, res, fs.bins, share, span, p.footprint_lateral_m);
    const auto right = makeStamp(a, b, fs.margin_m, res, fs.bins, share, span, -p.footprint_lateral_m);
    // The occupied squares' layer (in reach, zeroed again below), then a
    // copy of it (in escape) that the open unknown squares are stamped into
    // as well (one pass per border list, as above).
    const StampRows sides = toRows(left, &right, pack);
    YawMask* occ_l = reach;
    YawMask* any_l = escape;
    std::vector<YawMask> occ_r, any_r;
    if (!pack) occ_r.assign(n, 0);
    stampAt(occ_l, pack ? nullptr : occ_r.data(), occ_border, nx, ny, sides);
    std::copy(occ_l, occ_l + n, any_l);
    any_r = occ_r;
    stampAt(any_l, pack ? nullptr : any_r.data(), unk_border, nx, ny, sides);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (ground[i] != GroundState::Free) continue;
      const YawMask ol = occ_l[i] & low, orr = pack ? occ_l[i] >> 32 : occ_r[i];
      const YawMask al = any_l[i] & low, ar = pack ? any_l[i] >> 32 : any_r[i];
      clear_occ[i] |= all & ~(ol & orr);
      clear[i] |= all & ~(al & ar);
    }
    std::fill(occ_l, occ_l + n, YawMask(0));
    std::fill(any_l, any_l + n, YawMask(0));
  }

  // Where the body has been it can be again: the states of the swept path
  // (and of the 4-connected cells between consecutive poses) count as clear
  // of unknown, and turnable. The cameras see no floor within about 1 m of
  // their rim, so the unknown round a body standing in a door blocked the way
  // it had come in (b1, nbv: the reach of a robot in a door was a few cells).
  // Against occupied cells a swept state keeps the margin, or failing that
  // the rectangle shrunk by one cell at the bin's centre yaw (the yaw a path
  // holds): the guard kept the body 3 cm from what it sensed there, while a
  // door post's squares reach up to a cell into the opening and closed doors
  // the robot had passed (b1, nbv: a room it had entered became a trap). At
  // the centre yaw, not at every yaw of the bin: 2.8 deg off, the corners
  // of the 1.2 m body swing 3 cm sideways, and a robot that had driven
  // through a door squarely at 90 deg had the way back closed where its end
  // was in the door (b18, nearest: 0.088, "no frontier").
  if (!swept.empty())
  {
    const double sa = 0.5 * fs.length_m - res, sb = 0.5 * fs.width_m - res;
    // The bins of `bins` the swept state at cell c may hold: those already
    // turnable there, and the rest where the rectangle shrunk by a cell
    // clears the occupied squares (never on an occupied cell), at the bin's
    // centre yaw or, failing that, at the yaw the robot had there (`yaws`,
    // the two swept samples' yaws): a robot that drove through a door at
    // 99.8 deg overlapped the door post's squares at bin 18's 101.25 deg
    // (the squares are up to a cell larger than the post, as large as the
    // shrink), the swept chain broke in the door and the way back was closed
    // (b18, omniRob, nbv: 'no reachable frontier' at 0.076 after 7 m).
    auto trust = [&](const Cell& c, YawMask bins, const std::array<double, 2>& yaws) {
      if (c.cx < 0 || c.cy < 0 || c.cx >= nx || c.cy >= ny) return;
      const std::size_t i = static_cast<std::size_t>(c.cy) * nx + c.cx;
      if (occ[i]) return;
      auto overlaps = [&](double yaw) {
        return rectangleOverlaps(occ, nx, ny, res, c.cx, c.cy, yaw, sa, sb);
      };
      for (YawMask rest = bins & ~clear_turn[i]; rest; rest &= rest - 1)
      {
        const YawMask bin = rest & (~rest + 1);
        const int k = __builtin_ctzll(bin);
        if ((blockedOcc(i) & bin) && overlaps(fs.binYaw(k)) &&
            std::none_of(yaws.begin(), yaws.end(),
                         [&](double y) { return fs.binOf(y) == k && !overlaps(y); }))
          continue;
        clear_occ[i] |= bin;
        clear[i] |= bin;
        clear_turn[i] |= bin;
      }
    };
    Cell prev{-1, -1};
    YawMask prev_bin = 0;
    double prev_yaw = 0;
    for (const auto& q : swept)
    {
      Cell c;
      if (!cellOf(like, Eigen::Vector2d(q.x(), q.y()), c)) continue;
      const YawMask bin = YawMask(1) << fs.binOf(q.z());
      const std::array<double, 2> yaws{q.z(), prev.cx >= 0 ? prev_yaw : q.z()};
      if (prev.cx >= 0 && std::abs(c.cx - prev.cx) + std::abs(c.cy - prev.cy) <= 4)
      {
        // 4-connected walk from prev to c, x first.
        Cell w = prev;
        while (w.cx != c.cx)
        {
          w.cx += c.cx > w.cx ? 1 : -1;
          trust(w, bin | prev_bin, yaws);
        }
        while (w.cy != c.cy)
        {
          w.cy += c.cy > w.cy ? 1 : -1;
          trust(w, bin | prev_bin, yaws);
        }
      }
      trust(c, bin | prev_bin, yaws);
      prev = c;
      prev_bin = bin;
      prev_yaw = q.z();
    }
  }

  // Reachability from the robot's state. The robot stands where it is: its
  // own state is taken as clear of occupied cells (the map may put a wall a
  // cell too close); when it is not clear of open unknown it first escapes
  // through clear_occ states to the nearest clear ones.
  fs.robot = g.robot;
  fs.robot_bin = fs.binOf(robot.phi());
  const std::size_t ri = static_cast<std::size_t>(g.robot.cy) * nx + g.robot.cx;
  const YawMask own = YawMask(1) << fs.robot_bin;
  std::deque<int> queue;
  if (clear[ri] & own)
  {
    reach[ri] = own | fs.turnClosure(own, clear_turn[ri]);
    queue.push_back(static_cast<int>(ri));
  }
  else
  {
    // The escape may cross unknown cells (the ring the cameras did not see),
    // never bring the rectangle onto an occupied one. When the start itself
    // is within the margin of an occupied square (a turn at the last target
    // brought a corner within a cell of a wall: the squares are up to a cell
    // larger than the wall), the escape keeps the margin the start has,
    // shrunk in half-cell steps down to -2 cells: it moves through states at
    // least as far from occupied cells as the start, never closer (b1, nbv:
    // the start at 3.8 cm from a door post, blocked at 2 cm, reached no
    // state and ended the run).
    // The start alone is tested at each margin; the grid is stamped once,
    // at the margin found.
    const std::vector<YawMask>* esc_blocked = nullptr;  // null: blockedOcc
    std::vector<YawMask> shrunk;
    fs.escape_margin_m = fs.margin_m;
    bool blocked = (blockedOcc(ri) & own) != 0;
    std::vector<StampEntry> esc_stamp;
    for (int k = 0; blocked && k <= 4; ++k)
    {
      fs.escape_margin_m = -0.5 * k * res;
      esc_stamp =
          makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, fs.escape_margin_m, res, fs.bins, share, span);
      blocked = stampBlocks(esc_stamp, occ, nx, ny, g.robot.cx, g.robot.cy, own) != 0;
    }
    if (!esc_stamp.empty() && !blocked)
    {
      shrunk.assign(n, 0);
      stampAt(shrunk.data(), nullptr, occ_border, nx, ny, toRows(esc_stamp, nullptr));
      esc_blocked = &shrunk;
    }
    // Still blocked: the map puts occupied cells under the body itself (a
    // registration off by decimetres at the last stop, b2 nbv: 0.39 m into
    // a door post). The robot stands there, so those cells are contradicted:
    // the escape ignores the occupied cells under the rectangle at its pose
    // (grown by a cell) and keeps the margin from the rest. The guard still
    // keeps the real body off whatever the cameras sense.
    std::vector<uint8_t> occ_rest;
    if (blocked)
    {
      occ_rest = occ;
      const double c = std::cos(robot.phi()), sn = std::sin(robot.phi());
      const double hl = 0.5 * fs.length_m + res, hw = 0.5 * fs.width_m + res;
      const int reach_cells = static_cast<int>(std::ceil(std::hypot(hl, hw) / res)) + 1;
      for (int v = std::max(0, g.robot.cy - reach_cells); v <= std::min(ny - 1, g.robot.cy + reach_cells); ++v)
        for (int u = std::max(0, g.robot.cx - reach_cells); u <= std::min(nx - 1, g.robot.cx + reach_cells); ++u)
        {
          const Eigen::Vector2d q = cellCenter(like, Cell{u, v});
          const double dx = q.x() - robot.x(), dy = q.y() - robot.y();
          if (std::abs(c * dx + sn * dy) <= hl && std::abs(-sn * dx + c * dy) <= hw)
            occ_rest[static_cast<std::size_t>(v) * nx + u] = 0;
        }
      shrunk.assign(n, 0);
      stampAt(shrunk.data(), nullptr, borderCells(occ_rest, nx, ny), nx, ny, toRows(stamp, nullptr));
      esc_blocked = &shrunk;
      fs.escape_margin_m = fs.margin_m;
      fs.escape_ignored_occupied = true;
    }
    const std::vector<uint8_t>& esc_occ = occ_rest.empty() ? occ : occ_rest;
    std::vector<YawMask> esc_allowed(n);
    for (std::size_t i = 0; i < n; ++i)
      esc_allowed[i] = !esc_occ[i] ? all & ~(esc_blocked ? (*esc_blocked)[i] : blockedOcc(i)) : 0;
    esc_allowed[ri] |= own;
    escape[ri] = fs.turnClosure(own, esc_allowed[ri]);
    std::deque<int> q{static_cast<int>(ri)};
    // The escape goes on through clear states that are not turnable: a
    // robot that had reversed into a door stood (3.5 cm past its swept
    // path's last state) beside a clear bin whose states led a few cells
    // into the room and no further; the escape stopped there, the way back
    // was never tried, and 3 cells were reached (b11, omniRob, nearest:
    // 'all frontiers skipped' at 0.71). Turnable states join the rest.
    flood(fs, escape, esc_allowed.data(), esc_allowed.data(), q, nx, ny, clear_turn);
    // Seeds: the clear states the escape reached.
    for (std::size_t i = 0; i < n; ++i)
    {
      const YawMask s = escape[i] & clear[i];
      if (!s) continue;
      reach[i] = s | fs.turnClosure(s, clear_turn[i]);
      queue.push_back(static_cast<int>(i));
    }
    // The escape keeps the clear states it passed through: the search turns
    // at a cell only between bins of clear_turn | escape (those of escape
    // that are clear only when it finds no path otherwise), and the escape
    // turned between any bins of esc_allowed. Dropping them (as before the
    // twentieth session) left a reach the search could not follow: a robot
    // pinched in its own bin turned through two escape bins into clear, not
    // turnable ones, and every goal beyond was reached but had no path (b3,
    // compact footprint, nearest: 58 goals x 1.9 s, 'all frontiers skipped'
    // at 0.45).
  }
  if (pack)  // blockedOcc is not needed any more: clear_occ holds its bins alone
    for (std::size_t i = 0; i < n; ++i) clear_occ[i] &= low;
  flood(fs, reach, clear, clear_turn, queue, nx, ny);
  // Boxed in: the start is clear but no reached state can turn, i.e. no
  // reached bin of clear_turn has a neighbour bin in clear_turn (b14, nbv:
  // the robot stood in a door one bin off the way it came in, its bin
  // blocked by the unknown round the door a few cells on, no 5 cm turn
  // margin in the door: 4 cells reached, "no frontier", 0.319; b6, nbv: the
  // omniRob half through a 0.80 m door 11 deg off its axis, its own bin
  // turnable but neither neighbour, translation one cell: 2 cells reached,
  // 962 m^2 cut off). Escape through states clear of occupied cells by the
  // margin (unknown ignored), turning there without the turn margin, up to
  // the first state that can turn. The guard still holds a turn that comes
  // within its margin of a sensed point.
  const auto canTurn = [&](std::size_t i) {
    return clear_turn[i] & fs.neighbourBins(clear_turn[i]);
  };
  if (clear[ri] & own)
  {
    bool turns = false;
    for (std::size_t i = 0; i < n && !turns; ++i) turns = reach[i] && (reach[i] & canTurn(i));
    if (!turns)
    {
      std::vector<YawMask> turning(n);
      for (std::size_t i = 0; i < n; ++i) turning[i] = canTurn(i);
      escape[ri] = fs.turnClosure(own, clear_occ[ri]);
      std::deque<int> q{static_cast<int>(ri)};
      flood(fs, escape, clear_occ, clear_occ, q, nx, ny, turning.data());
      bool found = false;
      for (std::size_t i = 0; i < n; ++i)
      {
        const YawMask s = escape[i] & turning[i];
        if (!s) continue;
        found = true;
        escape[i] &= ~clear_turn[i];
        const YawMask fresh = (s | fs.turnClosure(s, clear_turn[i])) & ~reach[i];
        if (!fresh) continue;
        reach[i] |= fresh;
        queue.push_back(static_cast<int>(i));
      }
      if (!found && (clear_turn[ri] & own))
      {
        // No state that can turn anywhere the escape goes (a region too
        // narrow to turn in, a corridor narrower than the body's diagonal):
        // its states, clear of occupied cells only, do not join the reach;
        // a start that could not even turn in its own bin keeps them, as
        // before the twenty-first session.
        std::fill(escape, escape + n, YawMask(0));
      }
      else
      {
        fs.escape_boxed_in = true;
        flood(fs, reach, clear, clear_turn, queue, nx, ny);
      }
    }
  }
  // The escape states are reached too (the robot passes through them).
  for (std::size_t i = 0; i < n; ++i) reach[i] |= escape[i];

  return fs;
}

void applyFootprint(CollisionSpace& cs, const FootprintSpace& fs)
{
  cs.frontier_grow_m = 0.5 * fs.width_m + fs.margin_m + cs.state.getResolution();
  auto st = cs.state.begin();
  const auto& reach = fs.reach.data();
  const auto& clear_occ = fs.clear_occ.data();
  const auto& clear = fs.clear.data();
  for (std::size_t i = 0; i < reach.size(); ++i, ++st)
  {
    if (*st == SpaceState::Occupied || *st == SpaceState::Unknown) continue;
    if (reach[i] & clear[i])
      *st = SpaceState::Free;
    else if (clear_occ[i] && !clear[i])
      *st = SpaceState::MaybeCollision;
    else
      *st = SpaceState::Collision;
  }
}

}  // namespace voxplore::exploration
