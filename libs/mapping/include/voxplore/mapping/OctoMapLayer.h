/* voxplore — the 3D occupancy map V (thesis 4.4.3): an octomap::OcTree fed
 * per camera with world-frame rays from that camera's origin. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <voxplore/mapping/LowObstacleGrid.h>
#include <voxplore/mapping/map_changes.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace voxplore::mapping
{
/// @brief OctoMap settings; thresholds on the thesis' 0..255 occupancy scale
///        (p = value / 255). ini section [octomap].
struct OctoMapParams : public mrpt::config::CLoadableOptions
{
  double l_res_m = 0.05;  ///< voxel edge length l_res [m] (thesis: 5 cm)
  int th_free = 70;       ///< a voxel is free below this value (0..255)
  int th_occ = 240;       ///< a voxel is occupied above this value (0..255)
  /// Unknown / initial value (0..255). OctoMap starts every voxel at p = 0.5,
  /// so only 128 (the thesis start value) is accepted.
  int start_value = 128;
  double prob_hit = 0.7;      ///< inverse sensor model: P(occupied | hit)
  double prob_miss = 0.4;     ///< inverse sensor model: P(occupied | pass-through)
  double clamp_min = 0.1192;  ///< log-odds clamping, lower probability
  double clamp_max = 0.971;   ///< log-odds clamping, upper probability
  double max_range_m = 7.0;   ///< beams are truncated here (endpoint not marked occupied)
  /// Invalid (no-return) pixels clear free space along their ray up to this
  /// range [m]; 0 disables. A no-return of a ToF camera usually means nothing
  /// within max range, but also dark or specular surfaces, so the default is off.
  double invalid_free_range_m = 0.0;
  double start_box_x_m = 2.5;  ///< free box around the start pose: length [m]
  double start_box_y_m = 2.5;  ///< free box: width [m]
  double start_box_z_m = 0.5;  ///< free box: height above the floor [m]
  /// Low obstacles (LowObstacleGrid, beside the tree): a cell holding at
  /// least low_obstacle_min_hits measured points with heights in
  /// [low_obstacle_min_z_m, low_obstacle_max_z_m), that many being at least
  /// low_obstacle_min_share of its points there or on the floor (below
  /// low_obstacle_floor_z_m), is an obstacle for the planner. 0 = off [m].
  double low_obstacle_min_z_m = 0.03;
  double low_obstacle_max_z_m = 0.10;    ///< [m]; G's voxel columns start at [projection] z_min_m
  double low_obstacle_floor_z_m = 0.015;  ///< [m]
  int low_obstacle_min_hits = 3;
  double low_obstacle_min_share = 0.5;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
  /// @brief Occupancy probability of a 0..255 value.
  static double probOf(int value_0_255) { return value_0_255 / 255.0; }
};

/// @brief Counts of one insertion.
struct InsertStats
{
  std::size_t rays = 0;          ///< pixels turned into rays (valid + clearing invalid ones)
  std::size_t hits = 0;          ///< endpoints marked occupied
  std::size_t invalid = 0;       ///< pixels without a usable return (0, non-finite or negative range, garbage pose)
  std::size_t free_updates = 0;  ///< distinct voxels updated as free
  std::size_t occ_updates = 0;   ///< distinct voxels updated as occupied
};

/// @brief Classification of a voxel by the thesis thresholds.
enum class VoxelState
{
  Unknown,  ///< never observed, or between th_free and th_occ
  Free,     ///< value < th_free
  Occupied  ///< value > th_occ
};

struct PixelRays;

/// @brief The occupancy map V. Our own ray insertion (insertScan) gathers the
///        distinct free and occupied voxel keys of a whole camera image with
///        a 3D DDA on Morton codes and a sorted key vector, then applies one
///        Bayes update per voxel in a single depth-first walk of the tree that
///        keeps inner nodes consistent and prunes like non-lazy OctoMap.
///        insertScanStock does the same with stock OctoMap for comparison;
///        both give identical voxel values.
class OctoMapLayer
{
 public:
  explicit OctoMapLayer(const OctoMapParams& params = {});
  ~OctoMapLayer();
  OctoMapLayer(OctoMapLayer&&) noexcept;
  OctoMapLayer& operator=(OctoMapLayer&&) noexcept;

  const OctoMapParams& params() const { return params_; }

  /// @brief Marks the start box (start_box_*_m, centred on the robot, from
  ///        the floor up) as free (clamped minimum log-odds). thesis 4.4.3
  void setStartBoxFree(const mrpt::poses::CPose3D& T_world_robot);

  /// @brief Inserts one depth image: each valid pixel is a ray from the
  ///        camera origin (T_world_robot + obs.sensorPose) to its 3D point;
  ///        points beyond max_range_m are truncated (free up to max range, no hit).
  ///        Works for range_is_depth true or false. Inner nodes are updated.
  ///        Invalid pixels clear free space up to min(invalid_free_range_m,
  ///        max_range_m) when invalid_free_range_m > 0. A voxel both passed
  ///        and hit in one image is updated once, as occupied (OctoMap's rule).
  InsertStats insertScan(const mrpt::obs::CObservation3DRangeScan& obs,
                         const mrpt::poses::CPose3D& T_world_robot);

  /// @brief The same rays inserted the stock way: the body of
  ///        octomap::OcTree::insertPointCloud (discretize = false,
  ///        lazy_eval = false), i.e. computeUpdate + updateNode per key, with
  ///        the invalid-pixel rays joining the same key sets. The reference
  ///        our insertion is timed and checked against.
  InsertStats insertScanStock(const mrpt::obs::CObservation3DRangeScan& obs,
                              const mrpt::poses::CPose3D& T_world_robot);

  /// @brief State of the voxel containing world point p.
  VoxelState stateAt(const Eigen::Vector3d& p) const;

  /// @brief Centres of all leaf voxels (expanded to l_res) whose value > th_occ.
  std::vector<Eigen::Vector3d> occupiedVoxelCenters() const;

  /// @brief Centres of the cells holding a low obstacle (see
  ///        OctoMapParams::low_obstacle_min_z_m; empty when off), sorted [m].
  std::vector<Eigen::Vector2d> lowObstacles() const;
  const LowObstacleGrid& lowObstacleGrid() const { return low_; }

  /// @brief Number of leaf nodes and memory usage of the tree [bytes].
  std::size_t numLeafNodes() const;
  std::size_t memoryUsage() const;

  /// @brief Writes a .bt (binary, max-likelihood) file that bt2vrml and octovis load.
  ///        The format keeps only occupied (value > th_occ) and free leaves:
  ///        observed voxels between th_free and th_occ are written as free.
  ///        The tree itself is not changed (the bytes of OcTree::writeBinaryConst,
  ///        without octomap's "Writing N nodes... done." on stderr).
  /// @throws std::runtime_error naming the path when it cannot be written.
  void writeBinary(const std::string& path) const;

  const octomap::OcTree& tree() const;
  /// @brief The tree, for changes the journal cannot follow: the map gets a
  ///        new id, so that changedSince() answers "not known" to every
  ///        revision taken before.
  octomap::OcTree& mutableTree();

  /// @brief The map's revision now. insertScan, insertScanStock and
  ///        setStartBoxFree journal the box of keys they may change; a layer
  ///        moved in (the loop closure's rebuilt map) brings its own id.
  MapRevision revision() const { return {id_, rev_}; }
  /// @brief A box holding the key of every voxel changed since `since`
  ///        (empty: none), or nullopt when that is not known: `since` is of
  ///        another map (or of this one before mutableTree()), or older than
  ///        the journal keeps (kJournalSize changes).
  std::optional<KeyBox> changedSince(const MapRevision& since) const;
  static constexpr std::size_t kJournalSize = 1024;

 private:
  void countLow(const PixelRays& rays);
  /// Records a change within `b`; nullopt: somewhere (a new map id).
  void journal(const std::optional<KeyBox>& b);

  OctoMapParams params_;
  std::unique_ptr<octomap::OcTree> tree_;
  LowObstacleGrid low_;
  uint64_t id_ = 0;
  uint64_t rev_ = 0;
  uint64_t journal_first_ = 0;  ///< journal_[i] made revision journal_first_ + i + 1
  std::vector<KeyBox> journal_;
};

/// @brief Per-pixel ray of a depth image: world-frame camera origin and, for
///        every pixel, the world-frame endpoint (valid pixels) or unit
///        direction (invalid pixels).
struct PixelRays
{
  Eigen::Vector3d origin_world;
  std::vector<Eigen::Vector3d> endpoints_world;     ///< valid pixels
  std::vector<Eigen::Vector3d> invalid_dirs_world;  ///< unit directions of invalid pixels
  /// Pixels that give no ray at all: non-finite or negative range, non-finite
  /// camera pose or intrinsics (garbage must never reach OctoMap's keys).
  std::size_t unusable = 0;
};

/// @brief Unprojects a depth image into world-frame rays using MRPT's
///        per-pixel LUT (so range_is_depth true and false both work).
///        Pixels whose range, LUT entry or endpoint is not finite (or whose
///        range is negative), and every pixel when the camera pose is not
///        finite, are counted in PixelRays::unusable and give no ray.
PixelRays unprojectRays(const mrpt::obs::CObservation3DRangeScan& obs,
                        const mrpt::poses::CPose3D& T_world_robot);

}  // namespace voxplore::mapping
