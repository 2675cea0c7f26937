/* voxplore — one robot-frame point cloud per stop from all depth cameras (thesis 4.4.2). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>

#include <string>
#include <vector>

namespace voxplore::mapping
{
/// @brief Point cloud settings. ini section [cloud].
struct CloudParams : public mrpt::config::CLoadableOptions
{
  double z_min_m = 0.10;       ///< floor points below this height are dropped (thesis z_min) [m]
  double z_max_m = 2.0;        ///< points above this height are dropped [m]
  double max_range_m = 7.0;    ///< points farther from their camera are dropped [m]

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief The merged cloud Q of one stop, in the robot frame (x forward, z up,
///        floor at z = 0), and what was dropped.
struct RobotCloud
{
  mrpt::maps::CSimplePointsMap points;  ///< Q, robot frame
  std::size_t cameras = 0;           ///< depth images used
  std::size_t valid_pixels = 0;      ///< pixels with a return
  std::size_t invalid_pixels = 0;    ///< pixels without a return (0)
  std::size_t dropped_floor = 0;     ///< valid points below z_min_m
  std::size_t dropped_other = 0;     ///< above z_max_m, beyond max_range_m, or not finite
};

/// @brief All CObservation3DRangeScan with a range image in a sensory frame.
std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> depthScansOf(const mrpt::obs::CSensoryFrame& sf);

/// @brief Unprojects every depth image into the robot frame (each camera's
///        sensorPose applied) and keeps the points above the floor band.
RobotCloud buildRobotCloud(
    const std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& scans, const CloudParams& params);

/// @brief thesis eq. 4.1 and 4.2: the odometry increment between two
///        readings, applied to the previous pose estimate.
inline mrpt::poses::CPose2D predictPose(
    const mrpt::poses::CPose2D& T_world_prev, const mrpt::poses::CPose2D& odo_prev,
    const mrpt::poses::CPose2D& odo_now)
{
  return T_world_prev + (odo_now - odo_prev);  // (b T b_{i-1})^-1 (b T b_i), eq. 4.1; eq. 4.2
}

}  // namespace voxplore::mapping
