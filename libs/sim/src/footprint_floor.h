/* voxplore — internals of footprintReachableFloor (not installed): the floor
 * the body covers and the floor the cameras see from the reachable set. */
#pragma once

#include <voxplore/sim/footprint_reach.h>

namespace voxplore::sim::detail
{
/// @brief Sets r.swept (not yet masked by obstacles) to the cells whose
///        centre the rectangle `fp` covers at a reachable state of `r`
///        (r.reachable, r.bins and r.yaw_bins filled in).
void sweepFloor(FootprintReach& r, const Footprint& fp);

/// @brief Sets r.visible to the free cells in 2D line of sight (through
///        non-obstacle cells of r.obstacle) of a reachable centre within
///        `range_m`, outside r.reachable. Nothing when range_m is 0.
void seeFloor(FootprintReach& r, double range_m);

}  // namespace voxplore::sim::detail
