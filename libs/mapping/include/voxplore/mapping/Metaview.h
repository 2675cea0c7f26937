/* voxplore — the metaview M: all registered clouds with point reduction (thesis 4.4.2, fig. 4.8). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/mapping/PlanarIcp.h>

#include <cstdint>
#include <vector>

namespace voxplore::mapping
{
/// @brief Metaview settings. ini section [metaview].
struct MetaviewParams : public mrpt::config::CLoadableOptions
{
  double d_min_m = 0.02;  ///< a point joins only if no metaview point is closer (thesis d_min) [m]
  /// The floor-plane footprint (the planar ICP's model) takes a point only
  /// when no footprint point of a stop d_dup_after_m or more of travel back
  /// is within this distance; d_min_m still spaces the rest. A wall seen again a
  /// few cm off (registration scatter, drift) is not drawn a second time
  /// beside the first, so the next registrations have one version of it to
  /// lock onto, not two (fifty-second session: b3 compact nearest s3's
  /// estimate swung 5-9 cm in x from stop to stop between two versions of
  /// the same walls at goodness 0.99-1.0). 0 = the thesis: d_min_m only.
  /// Our own (the thesis' reduction keeps every point farther than d_min).
  /// Off by default: 0.04 m (with d_dup_after_m 12) was no better on the
  /// 40-run campaign, online or replayed both ways (BENCHMARKS.md,
  /// fifty-third session).
  double d_dup_2d_m = 0;
  /// d_dup_2d_m holds against the footprint points of stops at least this
  /// much travel (the path between the stops' poses) before the new one
  /// only; the nearer stops' points keep the thesis' d_min_m. 0 = against
  /// every earlier stop: the first, often far and noisy, view of a surface
  /// then shuts out the close ones that follow (one-way replays of 8
  /// baseline runs: 3 worse by 3-13 cm, against 1 by 5 mm with 12 m) [m].
  double d_dup_after_m = 12;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

namespace detail
{
/// @brief Cell key -> the indices of the points in that cell: an
///        open-addressing hash (linear probing) of each cell's first point,
///        the rest chained through one `next` entry per point. Our own:
///        std::unordered_map<key, std::vector<index>> allocated twice per
///        cell, and rebuilding it for a moved metaview of 2.5 million points
///        took seconds (issue 11's loops benchmark).
class CellIndex
{
 public:
  static constexpr uint32_t kNone = ~0u;
  /// Empties it, with room for about `cells` cells.
  void clear(std::size_t cells = 0);
  /// The first point of the cell, kNone if none.
  uint32_t head(uint64_t key) const;
  /// The point after `i` in its cell, kNone at the end.
  uint32_t next(uint32_t i) const { return next_[i]; }
  /// Adds point `i` (each point once) to cell `key`.
  void add(uint64_t key, uint32_t i);

 private:
  static constexpr uint64_t kFree = ~0ull;  // cell keys use 63 bits
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> heads_, next_;
  std::size_t cells_ = 0;
  std::size_t slot(uint64_t key) const;
  void rehash(std::size_t capacity);
};
}  // namespace detail

/// @brief The metaview point map in the map frame. Point reduction uses our
///        own hash grid of d_min cells (MRPT's KD-tree cannot take points
///        incrementally: it would be rebuilt for every inserted point), so a
///        neighbour query touches at most 27 cells; memory grows with the
///        building, not with the number of scans.
class Metaview
{
 public:
  explicit Metaview(const MetaviewParams& params = {});

  /// @brief Adds the points of `cloud_robot` placed at `T_map_robot` (planar),
  ///        each only when no metaview point (including points added earlier
  ///        in this call) is within d_min_m. d_min_m = 0 adds every point.
  /// @return the number of points added
  std::size_t insert(const mrpt::maps::CPointsMap& cloud_robot, const mrpt::poses::CPose2D& T_map_robot);

  /// @brief The number of insert() calls so far (one block of points each,
  ///        empty when nothing was added).
  std::size_t numBlocks() const { return blocks_.size(); }
  /// @brief The pose block `i` is placed at.
  const mrpt::poses::CPose2D& blockPose(std::size_t i) const { return blocks_.at(i).pose; }

  /// @brief After a pose-graph relaxation: moves the points each insert()
  ///        added rigidly from the pose they were placed at to `poses[i]`
  ///        (one pose per block, in insert order), with their viewpoints,
  ///        and rebuilds the reduction grids. Linear in the metaview's
  ///        points (0.25 s for 2.5 million on one core), where inserting every
  ///        keyframe again checks each of its cloud points against d_min
  ///        (5.9 s at 1,000 keyframes, issue 11's benchmark). Not identical
  ///        to a fresh insert: where two blocks that moved differently meet,
  ///        points closer than d_min may remain and a point refused near a
  ///        point that has moved away is not restored (d_min-sized seams).
  /// @throws std::invalid_argument when poses.size() != numBlocks().
  void reposition(const std::vector<mrpt::poses::CPose2D>& poses);

  /// @brief The 3D points (export, statistics).
  const mrpt::maps::CSimplePointsMap& points() const { return points_; }
  /// @brief The metaview's floor-plane footprint for the planar ICP: the
  ///        same points flattened to z = 0 and reduced with d_min in 2D. The
  ///        planar ICP ignores z anyway; reducing in 2D drops the ~25 copies
  ///        of each wall column (0.1-0.6 m at 2 cm), which makes the KD-tree
  ///        and the normal estimation that much cheaper. Its KD-tree is
  ///        rebuilt lazily by MRPT after each insert.
  const mrpt::maps::CSimplePointsMap& footprint() const { return points2d_; }
  /// @brief Where each footprint() point was seen from (the robot's position
  ///        when it joined), index-aligned: ICP pairs only surfaces seen
  ///        from the same side ([icp] same_side_only).
  const Viewpoints& footprintViewpoints() const { return viewpoints2d_; }
  std::size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  const MetaviewParams& params() const { return params_; }

 private:
  MetaviewParams params_;
  mrpt::maps::CSimplePointsMap points_, points2d_;
  Viewpoints viewpoints2d_;
  detail::CellIndex grid_, grid2d_;  ///< d_min cell -> point indices
  /// One per insert(): the pose its points were placed at and where they end.
  struct Block
  {
    mrpt::poses::CPose2D pose;
    uint32_t end3d = 0, end2d = 0;  ///< one past its last point in points_, points2d_
    double travel_m = 0;            ///< path from the first block's pose, as inserted [m]
  };
  std::vector<Block> blocks_;
  void rebuildGrid(const mrpt::maps::CSimplePointsMap& pts, detail::CellIndex& grid, bool planar) const;
  uint64_t cellKey(int64_t ix, int64_t iy, int64_t iz) const;
  /// The d_min cell of a point (z ignored when planar).
  uint64_t cellOf(float x, float y, float z, bool planar) const;
  /// Whether a point of `pts` with index < `below` is within `radius` (z
  /// ignored when planar) of (x, y, z).
  bool hasNeighbourWithin(const mrpt::maps::CSimplePointsMap& pts, const detail::CellIndex& grid,
                          bool planar, float x, float y, float z, double radius,
                          uint32_t below = detail::CellIndex::kNone) const;
  /// Adds the point unless a point of `pts` is within d_min_m, or one with
  /// index < `older_end` within d_dup_2d_m (0: no such test).
  /// @return whether the point was added
  bool addPoint(mrpt::maps::CSimplePointsMap& pts, detail::CellIndex& grid, bool planar, float x,
                float y, float z, uint32_t older_end = 0);
};

}  // namespace voxplore::mapping
