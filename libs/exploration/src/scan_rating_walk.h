/* voxplore — the beam walk of the fast scan rating (private to
 * libs/exploration): one beam's DDA state, set up and stepped exactly as
 * OcTree::computeRayKeys does, and the walkers that step many beams. */
#pragma once

#include <octomap/OcTree.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scan_rating_beams.h"
#include "scan_rating_window.h"

namespace voxplore::exploration::detail
{
/// @brief DDA state of one beam.
struct BeamDda
{
  double t_max[3], t_delta[3];  ///< computeRayKeys' tMax and tDelta per axis
  double length;                ///< its `length` (float, widened)
  std::size_t addr, end;        ///< window address of the current and the end voxel
  std::ptrdiff_t advance[3];    ///< address step along x, y, z (0 when not moving)
};

/// @brief The beams of one rating with their keys.
struct RatedBeams
{
  std::vector<VirtualBeam> beams;
  std::vector<octomap::OcTreeKey> origin_keys, end_keys;
  std::vector<uint32_t> in_tree;  ///< indices of the beams inside the tree's key range
};

/// @brief Hands out the beams in order, each started: its first voxel
///        visited and its DDA set up. The DDAs are set up in batches (the
///        divisions of many beams overlap instead of queueing one beam's).
class BeamFeed
{
 public:
  BeamFeed(const octomap::OcTree& V, const RatedBeams& beams, const VoxelWindow& w)
      : V_(V), beams_(beams), w_(w)
  {
  }
  /// @return false when no beam with steps to take is left
  bool pop(VoxelWindow& w, Tally& tally, BeamDda& s);

 private:
  static constexpr std::size_t kBatch = 64;
  void setUpBatch();

  const octomap::OcTree& V_;
  const RatedBeams& beams_;
  const VoxelWindow& w_;
  std::size_t next_ = 0;  ///< next entry of beams_.in_tree to set up
  BeamDda batch_[kBatch];
  bool one_voxel_[kBatch];  ///< origin and end in one voxel
  std::size_t size_ = 0, taken_ = 0;
};

/// @brief Steps `s` on (computeRayKeys' loop) to the end of its beam.
void finishBeam(BeamDda& s, VoxelWindow& w, Tally& tally);

/// @brief Walks every beam of `feed`, one at a time (portable).
void walkBeamsScalar(BeamFeed& feed, VoxelWindow& w, Tally& tally);

/// @brief Walks every beam of `feed`, four at a time in AVX2 registers;
///        false (nothing done) when the CPU or the build has no AVX2.
bool walkBeamsAvx2(BeamFeed& feed, VoxelWindow& w, Tally& tally);

}  // namespace voxplore::exploration::detail
