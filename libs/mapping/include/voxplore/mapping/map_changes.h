/* voxplore — which voxels of the occupancy map changed since a given
 * revision: lets a consumer (the planner's projection) redo only that part. */
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

namespace voxplore::mapping
{
/// @brief A half-open box of OctoMap keys, [lo, hi) per axis (x, y, z).
struct KeyBox
{
  std::array<int, 3> lo{0, 0, 0};
  std::array<int, 3> hi{0, 0, 0};

  bool empty() const { return lo[0] >= hi[0] || lo[1] >= hi[1] || lo[2] >= hi[2]; }
  /// @brief The smallest box holding both (an empty box adds nothing).
  void extend(const KeyBox& b)
  {
    if (b.empty()) return;
    if (empty())
    {
      *this = b;
      return;
    }
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], b.lo[a]);
      hi[a] = std::max(hi[a], b.hi[a]);
    }
  }
};

/// @brief A map's state at one moment: `map` names the tree (a new value
///        whenever the tree was replaced or changed outside the journal),
///        `rev` counts the journaled changes to it.
struct MapRevision
{
  uint64_t map = 0;  ///< 0: no map (every change unknown)
  uint64_t rev = 0;
};

}  // namespace voxplore::mapping
