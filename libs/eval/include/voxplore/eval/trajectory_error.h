/* voxplore — trajectory error of an estimate against ground truth. */
#pragma once

#include <voxplore/common/trajectory_io.h>

#include <vector>

namespace voxplore::eval
{
/// @brief Absolute trajectory error (ATE) of an estimate.
struct TrajectoryError
{
  std::size_t matched = 0;       ///< poses associated by timestamp
  double ate_rmse_m = 0;         ///< RMS of the position errors [m]
  double ate_max_m = 0;          ///< largest position error [m]
  double final_xy_error_m = 0;   ///< position error of the last matched pose [m]
  double final_yaw_error_rad = 0;  ///< |yaw error| of the last matched pose [rad]
  double max_yaw_error_rad = 0;    ///< largest |yaw error| [rad]
};

/// @brief Compares an estimate in the map frame (its first pose is where the
///        robot started) with ground truth in the world frame. The frames are
///        tied by the first matched pair (T_world_map = gt_0 * est_0^-1), as
///        in the thesis, with no further fitting: errors accumulate visibly.
/// @param max_dt_s poses closer in time than this are associated
/// @throws std::runtime_error when no pose can be associated.
TrajectoryError trajectoryError(
    const std::vector<common::StampedPose>& estimate,
    const std::vector<common::StampedPose>& ground_truth, double max_dt_s = 1e-3);

}  // namespace voxplore::eval
