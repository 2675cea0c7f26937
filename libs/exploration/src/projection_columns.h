/* voxplore — the projection's reading of V: the grid's key box and the
 * per-column tally of the z band (projection_columns.cpp). Internal to
 * libs/exploration (projection.cpp). */
#pragma once

#include <voxplore/exploration/stages.h>
#include <voxplore/mapping/map_changes.h>

#include <cstdint>
#include <vector>

namespace octomap
{
class OcTree;
class OcTreeKey;
}

namespace voxplore::exploration::detail
{
/// Per-column tally of the voxels in the z band (dense over the grid).
struct ColumnTally
{
  std::vector<uint8_t> occupied;     ///< 1 when a voxel of the band (or the band above) is occupied
  std::vector<uint16_t> free_count;  ///< free voxels of the band seen so far
};

/// @brief Grid key box: V's bounds plus margin_m and the robot's column, in
///        whole voxels (z left 0).
mapping::KeyBox gridKeyBox(const octomap::OcTree& V, const octomap::OcTreeKey& robot,
                           double margin_m);

/// @brief The tally of every column of `band` (z: the band) over the band,
///        with the occupied voxels of the band above it up to key `above_hi`
///        (exclusive; band.hi[2]: none); thresholds as probabilities. From
///        the cache `c` where V did not change since its last tally (same
///        tree, band and thresholds), which then holds this one; nullptr:
///        none. Returns the tally to use (the cache's, or `local`).
const ColumnTally& tallyColumns(const octomap::OcTree& V, const mapping::KeyBox& band,
                                int above_hi, double th_free, double th_occ,
                                ProjectionCache::State* c, ColumnTally& local);

}  // namespace voxplore::exploration::detail
