/* voxplore — the rectangle's collision space per yaw bin and its reachability
 * over (x, y, yaw) (issue 13). */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/footprint.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <vector>

namespace voxplore::exploration
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

/// Do [lo1, hi1] and [lo2, hi2] (lengths < pi) overlap modulo pi?
bool overlapModPi(double lo1, double hi1, double lo2, double hi2)
{
  const double shift = std::floor((lo1 - lo2) / kPi) * kPi;
  for (int j = -1; j <= 2; ++j)
  {
    const double a = lo2 + shift + j * kPi, b = hi2 + shift + j * kPi;
    if (a <= hi1 && b >= lo1) return true;
  }
  return false;
}

/// One entry of the stamp: the bins an obstacle cell at offset (dx, dy)
/// cells from the robot's cell blocks.
struct StampEntry
{
  int dx, dy;
  YawMask bins;
};

/// The bins for which an obstacle square (side res) centred at offset
/// (dx, dy) * res from the robot centre touches the rectangle (half sides a,
/// b) grown by margin, at some yaw of the bin. For the bin's yaws the square
/// is bounded, along each of the rectangle's axes, by its support
/// h (|cos| + |sin|) at the bin's worst yaw, so the test is the centre point
/// against the rectangle grown by margin + that support: exact on the faces,
/// conservative only round the corners. The blocked yaws of a point at
/// (rho, alpha) are theta = alpha -+ phi with acos(a'/rho) <= phi <= asin(b'/rho).
std::vector<StampEntry> makeStamp(double a, double b, double margin, double res, int bins,
                                  double square_share)
{
  const double h = 0.5 * res * square_share, delta = kPi / bins;
  std::vector<double> ak(bins), bk(bins);
  double reach = 0;
  for (int k = 0; k < bins; ++k)
  {
    const double lo = k * delta - 0.5 * delta, hi = k * delta + 0.5 * delta;
    // max of |cos| + |sin| over [lo, hi]: sqrt(2) when a diagonal lies inside.
    double s = 0;
    for (int i = 0; i <= 16; ++i)
    {
      const double t = lo + (hi - lo) * i / 16.0;
      s = std::max(s, std::abs(std::cos(t)) + std::abs(std::sin(t)));
    }
    for (int j = -2; j <= 4; ++j)
    {
      const double diag = kPi / 4 + j * kPi / 2;
      if (diag >= lo && diag <= hi) s = std::sqrt(2.0);
    }
    ak[k] = a + margin + h * s;
    bk[k] = b + margin + h * s;
    reach = std::max(reach, std::hypot(ak[k], bk[k]));
  }
  const int n = static_cast<int>(std::ceil(reach / res));
  std::vector<StampEntry> out;
  for (int dy = -n; dy <= n; ++dy)
    for (int dx = -n; dx <= n; ++dx)
    {
      const double rho = res * std::hypot(dx, dy), alpha = std::atan2(dy, dx);
      YawMask m = 0;
      for (int k = 0; k < bins; ++k)
      {
        bool blocked;
        if (rho <= bk[k] && rho <= ak[k])
          blocked = true;
        else if (rho * rho > ak[k] * ak[k] + bk[k] * bk[k])
          blocked = false;
        else
        {
          const double phi1 = rho > ak[k] ? std::acos(ak[k] / rho) : 0.0;
          const double phi2 = rho > bk[k] ? std::asin(bk[k] / rho) : 0.5 * kPi;
          const double lo = k * delta - 0.5 * delta, hi = k * delta + 0.5 * delta;
          blocked = phi1 <= phi2 && (overlapModPi(lo, hi, alpha - phi2, alpha - phi1) ||
                                     overlapModPi(lo, hi, alpha + phi1, alpha + phi2));
        }
        if (blocked) m |= YawMask(1) << k;
      }
      if (m) out.push_back({dx, dy, m});
    }
  return out;
}

/// The cells of `src` with an 8-neighbour outside `src` (or on the grid
/// border): a rectangle whose centre lies outside src and that overlaps a
/// src square overlaps such a border square.
std::vector<int> borderCells(const std::vector<uint8_t>& src, int nx, int ny)
{
  std::vector<int> out;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
    {
      const std::size_t i = static_cast<std::size_t>(y) * nx + x;
      if (!src[i]) continue;
      bool border = false;
      for (int k = 0; k < 8 && !border; ++k)
      {
        const int u = x + kDx[k], v = y + kDy[k];
        border = u < 0 || v < 0 || u >= nx || v >= ny || !src[static_cast<std::size_t>(v) * nx + u];
      }
      if (border) out.push_back(static_cast<int>(i));
    }
  return out;
}

/// A stamp (or two, at two margins) as rows of robot cells: row `dy` covers
/// obstacle offsets dx in [dx_max - len + 1, dx_max]; element k is the
/// offset dx_max - k, so that, round an obstacle cell at x, element k blocks
/// the robot cell x - dx_max + k (increasing: one vectorisable OR per row).
struct StampRows
{
  struct Row
  {
    int dy = 0, dx_max = 0;
    std::vector<YawMask> a, b;  ///< the first and second stamp's bins (b empty: one stamp)
  };
  std::vector<Row> rows;
};

/// Rows of `first`, and of `second` when given (then each row holds both).
StampRows toRows(const std::vector<StampEntry>& first, const std::vector<StampEntry>* second)
{
  std::map<int, std::map<int, std::pair<YawMask, YawMask>>> by_row;
  for (const StampEntry& e : first) by_row[e.dy][e.dx].first |= e.bins;
  if (second)
    for (const StampEntry& e : *second) by_row[e.dy][e.dx].second |= e.bins;
  StampRows out;
  for (const auto& [dy, cells] : by_row)
  {
    StampRows::Row r;
    r.dy = dy;
    const int lo = cells.begin()->first;
    r.dx_max = cells.rbegin()->first;
    const std::size_t len = static_cast<std::size_t>(r.dx_max - lo + 1);
    r.a.assign(len, 0);
    if (second) r.b.assign(len, 0);
    for (const auto& [dx, m] : cells)
    {
      const std::size_t k = static_cast<std::size_t>(r.dx_max - dx);
      r.a[k] = m.first;
      if (second) r.b[k] = m.second;
    }
    out.rows.push_back(std::move(r));
  }
  return out;
}

/// ORs the stamp's rows into `a` (and their second masks into `b`, when the
/// rows hold two) round every cell of `borders`.
void stampAt(std::vector<YawMask>& a, std::vector<YawMask>* b, const std::vector<int>& borders,
             int nx, int ny, const StampRows& stamp)
{
  for (const int i : borders)
  {
    const int x = i % nx, y = i / nx;
    for (const StampRows::Row& r : stamp.rows)
    {
      // An obstacle at offset d from the robot: the robot at (x, y) - d.
      const int v = y - r.dy;
      if (v < 0 || v >= ny) continue;
      const int u0 = x - r.dx_max, len = static_cast<int>(r.a.size());
      const int k0 = std::max(0, -u0), k1 = std::min(len, nx - u0);
      if (k0 >= k1) continue;
      const std::size_t base = static_cast<std::size_t>(v) * nx + u0;
      YawMask* out_a = a.data() + base;
      const YawMask* in_a = r.a.data();
      for (int k = k0; k < k1; ++k) out_a[k] |= in_a[k];
      if (b && !r.b.empty())
      {
        YawMask* out_b = b->data() + base;
        const YawMask* in_b = r.b.data();
        for (int k = k0; k < k1; ++k) out_b[k] |= in_b[k];
      }
    }
  }
}

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

YawMask FootprintSpace::turnClosure(YawMask seed, YawMask allowed) const
{
  YawMask m = seed & allowed;
  const YawMask all = allBins();
  for (;;)
  {
    // Circular shift by one bin either way (bin bins-1 borders bin 0: yaw pi is yaw 0).
    const YawMask up = ((m << 1) | (m >> (bins - 1))) & all;
    const YawMask down = ((m >> 1) | (m << (bins - 1))) & all;
    const YawMask next = m | ((up | down) & allowed);
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
  const auto stamp = makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, fs.margin_m, res, fs.bins, share);
  const auto stamp_turn =
      makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, fs.turn_margin_m, res, fs.bins, share);
  std::vector<uint8_t> occ(n);
  const auto& ground = g.state.data();
  for (std::size_t i = 0; i < n; ++i) occ[i] = ground[i] == GroundState::Occupied;
  const std::vector<int> occ_border = borderCells(occ, nx, ny);
  const std::vector<int> unk_border = borderCells(cs.open_unknown, nx, ny);
  // One pass per border list stamps both margins.
  const StampRows both = toRows(stamp, &stamp_turn);
  std::vector<YawMask> blocked_occ(n, 0), blocked_unk(n, 0), blocked_turn(n, 0);
  stampAt(blocked_occ, &blocked_turn, occ_border, nx, ny, both);
  stampAt(blocked_unk, &blocked_turn, unk_border, nx, ny, both);

  const YawMask all = fs.allBins();
  // Written in place into the grids returned (no copies of 2 MB layers).
  for (Grid<YawMask>* layer : {&fs.clear_occ, &fs.clear, &fs.clear_turn, &fs.reach, &fs.escape})
    sizeLike(*layer, like, YawMask(0));
  YawMask* clear_occ = &*fs.clear_occ.begin();
  YawMask* clear = &*fs.clear.begin();
  YawMask* clear_turn = &*fs.clear_turn.begin();
  YawMask* reach = &*fs.reach.begin();
  YawMask* escape = &*fs.escape.begin();
  for (std::size_t i = 0; i < n; ++i)
  {
    const bool free = ground[i] == GroundState::Free;
    clear_occ[i] = free ? all & ~blocked_occ[i] : 0;
    clear[i] = clear_occ[i] & ~blocked_unk[i];
    clear_turn[i] = clear[i] & ~blocked_turn[i];
  }

  // Where the body has been it can be again: the states of the swept path
  // (and of the 4-connected cells between consecutive poses) count as clear
  // of unknown, and turnable. The cameras see no floor within about 1 m of
  // their rim, so the unknown round a body standing in a door blocked the way
  // it had come in (b1, nbv: the reach of a robot in a door was a few cells).
  // Against occupied cells a swept state keeps the margin, or failing that
  // the rectangle shrunk by one cell: the guard kept the body 3 cm from what
  // it sensed there, while a door post's squares reach up to a cell into the
  // opening and closed doors the robot had passed (b1, nbv: a room it had
  // entered became a trap).
  if (!swept.empty())
  {
    const auto shrunk =
        makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, -res, res, fs.bins, share);
    auto touchesOccupied = [&](const Cell& c, YawMask bin) {
      for (const StampEntry& e : shrunk)
      {
        if (!(e.bins & bin)) continue;
        const int u = c.cx + e.dx, v = c.cy + e.dy;
        if (u < 0 || v < 0 || u >= nx || v >= ny) continue;
        if (occ[static_cast<std::size_t>(v) * nx + u]) return true;
      }
      return false;
    };
    auto trust = [&](const Cell& c, YawMask bins) {
      if (c.cx < 0 || c.cy < 0 || c.cx >= nx || c.cy >= ny) return;
      const std::size_t i = static_cast<std::size_t>(c.cy) * nx + c.cx;
      if (occ[i]) return;
      for (YawMask rest = bins & ~clear_turn[i]; rest; rest &= rest - 1)
      {
        const YawMask bin = rest & (~rest + 1);
        if ((blocked_occ[i] & bin) && touchesOccupied(c, bin)) continue;
        clear_occ[i] |= bin;
        clear[i] |= bin;
        clear_turn[i] |= bin;
      }
    };
    Cell prev{-1, -1};
    YawMask prev_bin = 0;
    for (const auto& q : swept)
    {
      Cell c;
      if (!cellOf(like, Eigen::Vector2d(q.x(), q.y()), c)) continue;
      const YawMask bin = YawMask(1) << fs.binOf(q.z());
      if (prev.cx >= 0 && std::abs(c.cx - prev.cx) + std::abs(c.cy - prev.cy) <= 4)
      {
        // 4-connected walk from prev to c, x first.
        Cell w = prev;
        while (w.cx != c.cx)
        {
          w.cx += c.cx > w.cx ? 1 : -1;
          trust(w, bin | prev_bin);
        }
        while (w.cy != c.cy)
        {
          w.cy += c.cy > w.cy ? 1 : -1;
          trust(w, bin | prev_bin);
        }
      }
      trust(c, bin | prev_bin);
      prev = c;
      prev_bin = bin;
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
    const std::vector<YawMask>* esc_blocked = &blocked_occ;
    std::vector<YawMask> shrunk;
    fs.escape_margin_m = fs.margin_m;
    for (int k = 0; (esc_blocked->at(ri) & own) && k <= 4; ++k)
    {
      const double m = -0.5 * k * res;
      const auto st = makeStamp(0.5 * fs.length_m, 0.5 * fs.width_m, m, res, fs.bins, share);
      shrunk.assign(n, 0);
      stampAt(shrunk, nullptr, occ_border, nx, ny, toRows(st, nullptr));
      esc_blocked = &shrunk;
      fs.escape_margin_m = m;
    }
    // Still blocked: the map puts occupied cells under the body itself (a
    // registration off by decimetres at the last stop, b2 nbv: 0.39 m into
    // a door post). The robot stands there, so those cells are contradicted:
    // the escape ignores the occupied cells under the rectangle at its pose
    // (grown by a cell) and keeps the margin from the rest. The guard still
    // keeps the real body off whatever the cameras sense.
    std::vector<uint8_t> occ_rest;
    if (esc_blocked->at(ri) & own)
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
      stampAt(shrunk, nullptr, borderCells(occ_rest, nx, ny), nx, ny, toRows(stamp, nullptr));
      esc_blocked = &shrunk;
      fs.escape_margin_m = fs.margin_m;
      fs.escape_ignored_occupied = true;
    }
    const std::vector<uint8_t>& esc_occ = occ_rest.empty() ? occ : occ_rest;
    std::vector<YawMask> esc_allowed(n);
    for (std::size_t i = 0; i < n; ++i)
      esc_allowed[i] = !esc_occ[i] ? all & ~(*esc_blocked)[i] : 0;
    esc_allowed[ri] |= own;
    escape[ri] = fs.turnClosure(own, esc_allowed[ri]);
    std::deque<int> q{static_cast<int>(ri)};
    flood(fs, escape, esc_allowed.data(), esc_allowed.data(), q, nx, ny, clear);
    // Seeds: the clear states the escape reached.
    for (std::size_t i = 0; i < n; ++i)
    {
      const YawMask s = escape[i] & clear[i];
      if (!s) continue;
      reach[i] = s | fs.turnClosure(s, clear_turn[i]);
      queue.push_back(static_cast<int>(i));
    }
    // The escape keeps only what lies before the first clear state.
    for (std::size_t i = 0; i < n; ++i) escape[i] &= ~clear[i];
  }
  flood(fs, reach, clear, clear_turn, queue, nx, ny);
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
