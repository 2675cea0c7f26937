/* voxplore — the stamp of the robot's rectangle over yaw bins (footprint_stamp.h). */
#include "footprint_stamp.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace voxplore::exploration::detail
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

}  // namespace

std::vector<StampEntry> makeStamp(double a, double b, double margin, double res, int bins,
                                  double square_share, double bin_span, double lateral_m)
{
  const double h = 0.5 * res * square_share, delta = kPi / bins, half = 0.5 * delta * bin_span;
  std::vector<double> ak(bins), bk(bins);
  double reach = 0;
  for (int k = 0; k < bins; ++k)
  {
    const double lo = k * delta - half, hi = k * delta + half;
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
  const int n = static_cast<int>(std::ceil((reach + std::abs(lateral_m)) / res));
  // The obstacle seen from the rectangle's centre moved lateral_m along the
  // +Y axis of the bin's centre yaw: the offset to add, per bin.
  std::vector<double> sx(bins), sy(bins);
  for (int k = 0; k < bins; ++k)
  {
    sx[k] = lateral_m * std::sin(k * delta);
    sy[k] = -lateral_m * std::cos(k * delta);
  }
  std::vector<StampEntry> out;
  for (int dy = -n; dy <= n; ++dy)
    for (int dx = -n; dx <= n; ++dx)
    {
      YawMask m = 0;
      for (int k = 0; k < bins; ++k)
      {
        const double px = res * dx + sx[k], py = res * dy + sy[k];
        const double rho2 = px * px + py * py;
        bool blocked;
        if (rho2 <= bk[k] * bk[k] && rho2 <= ak[k] * ak[k])
          blocked = true;
        else if (rho2 > ak[k] * ak[k] + bk[k] * bk[k])
          blocked = false;
        else
        {
          const double rho = std::sqrt(rho2), alpha = std::atan2(py, px);
          const double phi1 = rho > ak[k] ? std::acos(ak[k] / rho) : 0.0;
          const double phi2 = rho > bk[k] ? std::asin(bk[k] / rho) : 0.5 * kPi;
          const double lo = k * delta - half, hi = k * delta + half;
          blocked = phi1 <= phi2 && (overlapModPi(lo, hi, alpha - phi2, alpha - phi1) ||
                                     overlapModPi(lo, hi, alpha + phi1, alpha + phi2));
        }
        if (blocked) m |= YawMask(1) << k;
      }
      if (m) out.push_back({dx, dy, m});
    }
  return out;
}

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

StampRows toRows(const std::vector<StampEntry>& first, const std::vector<StampEntry>* second,
                 bool pack)
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
    if (second && !pack) r.b.assign(len, 0);
    for (const auto& [dx, m] : cells)
    {
      const std::size_t k = static_cast<std::size_t>(r.dx_max - dx);
      if (pack)
        r.a[k] = m.first | (m.second << 32);
      else
      {
        r.a[k] = m.first;
        if (second) r.b[k] = m.second;
      }
    }
    out.rows.push_back(std::move(r));
  }
  return out;
}

void stampAt(YawMask* a, YawMask* b, const std::vector<int>& borders,
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
      YawMask* out_a = a + base;
      const YawMask* in_a = r.a.data();
      for (int k = k0; k < k1; ++k) out_a[k] |= in_a[k];
      if (b && !r.b.empty())
      {
        YawMask* out_b = b + base;
        const YawMask* in_b = r.b.data();
        for (int k = k0; k < k1; ++k) out_b[k] |= in_b[k];
      }
    }
  }
}

YawMask stampBlocks(const std::vector<StampEntry>& stamp, const std::vector<uint8_t>& obstacle,
                    int nx, int ny, int cx, int cy, YawMask bins)
{
  YawMask blocked = 0;
  for (const StampEntry& e : stamp)
  {
    if (!(e.bins & bins & ~blocked)) continue;
    const int u = cx + e.dx, v = cy + e.dy;
    if (u < 0 || v < 0 || u >= nx || v >= ny) continue;
    if (obstacle[static_cast<std::size_t>(v) * nx + u]) blocked |= e.bins & bins;
  }
  return blocked;
}

bool rectangleOverlaps(const std::vector<uint8_t>& obstacle, int nx, int ny, double res, int cx,
                       int cy, double yaw, double a, double b)
{
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double h = 0.5 * res;
  const double support = h * (std::abs(c) + std::abs(s));  // the square along the rectangle's axes
  const double ex = a * std::abs(c) + b * std::abs(s), ey = a * std::abs(s) + b * std::abs(c);
  const int rx = static_cast<int>(std::ceil((ex + h) / res)), ry = static_cast<int>(std::ceil((ey + h) / res));
  for (int dy = -ry; dy <= ry; ++dy)
  {
    const int v = cy + dy;
    if (v < 0 || v >= ny) continue;
    for (int dx = -rx; dx <= rx; ++dx)
    {
      const int u = cx + dx;
      if (u < 0 || u >= nx || !obstacle[static_cast<std::size_t>(v) * nx + u]) continue;
      // Separating axes: the square's two (world x, y) and the rectangle's two.
      const double px = dx * res, py = dy * res;
      if (std::abs(px) > ex + h || std::abs(py) > ey + h) continue;
      if (std::abs(c * px + s * py) > a + support || std::abs(-s * px + c * py) > b + support) continue;
      return true;
    }
  }
  return false;
}

}  // namespace voxplore::exploration::detail
