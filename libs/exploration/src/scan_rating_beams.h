/* voxplore — internals shared by the fast and the naive scan rating: the
 * virtual beams of a pose and the voxel entropy, so both rate exactly the
 * same rays with the same arithmetic. Private to libs/exploration. */
#pragma once

#include <octomap/octomap_types.h>
#include <octomap/octomap_utils.h>
#include <voxplore/exploration/scan_rating.h>

#include <cmath>
#include <vector>

namespace voxplore::exploration::detail
{
/// @brief One virtual beam in world coordinates, in the float points OctoMap's
///        ray functions take (computeRayKeys(origin, end) defines its voxels).
struct VirtualBeam
{
  octomap::point3d origin;
  octomap::point3d end;  ///< origin + max_range_m along the normalised pixel direction
};

/// @brief Throws (naming the field) when `p` cannot drive a rating: no
///        cameras, beam_reduction < 1, non-positive range or image size.
void checkRatingParams(const ScanRatingParams& p);

/// @brief The beams of every camera at `pose` (robot at z = 0) into `out`
///        (cleared first): camera by camera, then image row v, then column u,
///        every beam_reduction-th pixel from (0, 0); i.e. ceil(w / r) *
///        ceil(h / r) beams per camera.
void virtualBeams(const mrpt::poses::CPose2D& pose, const ScanRatingParams& p,
                  std::vector<VirtualBeam>& out);

/// @brief The absolute z keys [lo, hi] of the voxels holding heights
///        count_z_min_m and count_z_max_m (clamped to the tree's key range).
void countBandKeys(const octomap::OcTree& V, const ScanRatingParams& p, uint32_t kz[2]);

/// @brief Log-odds above which a voxel stops a beam: p > th_occ / 255,
///        compared in OctoMap's float log-odds.
inline float stopLogOdds(int th_occ)
{
  return octomap::logodds(th_occ / 255.0);
}

/// @brief thesis eq. 3.11: H = -(p ln p + (1-p) ln(1-p)) [nats] of a voxel
///        with log-odds l (p = OctoMap's probability(l)); 0 at p = 0 or 1.
inline double entropyOfLogOdds(float l)
{
  const double p = octomap::probability(l);
  double h = 0;
  if (p > 0) h -= p * std::log(p);
  if (p < 1) h -= (1 - p) * std::log1p(-p);
  return h;
}

/// @brief Entropy of a never observed voxel (p = 0.5): ln 2.
inline double unknownEntropy()
{
  return std::log(2.0);
}

}  // namespace voxplore::exploration::detail
