/* voxplore — stage 2 of the planar ICP: point-to-line Gauss-Newton (point-to-point
 * where the metaview is not line-like) (private header). */
#pragma once

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/mapping/PlanarIcp.h>

#include <Eigen/Core>
#include <unordered_map>

namespace voxplore::mapping::detail
{
/// @brief A local line fitted to the reference points around one point.
struct LocalLine
{
  Eigen::Vector2d normal{0, 0};    ///< unit normal
  Eigen::Vector2d centroid{0, 0};  ///< mean of the neighbours: averages the range noise
  bool valid = false;              ///< false: the neighbourhood is not line-like
};

/// @brief Lazily fitted local lines of reference points (2D PCA of the
///        neighbours within a radius); cached per point index.
class LineNormals
{
 public:
  /// @param small_radius_m a neighbourhood that is not a line over radius_m
  ///        is fitted again over this one (0: not)
  LineNormals(const mrpt::maps::CPointsMap& ref, double radius_m, double small_radius_m)
      : ref_(ref), radius_m_(radius_m), small_radius_m_(small_radius_m)
  {
  }
  const LocalLine& lineAt(std::size_t idx);

 private:
  LocalLine fit(std::size_t idx, double radius_m, double max_ratio) const;

  const mrpt::maps::CPointsMap& ref_;
  double radius_m_, small_radius_m_;
  std::unordered_map<std::size_t, LocalLine> cache_;
};

/// @brief Result of the refinement.
struct RefineResult
{
  mrpt::poses::CPose2D pose;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  ///< sum of J^T J at the solution (x, y, yaw)
  std::size_t used = 0;    ///< cloud points tried
  std::size_t pairs = 0;   ///< of them paired within the final radius
  /// of them with a reference point within the final radius: `pairs` plus
  /// those refused for being seen from the other side of the line
  std::size_t near = 0;
  unsigned iterations = 0;
  bool converged = false;  ///< the last update was below the convergence step at the final radius
  double last_step_m = 0;  ///< translation of the last update [m]
  double last_step_rad = 0;  ///< rotation of the last update [rad]
  double rms_m = 0;
  bool degenerate = false;
  Eigen::Vector2d degenerate_dir{0, 0};
  double info_ratio = 0;
};

/// @brief Point-to-line Gauss-Newton from `start`, radius annealed from
///        `radius_start_m` down to params.d_max_final_m. Along a translation
///        direction with information below degeneracy_ratio (when enabled)
///        no update is made (solution remapping), unless `prior_std_m` > 0:
///        then the prior's translation along that direction is a prior of
///        that standard deviation (weight (pair_std_m / prior_std_m)^2
///        pairs) and the update is the information-weighted one. With
///        params.odometry_prior_pairs > 0 the translation of `prior` (the
///        odometry prediction) is a prior of that weight. With `viewpoints`
///        (where each reference point was seen from) a cloud point (seen
///        from the robot) is not paired with a reference line seen from its
///        other side.
RefineResult refinePointToLine(
    const mrpt::maps::CPointsMap& ref, const mrpt::maps::CPointsMap& cloud,
    const mrpt::poses::CPose2D& start, double radius_start_m, const IcpParams& params,
    const mrpt::poses::CPose2D& prior, const Viewpoints* viewpoints = nullptr, double prior_std_m = 0.0);

}  // namespace voxplore::mapping::detail
