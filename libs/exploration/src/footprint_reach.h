/* voxplore — the reachability of the rectangle's states over (x, y, yaw) from
 * the robot's state, on the collision layers per yaw bin (issue 13). Internal
 * to libs/exploration (footprint_space.cpp, footprint_reach.cpp). */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/footprint.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "footprint_stamp.h"

namespace voxplore::exploration::detail
{
/// What computeFootprintSpace's collision layers (footprint_space.cpp) hand
/// to its reachability (footprint_reach.cpp): its arguments, the grid, the
/// occupied cells and the stamp, and the layers of `fs` being written in
/// place (reach and escape zero).
struct FootprintLayers
{
  FootprintSpace& fs;
  const GroundGrid& g;
  const mrpt::poses::CPose2D& robot;
  const Grid<SpaceState>& like;
  int nx, ny;
  std::size_t n;
  double res;
  double share, span;  ///< footprint_square_share, footprint_bin_span
  const std::vector<uint8_t>& occ;          ///< per cell: occupied
  const std::vector<int>& occ_border;       ///< borderCells(occ)
  const std::vector<StampEntry>& stamp;     ///< at margin_m
  YawMask all;                              ///< fs.allBins()
  bool pack;                                ///< up to 32 bins: upper halves hold more bins
  YawMask low;                              ///< the lower half's bins (pack), else all
  const std::vector<YawMask>& blocked_occ;  ///< !pack: the occupied squares' bins
  YawMask *clear_occ, *clear, *clear_turn, *reach, *escape;  ///< fs's layers

  /// The bins the occupied squares block at cell i's centre (the margin).
  YawMask blockedOcc(std::size_t i) const { return pack ? clear_occ[i] >> 32 : blocked_occ[i]; }

  /// Fills fs.reach and fs.escape (and the robot's state, the escape's
  /// margin and flags), and drops blockedOcc's bins from clear_occ.
  void reachFromRobot() const;
};

}  // namespace voxplore::exploration::detail
