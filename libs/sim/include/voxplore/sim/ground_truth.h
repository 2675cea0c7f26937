/* voxplore — ground truth of a world for evaluating maps and exploration. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/World.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace voxplore::sim
{
class RayCaster;

/// @brief Integer voxel index: voxel i covers [i*res, (i+1)*res) on each axis
///        (the same convention as OctoMap keys minus their 2^15 offset).
using VoxelIndex = Eigen::Vector3i;

/// @brief All voxels at resolution `res_m` that a world triangle touches,
///        restricted to z in [z_min_m, z_max_m]; sorted (x, then y, then z), unique.
std::vector<VoxelIndex> occupiedVoxels(
    const TriangleMesh& mesh, double res_m, double z_min_m = -1e9, double z_max_m = 1e9);

/// @brief A 2D grid of cells; cell (ix, iy) covers
///        [origin + ix*res, origin + (ix+1)*res) x [...].
struct FloorGrid
{
  double res_m = 0.05;
  Eigen::Vector2d origin{0, 0};
  int nx = 0, ny = 0;
  std::vector<uint8_t> cells;  ///< row-major (iy * nx + ix)
  uint8_t& at(int ix, int iy) { return cells[static_cast<std::size_t>(iy) * nx + ix]; }
  uint8_t at(int ix, int iy) const { return cells[static_cast<std::size_t>(iy) * nx + ix]; }
  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < nx && iy < ny; }
  Eigen::Vector2d center(int ix, int iy) const
  {
    return origin + Eigen::Vector2d((ix + 0.5) * res_m, (iy + 0.5) * res_m);
  }
  /// @brief The same cells, all 0.
  FloorGrid emptyLike() const;
  /// @brief Area of the cells equal to 1 [m^2].
  double areaM2() const;
  /// @brief Exact squared distance in cells^2 from every cell to the nearest
  ///        non-zero cell (`to_nonzero`) or zero cell (otherwise);
  ///        common::kEdtFar where there is none. Row-major like `cells`.
  std::vector<double> squaredCellDistance(bool to_nonzero = true) const;
};

/// @brief Free floor reachable from the start pose for a disc robot.
struct ReachableFloor
{
  FloorGrid obstacle;   ///< 1 where a cell touches obstacle geometry (slab of the checker)
  FloorGrid reachable;  ///< 1 where the robot centre can go, connected to the start
  FloorGrid free_floor; ///< 1 where a cell is free and reachable by the robot's body
                        ///< (cells within robot_radius of a reachable centre)
  double reachable_area_m2 = 0;   ///< area of `reachable`
  double free_floor_area_m2 = 0;  ///< area of `free_floor`
};

/// @brief The floor grid of reachableFreeFloor (the mesh bounds plus one cell,
///        or around `start` for an empty world) with 1 where a cell's square
///        touches an obstacle polygon of `checker` and, with `region`, where a
///        cell's centre lies outside it.
FloorGrid obstacleFloorGrid(
    const World& world, const CollisionChecker& checker, const mrpt::poses::CPose2D& start,
    double res_m = 0.05, const Eigen::AlignedBox2d* region = nullptr);

/// @brief Computes the free floor reachable from `start` for a robot of radius
///        `robot_radius_m`: obstacle cells from the checker's slab (distance
///        transform, no per-cell disc loop), then a flood fill from the start cell.
///        With `region`, cells whose centre lies outside it count as obstacles
///        (a building open to the outside: only the floor inside counts).
ReachableFloor reachableFreeFloor(
    const World& world, const CollisionChecker& checker, const mrpt::poses::CPose2D& start,
    double robot_radius_m, double res_m = 0.05, const Eigen::AlignedBox2d* region = nullptr);

/// @brief The XY bounding box of everything the robot can collide with (the
///        checker's obstacle slab): the building's extent without a ground
///        plane that reaches past it. Empty box when there is no obstacle.
Eigen::AlignedBox2d obstacleBounds(const CollisionChecker& checker);

/// @brief Renders a top view of the world (height-coloured; obstacles between
///        floor and robot height dark) as a PNG, optionally with a trajectory
///        (red line, stops as dots) and the start pose.
/// @param px_per_m image scale
/// @throws std::runtime_error naming the path when it cannot be written.
void writeTopView(
    const World& world, const RayCaster& caster, const std::string& png_path,
    double px_per_m = 50.0, const std::vector<mrpt::poses::CPose2D>& trajectory = {},
    double robot_height_m = 0.645);

}  // namespace voxplore::sim
