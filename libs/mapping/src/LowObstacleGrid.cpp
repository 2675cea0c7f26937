/* voxplore — obstacles lower than a voxel column can show. */
#include <voxplore/mapping/LowObstacleGrid.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace voxplore::mapping
{
namespace
{
std::uint64_t tileKey(std::int64_t tx, std::int64_t ty)
{
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(tx)) << 32) |
         static_cast<std::uint32_t>(ty);
}

void bump(std::uint16_t& n)
{
  if (n < std::numeric_limits<std::uint16_t>::max()) n++;
}
}  // namespace

LowObstacleGrid::LowObstacleGrid(double cell_m) : inv_cell_(1.0 / cell_m), cell_(cell_m)
{
  if (!(cell_m > 0)) throw std::invalid_argument("LowObstacleGrid: cell_m must be > 0");
}

void LowObstacleGrid::setBands(double floor_max_z, double low_min_z, double low_max_z)
{
  if (!(floor_max_z <= low_min_z && low_min_z < low_max_z))
    throw std::invalid_argument("LowObstacleGrid: need floor_max_z <= low_min_z < low_max_z");
  floor_max_z_ = floor_max_z;
  low_min_z_ = low_min_z;
  low_max_z_ = low_max_z;
}

void LowObstacleGrid::add(double x, double y, double z)
{
  const bool floor = z < floor_max_z_;
  const bool low = z >= low_min_z_ && z < low_max_z_;
  if (!floor && !low) return;
  // The OctoMap's key arithmetic (coordinate times the inverse resolution):
  // the same cell as the voxel column G projects.
  const double fx = std::floor(x * inv_cell_), fy = std::floor(y * inv_cell_);
  if (!(std::abs(fx) < 1e9 && std::abs(fy) < 1e9)) return;  // NaN, inf, absurd
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  auto& tile = tiles_[tileKey(ix >> kTileBits, iy >> kTileBits)];
  if (!tile) tile = std::make_unique<Tile>();
  Counts& c = (*tile)[static_cast<std::size_t>((iy & (kTileSide - 1)) * kTileSide +
                                               (ix & (kTileSide - 1)))];
  bump(floor ? c.floor : c.low);
}

std::vector<Eigen::Vector2d> LowObstacleGrid::obstacles(int min_hits, double min_share) const
{
  std::vector<std::pair<std::int64_t, std::int64_t>> cells;  // (iy, ix)
  for (const auto& [key, tile] : tiles_)
  {
    const auto tx = static_cast<std::int64_t>(static_cast<std::int32_t>(key >> 32));
    const auto ty = static_cast<std::int64_t>(static_cast<std::int32_t>(key & 0xffffffffU));
    for (int j = 0; j < kTileSide; j++)
      for (int i = 0; i < kTileSide; i++)
      {
        const Counts& c = (*tile)[static_cast<std::size_t>(j * kTileSide + i)];
        if (c.low < min_hits || c.low < min_share * (c.low + c.floor)) continue;
        cells.emplace_back(ty * kTileSide + j, tx * kTileSide + i);
      }
  }
  std::sort(cells.begin(), cells.end());
  std::vector<Eigen::Vector2d> out;
  out.reserve(cells.size());
  for (const auto& [iy, ix] : cells)
    out.emplace_back((static_cast<double>(ix) + 0.5) * cell_, (static_cast<double>(iy) + 0.5) * cell_);
  return out;
}

std::size_t LowObstacleGrid::cells() const
{
  std::size_t n = 0;
  for (const auto& kv : tiles_)
    n += static_cast<std::size_t>(std::count_if(kv.second->begin(), kv.second->end(),
                                                [](const Counts& c) { return c.floor || c.low; }));
  return n;
}

}  // namespace voxplore::mapping
