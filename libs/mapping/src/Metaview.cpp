#include <voxplore/common/config.h>
#include <voxplore/mapping/Metaview.h>

#include "cell_key.h"

#include <cmath>

namespace voxplore::mapping
{
void MetaviewParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(d_min_m, double, c, s);
  common::requireValid(d_min_m >= 0 && d_min_m < 10, c, s, "d_min_m", "must be in [0, 10) m");
}

void MetaviewParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(d_min_m, c, s);
}

Metaview::Metaview(const MetaviewParams& params) : params_(params) {}

uint64_t Metaview::cellKey(int64_t ix, int64_t iy, int64_t iz) const
{
  return detail::cellKey(ix, iy, iz);
}

bool Metaview::hasNeighbourWithin(
    const mrpt::maps::CSimplePointsMap& pts,
    const std::unordered_map<uint64_t, std::vector<uint32_t>>& grid, bool planar, float x, float y,
    float z) const
{
  // thesis 4.4.2: a point is integrated only if ||m_k - p_i|| > d_min for all m_k in M.
  const double d = params_.d_min_m;
  const double d2 = d * d;
  const int64_t cx = static_cast<int64_t>(std::floor(x / d));
  const int64_t cy = static_cast<int64_t>(std::floor(y / d));
  const int64_t cz = planar ? 0 : static_cast<int64_t>(std::floor(z / d));
  const int64_t dz = planar ? 0 : 1;
  const auto& xs = pts.getPointsBufferRef_x();
  const auto& ys = pts.getPointsBufferRef_y();
  const auto& zs = pts.getPointsBufferRef_z();
  for (int64_t ix = cx - 1; ix <= cx + 1; ix++)
    for (int64_t iy = cy - 1; iy <= cy + 1; iy++)
      for (int64_t iz = cz - dz; iz <= cz + dz; iz++)
      {
        const auto it = grid.find(cellKey(ix, iy, iz));
        if (it == grid.end()) continue;
        for (uint32_t idx : it->second)
        {
          const double ex = xs[idx] - x, ey = ys[idx] - y, ez = zs[idx] - z;
          if (ex * ex + ey * ey + ez * ez <= d2) return true;
        }
      }
  return false;
}

bool Metaview::addPoint(
    mrpt::maps::CSimplePointsMap& pts, std::unordered_map<uint64_t, std::vector<uint32_t>>& grid,
    bool planar, float x, float y, float z)
{
  const double d = params_.d_min_m;
  if (d > 0)
  {
    if (hasNeighbourWithin(pts, grid, planar, x, y, z)) return false;
    const int64_t iz = planar ? 0 : static_cast<int64_t>(std::floor(z / d));
    grid[cellKey(static_cast<int64_t>(std::floor(x / d)), static_cast<int64_t>(std::floor(y / d)), iz)]
        .push_back(static_cast<uint32_t>(pts.size()));
  }
  pts.insertPointFast(x, y, z);
  return true;
}

std::size_t Metaview::insert(const mrpt::maps::CPointsMap& cloud_robot, const mrpt::poses::CPose2D& T_map_robot)
{
  // Non-finite (or astronomically far) coordinates would overflow the cell
  // index casts (undefined behaviour): such a pose or point is never inserted.
  constexpr double kFar = 1e6;  // [m]
  const auto usable = [&](double v) { return std::abs(v) < kFar; };  // false for NaN too
  if (!usable(T_map_robot.x()) || !usable(T_map_robot.y()) || !std::isfinite(T_map_robot.phi()))
    return 0;
  const double c = std::cos(T_map_robot.phi()), s = std::sin(T_map_robot.phi());
  const auto& xs = cloud_robot.getPointsBufferRef_x();
  const auto& ys = cloud_robot.getPointsBufferRef_y();
  const auto& zs = cloud_robot.getPointsBufferRef_z();
  const std::size_t before = points_.size();
  const Eigen::Vector2f viewpoint(static_cast<float>(T_map_robot.x()), static_cast<float>(T_map_robot.y()));
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    const float x = static_cast<float>(T_map_robot.x() + c * xs[i] - s * ys[i]);
    const float y = static_cast<float>(T_map_robot.y() + s * xs[i] + c * ys[i]);
    if (!usable(x) || !usable(y) || !usable(zs[i])) continue;
    addPoint(points_, grid_, false, x, y, zs[i]);
    if (addPoint(points2d_, grid2d_, true, x, y, 0.0f)) viewpoints2d_.push_back(viewpoint);
  }
  points_.mark_as_modified();  // KD-trees rebuilt on next query
  points2d_.mark_as_modified();
  return points_.size() - before;
}

}  // namespace voxplore::mapping
