/* voxplore — the key of a cubic grid cell (private header): 21 bits per axis
 * (+-1M cells: +-20 km at 2 cm). Used by the metaview's hash grid and the
 * loop-closure cloud reductions. */
#pragma once

#include <cstdint>

namespace voxplore::mapping::detail
{
inline uint64_t cellKey(int64_t ix, int64_t iy, int64_t iz)
{
  constexpr int64_t kOff = 1 << 20;
  constexpr uint64_t kMask = (1u << 21) - 1;
  return ((static_cast<uint64_t>(ix + kOff) & kMask) << 42) |
         ((static_cast<uint64_t>(iy + kOff) & kMask) << 21) | (static_cast<uint64_t>(iz + kOff) & kMask);
}
}  // namespace voxplore::mapping::detail
