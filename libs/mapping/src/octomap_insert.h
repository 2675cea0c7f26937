/* voxplore — private: batched ray insertion into an octomap::OcTree.
 *
 * The keys of all rays of one depth image are gathered as Morton codes (the
 * octree's own child order), sorted, deduplicated with "occupied wins", and
 * applied in one depth-first walk of the tree that updates each touched node
 * once, keeps inner nodes at the maximum of their children and prunes like
 * OcTree::updateNode(..., lazy_eval = false) does. Not installed. */
#pragma once

#include <octomap/OcTree.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace voxplore::mapping::detail
{
/// @brief An OcTree that can create its root for a batched update (the root
///        pointer is protected in octomap::OcTreeBaseImpl). Same file type
///        ("OcTree") and behaviour as its base otherwise.
class LayerTree : public octomap::OcTree
{
 public:
  using octomap::OcTree::OcTree;

  /// @brief The root, created when the tree is empty.
  /// @param created set to true when the root was created by this call
  octomap::OcTreeNode* rootForUpdate(bool& created);
};

/// @brief OcTree::coordToKeyChecked without its undefined behaviour: OctoMap
///        casts floor(coordinate / resolution) to int before its range check,
///        which is undefined for NaN, inf and values beyond int's range.
/// @return false when a coordinate is not finite or outside the tree
bool coordToKeySafe(const octomap::OcTree& tree, const octomap::point3d& p, octomap::OcTreeKey& key);

/// @brief Where a ray stops: at the measured point when it is within
///        `max_range_m` of the origin (hit), else truncated there (no hit).
///        The same arithmetic as OccupancyOcTreeBase::computeUpdate.
/// @return true when the ray ends in a hit
bool clipRay(const octomap::point3d& origin, const octomap::point3d& p, double max_range_m,
             octomap::point3d& end);

/// @brief Gathers Morton-coded voxel keys of rays, each entry being
///        (morton << 1) | is_hit. Consecutive duplicates (rays of neighbouring
///        pixels share most voxels near the camera) are dropped on the fly by
///        a small direct-mapped cache; sortUnique() removes the rest.
class RayKeyCollector
{
 public:
  explicit RayKeyCollector(const octomap::OcTree& tree);

  /// @brief Adds the voxels a ray from `origin` to `end` passes (the end
  ///        voxel excluded; a 3D DDA equal to OcTreeBaseImpl::computeRayKeys)
  ///        and, when `hit`, the end voxel as occupied.
  /// @return false when origin or end is outside the tree (nothing added,
  ///         except the hit when only the origin is outside)
  bool addRay(const octomap::point3d& origin, const octomap::point3d& end, bool hit);

  /// @brief Hands over the entries gathered so far (the collector is empty
  ///        afterwards and must not be used again).
  std::vector<std::uint64_t> release();

  /// Per-axis state of the 3D DDA.
  struct DdaAxes
  {
    double t_max[3], t_delta[3];
    std::uint64_t and_mask[3], or_mask[3], inc[3];
  };

 private:
  void push(std::uint64_t entry);
  void reserveForRay(float length);
  void walkDda(const DdaAxes& ax, std::uint64_t code, std::uint64_t code_end, double length);

  const octomap::OcTree& tree_;
  std::vector<std::uint64_t> entries_;  ///< [0, size_) used, the rest is room
  std::size_t size_ = 0;
  std::vector<std::uint64_t> cache_;
};

/// @brief Sorts entries by Morton code and keeps one entry per voxel, the
///        occupied one when a voxel is both passed and hit (OctoMap's rule).
/// @return (free voxels, occupied voxels)
std::pair<std::size_t, std::size_t> sortUnique(std::vector<std::uint64_t>& entries);

/// @brief Applies one hit or miss update per entry (sorted by sortUnique) in a
///        single depth-first walk; inner nodes are updated and collapsible
///        nodes pruned on the touched paths.
void applyBatch(LayerTree& tree, const std::vector<std::uint64_t>& entries);

/// @brief The Morton code of a key: bit b of key[0], key[1], key[2] at
///        3b, 3b+1, 3b+2, so 3 bits at a level are OctoMap's child index.
std::uint64_t mortonOf(const octomap::OcTreeKey& key);

}  // namespace voxplore::mapping::detail
