/* voxplore — unknown cells the cameras looked at and left unknown (issue 12:
 * "a real end"). A frontier is retired when the poses that should have seen
 * what lies behind it have looked, and nothing changed: the floor under a
 * table, behind a cabinet, between a wall's foot and a plinth. Our own: the
 * thesis retires a frontier only when the sampler finds no view of it. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/grid.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace voxplore::exploration
{
struct CollisionSpace;
struct GroundGrid;
struct ProjectionParams;
struct SamplingParams;
struct ScanRatingParams;

/// @brief How often each unknown cell of G was looked at by a stop whose
///        scan went into the map, and stayed unknown.
///
///        A look: the stop's robot centre sees the cell along a 2D ray over
///        Free cells of G (the first non-Free cell of the ray), within
///        SamplingParams::look_range_m, and every height of the projection's
///        band over the cell's centre lies inside a camera's field of view
///        (ScanRatingParams' mounts, hfov, vfov; 2 deg inside the sides,
///        0.5 deg inside the top and bottom) and range. Looks count from
///        stops at least look_spacing_m apart.
///        Cells are keyed in the map frame, so grids of different extents
///        share them.
class FrontierLooks
{
 public:
  /// @brief One cell's record.
  struct Look
  {
    int32_t kx = 0, ky = 0;  ///< the cell: floor(centre / res) in the map frame
    uint32_t n = 0;          ///< looks counted
    float x = 0, y = 0;      ///< the robot centre of the last look counted [m]
  };

  /// @brief A stop whose scan entered the map (map frame); judged at the
  ///        next update().
  void addStop(const mrpt::poses::CPose2D& robot) { pending_.push_back(robot); }

  /// @brief Judges the stops added since the last update on `g`, which holds
  ///        their scans, and forgets them.
  void update(const GroundGrid& g, const ProjectionParams& band, const ScanRatingParams& cameras,
              const SamplingParams& p);

  /// @brief Row-major over `state`: 1 for the Unknown cells looked at at
  ///        least `looks` times; with `open_unknown` (row-major, as
  ///        CollisionSpace's) and pocket_m2 > 0, only the open unknown ones
  ///        whose 4-connected pocket of open unknown is smaller than
  ///        pocket_m2 and off the grid's border. Empty when looks <= 0 or no
  ///        cell is.
  std::vector<uint8_t> retiredMask(const Grid<GroundState>& state, int looks,
                                   const std::vector<uint8_t>* open_unknown = nullptr,
                                   double pocket_m2 = 0) const;

  /// @brief The records and the stops not judged yet (voxplore-plan's inputs).
  std::vector<Look> records() const;
  const std::vector<mrpt::poses::CPose2D>& pending() const { return pending_; }
  /// @brief Adds a record read back (records() of another instance).
  void restore(const Look& l);

 private:
  std::unordered_map<uint64_t, Look> looks_;
  std::vector<mrpt::poses::CPose2D> pending_;
};

/// @brief plan()'s use: judges `looks`' pending stops on g, then the cells
///        retired (retiredMask with SamplingParams' retire_looks and
///        retire_pocket_m2).
/// @param retired_m2 out: the open unknown retired [m^2]
std::vector<uint8_t> retireLooked(FrontierLooks& looks, const GroundGrid& g,
                                  const CollisionSpace& cs, const ProjectionParams& band,
                                  const ScanRatingParams& cameras, const SamplingParams& p,
                                  double& retired_m2);

}  // namespace voxplore::exploration
