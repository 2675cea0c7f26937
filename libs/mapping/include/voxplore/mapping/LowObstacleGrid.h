/* voxplore — obstacles lower than a voxel column can show: a 2D grid of the
 * heights the depth images measured just above the floor. */
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace voxplore::mapping
{
/// @brief Per map cell (the OctoMap's l_res, aligned with its keys), how many
///        measured points lay on the floor and how many just above it.
///
/// Our own (no MRPT or OctoMap structure does this): with 5 cm voxels the
/// floor's own noisy returns fill the voxel layer [0, 5 cm), so a 3-5 cm
/// obstacle (a table's base plate, a door sill) is invisible to the voxel
/// columns G is projected from (which start at [projection] z_min_m, 10 cm),
/// while one point's height is good to a few millimetres: a floor point is
/// seen at most 30 deg below the horizon, its height error is the range error
/// times sin(30 deg) at most (< 1 cm, 4 sigma under a 3 cm threshold).
/// A cell is a low obstacle when at least `min_hits` points in it lay in
/// [low_min_z, low_max_z) and they are at least `min_share` of the points in
/// it that lay either there or on the floor (z < floor_max_z): the share keeps
/// the cell in front of a wall, which catches some of the wall base's points
/// through range noise, free while it shows its floor.
class LowObstacleGrid
{
 public:
  /// @param cell_m the OctoMap's voxel edge (cells are floor(x / cell_m))
  explicit LowObstacleGrid(double cell_m);

  /// @brief Counts one measured world point by its height: floor (z <
  ///        floor_max_z), low (low_min_z <= z < low_max_z) or neither.
  void add(double x, double y, double z);

  /// @brief Thresholds; floor_max_z <= low_min_z < low_max_z [m].
  void setBands(double floor_max_z, double low_min_z, double low_max_z);

  /// @brief Centres of the low obstacle cells, sorted by (y, x) cell [m].
  std::vector<Eigen::Vector2d> obstacles(int min_hits, double min_share) const;

  /// @brief Cells with any count.
  std::size_t cells() const;

 private:
  struct Counts
  {
    std::uint16_t floor = 0, low = 0;
  };
  static constexpr int kTileBits = 6;  ///< 64 x 64 cells per tile
  static constexpr int kTileSide = 1 << kTileBits;
  using Tile = std::array<Counts, kTileSide * kTileSide>;

  double inv_cell_, cell_;
  double floor_max_z_ = 0.015, low_min_z_ = 0.03, low_max_z_ = 0.10;
  std::unordered_map<std::uint64_t, std::unique_ptr<Tile>> tiles_;
};

}  // namespace voxplore::mapping
