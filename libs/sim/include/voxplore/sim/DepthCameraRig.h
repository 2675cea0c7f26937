/* voxplore — simulated ToF depth cameras (default: 8 x ifm O3D100 around the omniRob). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

namespace voxplore::sim
{
class RayCaster;

/// @brief Intrinsics, noise and mounting of the depth cameras. ini section [cameras].
///
/// Noise: the O3D100 datasheet gives a repeatability of a few millimetres to
/// about 1 cm (1 sigma) at 1-5 m for bright targets; the default
/// range_noise_sigma_m = 0.01 m plus range_noise_sigma_per_m = 0.002 (per
/// metre of range) sits at the pessimistic end, which is what made the thesis
/// use z_min = 0.10 m (thesis 5.3.3).
struct CameraRigParams : public mrpt::config::CLoadableOptions
{
  int width_px = 64;        ///< image columns (O3D100: 64)
  int height_px = 48;       ///< image rows (O3D100: 48)
  double hfov = mrpt::DEG2RAD(40.0);  ///< horizontal field of view [rad] (ini: degrees)
  double vfov = mrpt::DEG2RAD(30.0);  ///< vertical field of view [rad] (ini: degrees)
  double min_range_m = 0.12;  ///< closer returns are invalid (0) [m]
  double max_range_m = 7.0;   ///< farther returns / no return are invalid (0) [m]
  double range_noise_sigma_m = 0.01;      ///< Gaussian range noise, constant part [m]
  double range_noise_sigma_per_m = 0.002; ///< Gaussian range noise, part proportional to range [m/m]
  double range_units_m = 0.001;  ///< quantisation of the uint16 range image [m]
  int num_cameras = 8;           ///< number of cameras; camN_pose for N < num_cameras
  /// T_robot_camera of each camera: x y z [m] yaw pitch roll [rad] (ini:
  /// "camN_pose = x y z yaw_deg pitch_deg roll_deg"). MRPT camera frame: +X
  /// depth, +Y left, +Z up; positive pitch looks down.
  std::vector<mrpt::poses::CPose3D> mounts;

  CameraRigParams();  ///< the omniRob ring (see ringAround)

  /// @brief The thesis' ring: yaws 0, +-40, +-90, +-140, 180 deg, cameras on
  ///        the border of a length x width footprint at `height_m`, pitched
  ///        down by half the vertical FoV so the top row is horizontal.
  static std::vector<mrpt::poses::CPose3D> ringAround(
      double length_m, double width_m, double height_m, double vfov_rad);

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;

  /// @brief Pinhole intrinsics with fx, fy from the FoV and the principal
  ///        point at the image centre ((w-1)/2, (h-1)/2).
  mrpt::img::TCamera intrinsics() const;
};

/// @brief Renders depth images of all cameras by ray casting. Keeps the per
///        pixel ray directions precomputed.
class DepthCameraRig
{
 public:
  explicit DepthCameraRig(const CameraRigParams& params);

  const CameraRigParams& params() const { return params_; }

  /// @brief One CObservation3DRangeScan per camera (range image only, no
  ///        points3D), range_is_depth = true, labelled "CAM<i>", timestamped `t`.
  /// @param T_world_robot 3D pose of the robot base (z = 0 on the floor)
  /// @param rng noise source; ignored when `noise` is false
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> scan(
      const RayCaster& caster, const mrpt::poses::CPose3D& T_world_robot,
      mrpt::Clock::time_point t, std::mt19937_64& rng, bool noise = true) const;

  /// @brief scan() with each camera exposed at its own robot pose and time
  ///        (a robot that moves during the exposures): camera c from
  ///        T_world_robot[c], timestamped t[c]; one entry per camera.
  /// @throws std::invalid_argument when a vector does not hold num_cameras entries.
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> scan(
      const RayCaster& caster, const std::vector<mrpt::poses::CPose3D>& T_world_robot,
      const std::vector<mrpt::Clock::time_point>& t, std::mt19937_64& rng, bool noise = true) const;

  /// @brief Per-pixel direction in the camera frame, x component 1 (so the ray
  ///        parameter is the depth), row-major (v * width + u).
  const std::vector<Eigen::Vector3f>& pixelDirections() const { return dirs_cam_; }

 private:
  CameraRigParams params_;
  mrpt::img::TCamera intrinsics_;
  std::vector<Eigen::Vector3f> dirs_cam_;
};

}  // namespace voxplore::sim
