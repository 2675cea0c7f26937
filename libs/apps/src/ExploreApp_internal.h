/* voxplore — internals of ExploreApp shared by its source files (not installed). */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <voxplore/exploration/stages.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/footprint_reach.h>
#include <voxplore/sim/ground_truth.h>

#include <Eigen/Core>
#include <vector>

namespace voxplore::apps::explore_detail
{
/// @brief Share of the ground-truth free floor (world frame, cells = 1) whose
///        cell centre falls into a Free cell of the map-frame ground grid `g`.
/// @param T_world_map the map frame in the world (the robot's start pose)
/// @return 0 when the ground truth has no free cell
double coverage2d(
    const exploration::GroundGrid& g, const sim::FloorGrid& free_floor_world,
    const mrpt::poses::CPose2D& T_world_map);

/// @brief Share of the ground-truth surface voxels `band` (world frame,
///        resolution res_m) that have an occupied map voxel within one voxel
///        (3 x 3 x 3 neighbourhood, the tolerance of eval::mapPrecision).
/// @return 0 when `band` is empty
double coverage3d(
    const std::vector<Eigen::Vector3d>& occupied_centers_map, const mrpt::poses::CPose3D& T_world_map,
    const std::vector<sim::VoxelIndex>& band, double res_m);

/// @brief coverage_map.png: the ground-truth floor grid (world frame, y up).
///        The floor coverage_2d is measured on (`gt`: what the footprint
///        reaches or sees) in blue where the map knows it as Free and red where
///        it missed it; where the planner's circle reaches none of it (in
///        `gt` but not in `planner`'s free floor: rooms behind doors narrower
///        than the circle, floor seen through a gap) teal when known, purple
///        when missed. Floor that only a circle reaches (`planner` or `body`
///        free floor outside `gt`; rare, a cell or two where a yaw bin's
///        rectangle is tighter than the circle) orange, light when known.
///        Obstacles black, the rest light grey, the true trajectory dark red:
///        where coverage_2d was lost. All three share one grid.
/// @throws std::runtime_error naming the path when it cannot be written.
void writeCoverageMap(
    const exploration::GroundGrid& g, const sim::FootprintReach& gt,
    const sim::ReachableFloor& planner, const sim::ReachableFloor& body,
    const mrpt::poses::CPose2D& T_world_map,
    const std::vector<mrpt::poses::CPose2D>& trajectory_world, const std::string& png_path,
    int scale = 2);

/// @brief The smallest clearance along a trajectory and where it was.
struct ClearanceMin
{
  double clearance_m = 0;           ///< 0 when a pose collides; cap_m when nothing was within it
  std::size_t index = 0;            ///< trajectory index of the first pose at that clearance
  mrpt::poses::CPose2D pose_world;  ///< that pose
};

/// @brief Smallest distance between the footprint and the world geometry
///        over `trajectory_world`: for each pose, bisection on the margin d
///        by which the footprint rectangle is offset (its corners rounded,
///        drawn as a polygon circumscribing the arcs) until it touches an
///        obstacle (CollisionChecker::overlapsObstacle), to 1 mm; a pose that
///        collides as it is gives 0. A lower bound of the true clearance,
///        within 2 % of it at the corners.
/// @return the minimum and its pose (the first pose when nothing is within cap_m)
ClearanceMin minClearance(
    const sim::CollisionChecker& checker, const sim::Footprint& footprint,
    const std::vector<mrpt::poses::CPose2D>& trajectory_world, double cap_m = 2.0);

}  // namespace voxplore::apps::explore_detail
