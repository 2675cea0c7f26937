/* voxplore — unknown cells the cameras looked at and left unknown (issue 12). */
#include <mrpt/core/exceptions.h>
#include <mrpt/poses/CPose3D.h>
#include <voxplore/exploration/looks.h>
#include <voxplore/exploration/scan_rating.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace voxplore::exploration
{
namespace
{
constexpr double kPi = 3.14159265358979323846;
/// A height counts as in view this far inside the field of view's edges:
/// the rig's mounting and the pixel grid are not exact. Less at the top and
/// bottom: the thesis' ring looks from 0.6 m down to the horizon, and the
/// band's top (0.5 m) lies within 1.5 deg of it beyond 4 m.
constexpr double kHfovMarginRad = 2.0 * kPi / 180.0;
constexpr double kVfovMarginRad = 0.5 * kPi / 180.0;

uint64_t keyOf(int32_t kx, int32_t ky)
{
  return (static_cast<uint64_t>(static_cast<uint32_t>(kx)) << 32) | static_cast<uint32_t>(ky);
}

/// The grid's first cell in map-frame cell units (G's extent is a multiple of its resolution).
void originCells(const Grid<GroundState>& st, int32_t& ox, int32_t& oy)
{
  const double res = st.getResolution();
  ox = static_cast<int32_t>(std::lround(st.getXMin() / res));
  oy = static_cast<int32_t>(std::lround(st.getYMin() / res));
}

/// The cells of G a robot centre at (x, y) sees first along 2D rays over
/// Free cells, within `range` (row-major indices, each once), when they are
/// Unknown.
std::vector<int> firstUnknownCells(const Grid<GroundState>& st, double x, double y, double range)
{
  const double res = st.getResolution();
  const int nx = static_cast<int>(st.getSizeX()), ny = static_cast<int>(st.getSizeY());
  // Rays a cell apart at the range's end, each walking the cells it crosses
  // (Amanatides and Woo's grid traversal), in cell units from the grid's corner.
  const int rays = std::max(8, static_cast<int>(std::ceil(2.0 * kPi * range / res)));
  const double ux = (x - st.getXMin()) / res, uy = (y - st.getYMin()) / res, reach = range / res;
  const int cx0 = static_cast<int>(std::floor(ux)), cy0 = static_cast<int>(std::floor(uy));
  std::vector<int> out;
  if (cx0 < 0 || cy0 < 0 || cx0 >= nx || cy0 >= ny) return out;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < rays; ++k)
  {
    const double a = 2.0 * kPi * k / rays, dx = std::cos(a), dy = std::sin(a);
    const int sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
    const double step_x = dx != 0 ? std::abs(1.0 / dx) : kInf;
    const double step_y = dy != 0 ? std::abs(1.0 / dy) : kInf;
    double next_x = dx != 0 ? (dx > 0 ? cx0 + 1 - ux : ux - cx0) * step_x : kInf;
    double next_y = dy != 0 ? (dy > 0 ? cy0 + 1 - uy : uy - cy0) * step_y : kInf;
    int cx = cx0, cy = cy0;
    for (;;)
    {
      // Leave the current cell through the nearer side.
      const double t = std::min(next_x, next_y);
      if (t > reach) break;
      if (next_x < next_y)
      {
        cx += sx;
        next_x += step_x;
      }
      else
      {
        cy += sy;
        next_y += step_y;
      }
      if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) break;
      const int i = cx + cy * nx;
      const GroundState v = st.data()[static_cast<std::size_t>(i)];
      if (v == GroundState::Free) continue;
      if (v == GroundState::Unknown) out.push_back(i);
      break;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Does every height of `zs` over (x, y) lie in one of the cameras' views?
bool inView(const std::vector<mrpt::poses::CPose3D>& cams, double x, double y,
            const double (&zs)[3], double tan_h, double tan_v, double max_range)
{
  for (const double z : zs)
  {
    bool seen = false;
    for (const auto& T : cams)
    {
      double lx, ly, lz;
      T.inverseComposePoint(x, y, z, lx, ly, lz);
      if (lx <= 0 || std::abs(ly) > tan_h * lx || std::abs(lz) > tan_v * lx) continue;
      if (lx * lx + ly * ly + lz * lz > max_range * max_range) continue;
      seen = true;
      break;
    }
    if (!seen) return false;
  }
  return true;
}
}  // namespace

void FrontierLooks::update(const GroundGrid& g, const ProjectionParams& band,
                           const ScanRatingParams& cameras, const SamplingParams& p)
{
  std::vector<mrpt::poses::CPose2D> stops;
  stops.swap(pending_);
  const Grid<GroundState>& st = g.state;
  if (p.retire_looks <= 0 || stops.empty() || st.getSizeX() == 0 || st.getSizeY() == 0) return;
  const double res = st.getResolution();
  const double zs[3] = {band.z_min_m + 0.5 * res, 0.5 * (band.z_min_m + band.z_max_m),
                        band.z_max_m - 0.5 * res};
  const double tan_h = std::tan(std::max(0.0, 0.5 * cameras.hfov - kHfovMarginRad));
  const double tan_v = std::tan(std::max(0.0, 0.5 * cameras.vfov - kVfovMarginRad));
  int32_t ox, oy;
  originCells(st, ox, oy);
  const int nx = static_cast<int>(st.getSizeX());
  const double range = p.look_range_m;
  std::vector<mrpt::poses::CPose3D> cams(cameras.mounts.size());
  for (const auto& robot : stops)
  {
    const mrpt::poses::CPose3D T_world_robot(robot);
    for (std::size_t k = 0; k < cams.size(); ++k) cams[k] = T_world_robot + cameras.mounts[k];
    for (const int i : firstUnknownCells(st, robot.x(), robot.y(), range))
    {
      const int cx = i % nx, cy = i / nx;
      const double x = st.idx2x(cx), y = st.idx2y(cy);
      if (!inView(cams, x, y, zs, tan_h, tan_v, cameras.max_range_m)) continue;
      Look& l = looks_[keyOf(ox + cx, oy + cy)];
      if (l.n > 0 && std::hypot(robot.x() - l.x, robot.y() - l.y) < p.look_spacing_m) continue;
      l.kx = ox + cx;
      l.ky = oy + cy;
      l.n++;
      l.x = static_cast<float>(robot.x());
      l.y = static_cast<float>(robot.y());
    }
  }
}

std::vector<uint8_t> FrontierLooks::retiredMask(const Grid<GroundState>& st, int looks,
                                                const std::vector<uint8_t>* open_unknown,
                                                double pocket_m2) const
{
  std::vector<uint8_t> mask;
  if (looks <= 0) return mask;
  int32_t ox, oy;
  originCells(st, ox, oy);
  const int nx = static_cast<int>(st.getSizeX()), ny = static_cast<int>(st.getSizeY());
  const double res = st.getResolution();
  const std::size_t max_pocket = open_unknown && pocket_m2 > 0
                                     ? static_cast<std::size_t>(pocket_m2 / (res * res))
                                     : 0;
  if (open_unknown) ASSERT_EQUAL_(open_unknown->size(), st.data().size());
  std::optional<UnknownPockets> pockets;  // labelled when first needed
  const auto small = [&](std::size_t i)
  {
    if (!(*open_unknown)[i]) return false;
    if (!pockets) pockets = openUnknownPockets(open_unknown->data(), nx, ny);
    const int64_t cells = pockets->cells[static_cast<std::size_t>(pockets->label[i])];
    return cells >= 0 && static_cast<std::size_t>(cells) < max_pocket;
  };
  for (const auto& [key, l] : looks_)
  {
    if (l.n < static_cast<uint32_t>(looks)) continue;
    const int cx = l.kx - ox, cy = l.ky - oy;
    if (cx < 0 || cy < 0 || cx >= nx || cy >= ny) continue;
    const std::size_t i = static_cast<std::size_t>(cx) + static_cast<std::size_t>(cy) * nx;
    if (st.data()[i] != GroundState::Unknown) continue;
    if (max_pocket > 0 && !small(i)) continue;
    if (mask.empty()) mask.assign(st.data().size(), 0);
    mask[i] = 1;
  }
  return mask;
}

std::vector<FrontierLooks::Look> FrontierLooks::records() const
{
  std::vector<Look> out;
  out.reserve(looks_.size());
  for (const auto& kv : looks_) out.push_back(kv.second);
  std::sort(out.begin(), out.end(), [](const Look& a, const Look& b)
            { return a.kx != b.kx ? a.kx < b.kx : a.ky < b.ky; });
  return out;
}

std::vector<uint8_t> retireLooked(FrontierLooks& looks, const GroundGrid& g,
                                  const CollisionSpace& cs, const ProjectionParams& band,
                                  const ScanRatingParams& cameras, const SamplingParams& p,
                                  double& retired_m2)
{
  looks.update(g, band, cameras, p);
  std::vector<uint8_t> out =
      looks.retiredMask(g.state, p.retire_looks, &cs.open_unknown, p.retire_pocket_m2);
  std::size_t n = 0;
  for (std::size_t i = 0; i < out.size(); ++i) n += out[i] && cs.open_unknown[i];
  const double res = g.state.getResolution();
  retired_m2 = static_cast<double>(n) * res * res;
  return out;
}

void FrontierLooks::restore(const Look& l)
{
  ASSERTMSG_(l.n > 0, "FrontierLooks::restore: a record with no look");
  looks_[keyOf(l.kx, l.ky)] = l;
}

}  // namespace voxplore::exploration
