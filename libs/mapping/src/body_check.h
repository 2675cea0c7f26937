/* voxplore — the body check of a registration: a pose that puts the robot's
 * body into what the map holds occupied is not where the robot stands. */
#pragma once

#include <mrpt/poses/CPose2D.h>

#include <cstddef>

namespace octomap
{
class OcTree;
}

namespace voxplore::mapping
{
struct IcpParams;

namespace detail
{
/// @brief The occupied voxels of `V` whose centres lie inside the robot's
///        body rectangle at `pose` ([icp] body_length_m x body_width_m,
///        shrunk by body_margin_m on each side) between body_z_min_m and
///        body_z_max_m. 0 when the check is off (body_length_m or
///        body_width_m 0, or nothing left after the margin).
std::size_t occupiedUnderBody(const octomap::OcTree& V, const mrpt::poses::CPose2D& pose,
                              const IcpParams& p);
}  // namespace detail
}  // namespace voxplore::mapping
