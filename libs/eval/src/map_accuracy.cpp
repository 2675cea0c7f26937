#include <voxplore/eval/map_accuracy.h>

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace voxplore::eval
{
namespace
{
uint64_t packKey(int x, int y, int z)
{
  constexpr int64_t kOff = 1 << 20;
  return (static_cast<uint64_t>(x + kOff) << 42) | (static_cast<uint64_t>(y + kOff) << 21) |
         static_cast<uint64_t>(z + kOff);
}
}  // namespace

MapPrecision mapPrecision(
    const std::vector<Eigen::Vector3d>& occupied_centers_map, const mrpt::poses::CPose3D& T_world_map,
    const std::vector<sim::VoxelIndex>& surface_voxels, double res_m)
{
  std::unordered_set<uint64_t> surface;
  surface.reserve(surface_voxels.size() * 2);
  for (const auto& v : surface_voxels) surface.insert(packKey(v.x(), v.y(), v.z()));
  MapPrecision r;
  for (const auto& c : occupied_centers_map)
  {
    double wx, wy, wz;
    T_world_map.composePoint(c.x(), c.y(), c.z(), wx, wy, wz);
    const int ix = static_cast<int>(std::floor(wx / res_m));
    const int iy = static_cast<int>(std::floor(wy / res_m));
    const int iz = static_cast<int>(std::floor(wz / res_m));
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; dx++)
      for (int dy = -1; dy <= 1 && !near; dy++)
        for (int dz = -1; dz <= 1 && !near; dz++) near = surface.count(packKey(ix + dx, iy + dy, iz + dz)) > 0;
    r.occupied++;
    r.near_surface += near;
  }
  r.precision = r.occupied ? double(r.near_surface) / double(r.occupied) : 0.0;
  return r;
}

}  // namespace voxplore::eval
