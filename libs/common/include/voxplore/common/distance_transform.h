/* voxplore — exact Euclidean distance transform (columns: Meijster et al.,
 * "A General Algorithm for Computing Distance Transforms in Linear Time",
 * 2000, phase 1; rows: Felzenszwalb & Huttenlocher, "Distance Transforms of
 * Sampled Functions", 2012), shared by the
 * ground truth (libs/sim) and the collision-space and sample-space stages
 * (libs/exploration). */
#pragma once

#include <vector>

namespace voxplore::common
{
/// @brief "No source" value of the input; outputs >= kEdtFar / 2 mean "no
///        source in the grid". Large but finite so that the lower envelope
///        arithmetic never sees inf - inf.
constexpr double kEdtFar = 1e20;

/// @brief In place: `sq` holds 0 at source cells and kEdtFar elsewhere (row
///        major, index = x + y * width); on return it holds the squared
///        Euclidean distance in cells from each cell centre to the nearest
///        source cell centre (>= kEdtFar / 2 when there is no source).
/// @param sq     width * height values
/// @param width  cells per row (> 0)
/// @param height rows (> 0)
void squaredDistanceTransform(std::vector<double>& sq, int width, int height);

}  // namespace voxplore::common
