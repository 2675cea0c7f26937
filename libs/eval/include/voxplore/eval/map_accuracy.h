/* voxplore — accuracy of an occupancy map against a world's ground-truth surfaces. */
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <voxplore/sim/ground_truth.h>

#include <Eigen/Core>
#include <vector>

namespace voxplore::eval
{
/// @brief Share of occupied map voxels near a true surface.
struct MapPrecision
{
  std::size_t occupied = 0;      ///< occupied map voxels evaluated
  std::size_t near_surface = 0;  ///< of them, within one voxel of a ground-truth surface voxel
  double precision = 0;          ///< near_surface / occupied (0 when nothing is occupied)
};

/// @brief For each occupied voxel centre (map frame), transformed into the
///        world by T_world_map, checks whether a ground-truth surface voxel
///        (resolution res_m) lies in the 3 x 3 x 3 neighbourhood of the
///        voxel containing it.
MapPrecision mapPrecision(
    const std::vector<Eigen::Vector3d>& occupied_centers_map, const mrpt::poses::CPose3D& T_world_map,
    const std::vector<sim::VoxelIndex>& surface_voxels, double res_m);

}  // namespace voxplore::eval
