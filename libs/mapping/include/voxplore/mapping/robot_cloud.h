/* voxplore — one robot-frame point cloud per stop from all depth cameras (thesis 4.4.2). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/math/TTwist2D.h>
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
  /// A camera whose returns are more than this share impossible (0xFFFF, the
  /// uint16 saturation, or beyond the observation's own maxRange) is skipped
  /// as faulty; below it only those pixels are dropped (0..1).
  double max_impossible_share = 0.5;
  /// Each simplemap keyframe also carries the stop's cloud Q (robot frame,
  /// floor removed) thinned to one point per cube this big, for MRPT's
  /// tools (observations2map, ...): see makeToolsCloud(). 0: not added [m].
  double tools_cloud_cell_m = 0.10;
  /// Each simplemap keyframe also carries a horizontal 360 deg slice of Q at
  /// this height as a CObservation2DRangeScan, for MRPT's 2D tools (point
  /// maps with isPlanarMap = true take nothing else): see makeToolsSlice().
  /// 0: not added [m].
  double tools_slice_z_m = 0.30;
  /// A camera exposed before the stop's odometry reading (a scan taken
  /// while driving, [explore] scan_mode = continuous: its timestamp is
  /// earlier) is moved to where the robot was at its exposure: back along
  /// the odometry's velocity (CObservationOdometry::velocityLocal, held
  /// constant) over the time between them (deskewScans()). false = every
  /// camera at the stop's pose.
  bool deskew = true;

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

/// @brief sensorLabel of the keyframe cloud for MRPT's tools (makeToolsCloud()).
inline constexpr const char* kToolsCloudLabel = "VOXPLORE_CLOUD";

/// @brief The cloud a simplemap keyframe carries for MRPT's tools: a
///        CObservation3DRangeScan without range image whose points3D are
///        `robot_cloud` (robot frame) thinned to the first point in each
///        `cell_m` cube, with an identity sensorPose and label
///        kToolsCloudLabel. MRPT 2.5.8 inserts a CObservation3DRangeScan into
///        its maps only from points3D, and disagrees on the frame:
///        CPointsMap applies sensorPose, COctoMap does not (it takes points3D
///        as robot-frame; with CObservationPointCloud CPointsMap drops the
///        robot pose instead). An identity sensorPose is right for both.
///        Our own readers skip it (isToolsCloud()): they use the depth images.
/// @param cell_m > 0 [m]
mrpt::obs::CObservation3DRangeScan::Ptr makeToolsCloud(
    const mrpt::maps::CSimplePointsMap& robot_cloud, double cell_m,
    mrpt::Clock::time_point timestamp);

/// @brief sensorLabel of the keyframe slice for MRPT's 2D tools (makeToolsSlice()).
inline constexpr const char* kToolsSliceLabel = "VOXPLORE_SLICE";

/// @brief The 2D laser scan a simplemap keyframe carries for MRPT's 2D tools:
///        `rays` bearings over 360 deg from a sensor at (0, 0, z_m) on the
///        robot, each the nearest point of `robot_cloud` within +-band_m / 2
///        of z_m in its bearing bin (ranges in the plane), invalid where the
///        bin holds none or it is beyond max_range_m. MRPT 2.5.8's point maps
///        with isPlanarMap = true (the 2D-laser maps of its sample configs,
///        e.g. icp-slam_demo_with_octomap.ini) insert only such scans.
/// @param rays >= 2; z_m, band_m, max_range_m > 0
mrpt::obs::CObservation2DRangeScan::Ptr makeToolsSlice(
    const mrpt::maps::CSimplePointsMap& robot_cloud, double z_m, double band_m, int rays,
    double max_range_m, mrpt::Clock::time_point timestamp);

/// @brief True for the observation makeToolsCloud() makes (label
///        kToolsCloudLabel, points3D and no range image).
bool isToolsCloud(const mrpt::obs::CObservation3DRangeScan& obs);

/// @brief All CObservation3DRangeScan with a range image in a sensory frame.
std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> depthScansOf(const mrpt::obs::CSensoryFrame& sf);

/// @brief Every CObservation3DRangeScan of a sensory frame, with or without a
///        range image, except the keyframe clouds for MRPT's tools (isToolsCloud()).
std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> allDepthObservationsOf(
    const mrpt::obs::CSensoryFrame& sf);

/// @brief What checkDepthScan() found in one depth image.
struct DepthScanCheck
{
  std::string reason;             ///< why the camera cannot be used; empty: usable
  std::size_t returns = 0;        ///< non-zero pixels
  std::size_t impossible = 0;     ///< of them 0xFFFF or beyond the observation's maxRange
  bool usable() const { return reason.empty(); }
};

/// @brief Checks a depth image before any of it is unprojected: a range
///        image that is present and not empty, rangeUnits finite and > 0,
///        intrinsics finite with fx, fy > 0 and the range image's size,
///        sensorPose finite, at least one return, and at most
///        params.max_impossible_share of the returns impossible (0xFFFF, or
///        beyond obs.maxRange when that is finite and > 0). Non-finite values
///        would reach OctoMap's key computation (undefined behaviour) and
///        the metaview's hash grid.
/// @return the reason in DepthScanCheck::reason when the camera must be skipped
DepthScanCheck checkDepthScan(const mrpt::obs::CObservation3DRangeScan& obs, const CloudParams& params);

/// @brief A depth image a stop could not use as it was (one per camera).
struct CameraIssue
{
  std::string label;    ///< sensorLabel
  std::string reason;   ///< what is wrong
  bool skipped = true;  ///< false: used, with the impossible pixels dropped
};

/// @brief The depth images of a stop that pass checkDepthScan(), copies with
///        their impossible pixels set to 0 where there were some, and what
///        was wrong with the others.
struct UsableScans
{
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> scans;
  std::vector<CameraIssue> issues;
  std::size_t observations = 0;  ///< CObservation3DRangeScan in the frame (usable or not)
};

/// @brief checkDepthScan() over every CObservation3DRangeScan of `sf`.
UsableScans usableDepthScans(const mrpt::obs::CSensoryFrame& sf, const CloudParams& params);

/// @brief The robot's motion over `tau` seconds at the constant robot-frame
///        velocity `v` (the exact SE(2) exponential; tau < 0: backwards).
mrpt::poses::CPose2D motionOver(const mrpt::math::TTwist2D& v, double tau);

/// @brief Deskewing a scan taken while driving: every depth image of `scans`
///        timestamped before the odometry observation of `sf` gets the
///        sensorPose it had relative to the robot at the odometry's time:
///        motionOver(velocityLocal, t_camera - t_odometry) + sensorPose.
///        Those scans are replaced by moved copies (the frame's own stay as
///        they were). Nothing without a CObservationOdometry that has
///        velocities.
/// @return the number of depth images moved
std::size_t deskewScans(std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& scans,
                        const mrpt::obs::CSensoryFrame& sf);

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
