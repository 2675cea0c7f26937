/* voxplore — the reachability of the rectangle's states over (x, y, yaw) from
 * the robot's state, escaping when it does not fit (footprint_reach.h,
 * issue 13). */
#include "footprint_reach.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <vector>

namespace voxplore::exploration::detail
{
namespace
{
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

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

void FootprintLayers::reachFromRobot() const
{
  // Reachability from the robot's state. The robot stands where it is: its
  // own state is taken as clear of occupied cells (the map may put a wall a
  // cell too close); when it is not clear of open unknown it first escapes
  // through clear_occ states to the nearest clear ones.
  fs.robot = g.robot;
  fs.robot_bin = fs.binOf(robot.phi());
  fs.escape_margin_m = fs.margin_m;  // less only where an escape needs it
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
    // A reach shorter than the body is boxed in too, turnable or not (b7
    // compact, nbv, seed 2: a drive ended between two tables' leg groups
    // 0.55-0.6 m apart; the robot's bin reached 3 cells, two of them
    // turnable between that bin and the next only, and all 146 m^2 of known
    // floor were cut off: "the map shut the robot in" at coverage 0.40).
    const std::size_t body_cells = static_cast<std::size_t>(std::ceil(fs.length_m / res));
    bool turns = false;
    std::size_t reached = 0;
    for (std::size_t i = 0; i < n && !(turns && reached >= body_cells); ++i)
    {
      reached += reach[i] != 0;
      turns = turns || (reach[i] & canTurn(i));
    }
    if (!turns || reached < body_cells)
    {
      // The escape goes on to turnable states the reach does not hold.
      std::vector<YawMask> turning(n);
      for (std::size_t i = 0; i < n; ++i) turning[i] = canTurn(i) & ~reach[i];
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
}

}  // namespace voxplore::exploration::detail
