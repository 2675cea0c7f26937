/* voxplore — entropy scan rating of a candidate pose (thesis 3.7, 4.5.4). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace voxplore::exploration
{
/// @brief ini section [scan_rating]. The virtual cameras default to the
///        simulator's 8 x O3D100 ring; set them to the real rig.
struct ScanRatingParams : public mrpt::config::CLoadableOptions
{
  int beam_reduction = 3;      ///< use every N-th pixel in each image direction (thesis: 3)
  double max_range_m = 7.0;    ///< virtual beam length [m]
  int th_occ = 240;            ///< a beam stops at the first voxel above this (0..255)
  int width_px = 64;           ///< virtual camera image size
  int height_px = 48;
  double hfov = 0.6981317007977318;  ///< [rad] (ini: deg) 40 deg
  double vfov = 0.5235987755982988;  ///< [rad] (ini: deg) 30 deg
  /// Count only the voxels holding heights in [count_z_min_m, count_z_max_m]
  /// (set it to [projection] z_min_m..z_max_m, the band G and the floor
  /// coverage are made of); beams still walk and stop everywhere. The
  /// thesis counts every voxel a beam crosses: the unknown below the floor,
  /// above the cameras' band and inside walls drew the robot to views that
  /// found no floor. count_z_max_m <= count_z_min_m = every voxel (thesis) [m].
  double count_z_min_m = 0.0;
  double count_z_max_m = 0.0;
  /// @brief Does the counting band apply?
  bool countBand() const { return count_z_max_m > count_z_min_m; }
  /// T_robot_camera of each virtual camera (ini: camN_pose = x y z yaw pitch roll, degrees);
  /// default: the omniRob ring (as sim::CameraRigParams).
  std::vector<mrpt::poses::CPose3D> mounts;

  ScanRatingParams();
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Expected information of one virtual scan.
struct ScanRating
{
  double gain = 0;               ///< sum of the entropies (nats) of the distinct voxels the beams traverse
  std::size_t beams = 0;         ///< beams cast
  std::size_t voxels = 0;        ///< distinct voxels traversed
  std::size_t unknown_voxels = 0;  ///< of them never observed (p = 0.5)
};

/// @brief Rates a robot pose by a virtual scan of every camera through V:
///        each beam (every beam_reduction-th pixel) walks the voxels from the
///        camera until the first voxel above th_occ (included) or max range;
///        the gain is the summed entropy H = -(p ln p + (1-p) ln(1-p)) of the
///        distinct voxels traversed (in the counting band, when set), unknown
///        voxels counting p = 0.5.
///        Ours: one DDA per beam on integer keys, one shared voxel cache and
///        one visited set per rating (no repeated tree searches).
ScanRating rateScan(const octomap::OcTree& V, const mrpt::poses::CPose2D& pose, const ScanRatingParams& p);

/// @brief rateScan of every pose, in order, sharing one voxel window: the
///        samples of a planning step lie within a few metres of each other,
///        so their windows overlap, and each octree block is read once for
///        all instead of once per rating (filling the window was ~70 % of a
///        rating at beam_reduction 3). Same voxels and counts as rateScan;
///        the gain may differ from it in the last bits (the four-lane walker
///        adds the same entropies in another order; the portable walker gives
///        the same bits). Poses too far apart for one window (more than
///        4 times a single rating's) are rated one by one.
std::vector<ScanRating> rateScans(const octomap::OcTree& V,
                                  const std::vector<mrpt::poses::CPose2D>& poses,
                                  const ScanRatingParams& p);

/// @brief The same rating done naively: one OcTree::castRay per beam to find
///        its end, then computeRayKeys and one tree search per key (with a
///        KeySet for distinct voxels). The reference for tests and benchmarks.
ScanRating rateScanNaive(
    const octomap::OcTree& V, const mrpt::poses::CPose2D& pose, const ScanRatingParams& p);

/// @brief Index of the best-rated pose: the highest gain; ties (within 1e-9
///        relative) go to the lower index (the order the sampler drew them).
/// @return empty when `ratings` is empty or every gain is 0
std::optional<std::size_t> bestRated(const std::vector<ScanRating>& ratings);

}  // namespace voxplore::exploration
