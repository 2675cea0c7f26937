/* voxplore — the floor a rectangular robot can reach (position x yaw) and see (issue 10). */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/World.h>
#include <voxplore/sim/ground_truth.h>

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

namespace voxplore::sim
{
/// @brief Settings of footprintReachableFloor().
struct FootprintReachParams
{
  double res_m = 0.05;        ///< floor grid resolution (the grid of reachableFreeFloor) [m]
  int yaw_bins = 72;          ///< yaw bins over [0, 180) (the rectangle is symmetric), 2..128
  double view_range_m = 3.0;  ///< free floor in line of sight of a reachable centre up to this
                              ///< distance counts as reachable by the cameras [m]; 0 = none
};

/// @brief The floor the robot's real footprint can reach from the start, in
///        configuration space (cell, yaw bin), and the floor seen from there.
///        Every grid has the cells of reachableFreeFloor's grid (same world,
///        start, resolution and region), so the two can be compared cell by cell.
struct FootprintReach
{
  FloorGrid obstacle;    ///< 1 where a cell touches obstacle geometry or lies outside the region
  FloorGrid reachable;   ///< 1 where the robot centre can go at some yaw, connected to the start
  FloorGrid swept;       ///< 1 on free cells the rectangle covers at a reachable (cell, yaw bin)
  FloorGrid visible;     ///< 1 on free cells in 2D line of sight of a reachable centre, in range
  FloorGrid free_floor;  ///< reachable | swept | visible: the floor coverage_2d is measured on
  int yaw_bins = 0;      ///< yaw bins over [0, pi); bin k is centred on yaw k * pi / yaw_bins
  double sweep_margin_m = 0;  ///< growth of the rectangle on each side that covers a bin's turn [m]
  bool start_free = false;    ///< false when no yaw bin near the start yaw fits at the start
  double reachable_area_m2 = 0;   ///< area of `reachable`
  double free_floor_area_m2 = 0;  ///< area of `free_floor`

  /// @brief Yaw of bin k's centre [rad], in [0, pi).
  double binYaw(int bin) const;
  /// @brief True when the state (cell (ix, iy), yaw bin) is reachable from the start.
  /// @return false outside the grid or for a bin outside [0, yaw_bins)
  bool reachableAt(int ix, int iy, int bin) const;

  /// Reachable bins per cell of the window [bins_x0, bins_x0 + bins_nx) x
  /// [bins_y0, ...) of the grid (bit k of the 128-bit mask = bin k).
  std::vector<std::array<uint64_t, 2>> bins;
  int bins_x0 = 0, bins_y0 = 0, bins_nx = 0, bins_ny = 0;
};

/// @brief The free floor the rectangle `footprint`, as `checker` sees it (its
///        obstacle polygons: the world in the slab [z_low, z_high]), can reach
///        from `start` by translating (8-neighbour cells, yaw kept) and turning
///        in place (to the next yaw bin), plus the floor it can see from there.
///
///        A state (cell, bin k) is free when the rectangle at the cell centre
///        and yaw k * delta (delta = pi / yaw_bins) touches no obstacle
///        polygon; a translation between 8-neighbour cells keeps the bin and
///        needs both states free. Turning to bin k +- 1 needs both bins free
///        for the rectangle grown by sweep_margin_m = 2 R sin(delta / 4) on
///        each side (R its circumradius): that grown rectangle holds the
///        rectangle at every yaw within half a bin, so the whole turn is free.
///        Both tests are exact at the cell centre (the centre against the
///        Minkowski sum of each obstacle polygon and the rectangle), with no
///        sampling of the obstacles; a straight passage at a bin's yaw (every
///        axis-aligned door) is passable when it is at least the footprint's
///        width plus one cell wide and never when it is narrower than the
///        width; at other yaws the nearest bin is off by up to delta / 2. A
///        move between two free neighbouring cell centres is taken as free:
///        it can cut a corner of an obstacle's configuration space (interior
///        angles >= 90 deg) by at most half a step (2.5 cm straight, 3.5 cm
///        diagonal at 5 cm cells), never cross a wall.
///        Analytic solids (World::insideObstacle) are not tested: their
///        triangles enclose them, so no path from outside enters one.
///        With `region`, cells whose centre lies outside it are obstacle cells
///        and the rectangle may not touch the outside of the box.
/// @return all grids empty but sized, and start_free false, when the start
///         lies outside the grid (or region) or the footprint fits at the start
///         yaw's bin or the bins beside it neither at the start cell nor at
///         one of its 8 neighbours.
/// @throws std::logic_error (ASSERTMSG_) on a resolution <= 0, yaw_bins outside
///         2..128 or a negative view range.
FootprintReach footprintReachableFloor(const World& world, const CollisionChecker& checker,
                                       const mrpt::poses::CPose2D& start,
                                       const Footprint& footprint,
                                       const FootprintReachParams& params = {},
                                       const Eigen::AlignedBox2d* region = nullptr);

}  // namespace voxplore::sim
