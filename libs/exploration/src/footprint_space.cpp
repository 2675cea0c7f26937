/* voxplore — the rectangle's collision space per yaw bin: the layers of the
 * states clear of occupied and open unknown cells, and clear to turn (issue
 * 13); the reachability over them is in footprint_reach.cpp. */
#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/footprint.h>

#include "footprint_reach.h"
#include "footprint_stamp.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace voxplore::exploration
{
using namespace detail;

namespace
{
constexpr double kPi = 3.14159265358979323846;

/// Layers of footprint spaces no longer used, kept for the next one (per
/// thread; recycleFootprintSpace fills it). A fresh 2 MB layer costs its
/// page faults on first touch: with five fresh layers per planning step,
/// 44 % of computeFootprintSpace went to the fill and the kernel's fault path
/// (perf, b10 omniRob map, twenty-seventh session).
constexpr std::size_t kSpareLayers = 5;
thread_local std::vector<std::vector<YawMask>> t_spare_layers;

/// The smallest spare layer whose capacity holds n cells, or none.
std::vector<YawMask> spareLayer(std::size_t n)
{
  auto& pool = t_spare_layers;
  auto best = pool.end();
  for (auto it = pool.begin(); it != pool.end(); ++it)
    if (it->capacity() >= n && (best == pool.end() || it->capacity() < best->capacity())) best = it;
  if (best == pool.end()) return {};
  std::vector<YawMask> out = std::move(*best);
  pool.erase(best);
  return out;
}

void sizeLike(Grid<YawMask>& out, const Grid<SpaceState>& like, YawMask value)
{
  out.resetLike(like, value, spareLayer(like.getSizeX() * like.getSizeY()));
}
}  // namespace

void recycleFootprintSpace(FootprintSpace&& fs)
{
  for (Grid<YawMask>* layer : {&fs.clear_occ, &fs.clear, &fs.clear_turn, &fs.reach, &fs.escape})
  {
    std::vector<YawMask> v = layer->releaseStorage();
    if (v.capacity() == 0) continue;
    auto& pool = t_spare_layers;
    if (pool.size() < kSpareLayers)
    {
      pool.push_back(std::move(v));
      continue;
    }
    // Full: keep the larger ones (the map only grows during a run).
    auto smallest = std::min_element(pool.begin(), pool.end(), [](const auto& a, const auto& b)
                                     { return a.capacity() < b.capacity(); });
    if (smallest->capacity() < v.capacity()) *smallest = std::move(v);
  }
}

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

std::optional<double> FootprintSpace::nearestReachedYaw(std::size_t i, double yaw_rad) const
{
  const YawMask m = reach.data()[i];
  if (!m) return std::nullopt;
  const int want = binOf(yaw_rad);
  for (int d = 0; d <= bins / 2; ++d)
    for (const int b : {(want + d) % bins, (want - d + bins) % bins})
      if ((m >> b) & 1u)
      {
        if (d == 0) return yaw_rad;
        // The half turn of the bin's centre nearer yaw_rad.
        return yaw_rad + mrpt::math::wrapToPi(2.0 * (binYaw(b) - yaw_rad)) / 2.0;
      }
  return std::nullopt;
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
  const auto& like = cs.state;
  const int nx = static_cast<int>(like.getSizeX()), ny = static_cast<int>(like.getSizeY());
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  const double res = like.getResolution();
  fs.margin_m = p.marginInForce(res);

  fs.turn_margin_m = std::max(p.footprint_turn_margin_m, fs.margin_m);
  const double share = p.squareShareInForce(res);
  const double lateral = p.lateralInForce(res);
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
  // What the swept path below and the reachability (footprint_reach.cpp)
  // need of the layers.
  const FootprintLayers layers{fs, g, robot, like, nx, ny, n, res, share, span, occ, occ_border,
                               stamp, all, pack, low, blocked_occ, clear_occ, clear, clear_turn,
                               reach, escape};
  // The rectangle moved sideways by footprint_lateral_m either way: a state
  // is clear for translation when it fits at one of the three places (each
  // tested against both occupied and open unknown cells at that place).
  // Turning stays at the cell centre.
  if (lateral > 0)
  {
    const double a = 0.5 * fs.length_m, b = 0.5 * fs.width_m;
    const auto left = makeStamp(a, b, fs.margin_m, res, fs.bins, share, span, lateral);
    const auto right = makeStamp(a, b, fs.margin_m, res, fs.bins, share, span, -lateral);
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
        if ((layers.blockedOcc(i) & bin) && overlaps(fs.binYaw(k)) &&
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

  layers.reachFromRobot();

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
