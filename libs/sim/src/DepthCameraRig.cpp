#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/common/camera_mounts.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>

#include <cmath>
#include <limits>
#include <sstream>

namespace voxplore::sim
{
using mrpt::poses::CPose3D;

CameraRigParams::CameraRigParams() : mounts(ringAround(1.2, 0.712, 0.60, vfov)) {}

std::vector<CPose3D> CameraRigParams::ringAround(
    double length_m, double width_m, double height_m, double vfov_rad)
{
  return common::cameraRing(length_m, width_m, height_m, vfov_rad);
}

void CameraRigParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(width_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(hfov, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(vfov, c, s);
  MRPT_LOAD_CONFIG_VAR(min_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(range_noise_sigma_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(range_noise_sigma_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(range_units_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(num_cameras, int, c, s);
  using common::requireValid;
  requireValid(width_px > 0 && height_px > 0, c, s, "width_px", "image size must be positive");
  requireValid(hfov > 0 && hfov < M_PI, c, s, "hfov", "must be in (0, 180) deg");
  requireValid(vfov > 0 && vfov < M_PI, c, s, "vfov", "must be in (0, 180) deg");
  requireValid(min_range_m >= 0 && min_range_m < max_range_m, c, s, "min_range_m",
               "need 0 <= min_range_m < max_range_m");
  requireValid(range_noise_sigma_m >= 0, c, s, "range_noise_sigma_m", "must be >= 0");
  requireValid(range_noise_sigma_per_m >= 0, c, s, "range_noise_sigma_per_m", "must be >= 0");
  requireValid(range_units_m > 0 && max_range_m / range_units_m < 65535, c, s, "range_units_m",
               "must be > 0 and max_range_m / range_units_m must fit in uint16");
  requireValid(num_cameras > 0, c, s, "num_cameras", "need at least one camera");
  common::loadCameraMounts(c, s, num_cameras, mounts);
}

void CameraRigParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(width_px, c, s);
  MRPT_SAVE_CONFIG_VAR(height_px, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(hfov, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(vfov, c, s);
  MRPT_SAVE_CONFIG_VAR(min_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(range_noise_sigma_m, c, s);
  MRPT_SAVE_CONFIG_VAR(range_noise_sigma_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR(range_units_m, c, s);
  MRPT_SAVE_CONFIG_VAR(num_cameras, c, s);
  common::saveCameraMounts(c, s, mounts);
}

mrpt::img::TCamera CameraRigParams::intrinsics() const
{
  mrpt::img::TCamera cam;
  cam.ncols = static_cast<uint32_t>(width_px);
  cam.nrows = static_cast<uint32_t>(height_px);
  const double fx = 0.5 * width_px / std::tan(0.5 * hfov);
  const double fy = 0.5 * height_px / std::tan(0.5 * vfov);
  cam.setIntrinsicParamsFromValues(fx, fy, 0.5 * (width_px - 1), 0.5 * (height_px - 1));
  cam.focalLengthMeters = 0.0;
  return cam;
}

DepthCameraRig::DepthCameraRig(const CameraRigParams& params)
    : params_(params), intrinsics_(params.intrinsics())
{
  ASSERTMSG_(
      static_cast<int>(params_.mounts.size()) == params_.num_cameras,
      "CameraRigParams: mounts.size() must equal num_cameras");
  const double fx = intrinsics_.fx(), fy = intrinsics_.fy();
  const double cx = intrinsics_.cx(), cy = intrinsics_.cy();
  dirs_cam_.reserve(static_cast<std::size_t>(params_.width_px * params_.height_px));
  // MRPT's 3D range scan frame: +X depth, +Y left, +Z up; image u grows to the
  // right (-Y), v grows down (-Z). x = 1 makes the ray parameter the depth.
  for (int v = 0; v < params_.height_px; v++)
    for (int u = 0; u < params_.width_px; u++)
      dirs_cam_.emplace_back(1.0f, static_cast<float>((cx - u) / fx),
                             static_cast<float>((cy - v) / fy));
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> DepthCameraRig::scan(
    const RayCaster& caster, const CPose3D& T_world_robot, mrpt::Clock::time_point t,
    std::mt19937_64& rng, bool noise) const
{
  const auto n = static_cast<std::size_t>(params_.num_cameras);
  return scan(caster, std::vector<CPose3D>(n, T_world_robot),
              std::vector<mrpt::Clock::time_point>(n, t), rng, noise);
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> DepthCameraRig::scan(
    const RayCaster& caster, const std::vector<CPose3D>& T_world_robot,
    const std::vector<mrpt::Clock::time_point>& t, std::mt19937_64& rng, bool noise) const
{
  if (T_world_robot.size() != static_cast<std::size_t>(params_.num_cameras) ||
      t.size() != T_world_robot.size())
    throw std::invalid_argument("DepthCameraRig::scan: one robot pose and one time per camera");
  const int W = params_.width_px, H = params_.height_px;
  const std::size_t n = dirs_cam_.size();
  std::vector<Eigen::Vector3f> dirs_world(n);
  std::vector<float> depth(n);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double units = params_.range_units_m;
  const double max_sigma = params_.range_noise_sigma_m +
                           params_.range_noise_sigma_per_m * params_.max_range_m;
  const double cast_max_range = params_.max_range_m + (noise ? 5.0 * max_sigma : 0.0);

  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> out;
  for (int c = 0; c < params_.num_cameras; c++)
  {
    const CPose3D T_world_cam = T_world_robot[c] + params_.mounts[c];
    const Eigen::Matrix3f R = T_world_cam.getRotationMatrix().asEigen().cast<float>();
    const Eigen::Vector3f origin(
        static_cast<float>(T_world_cam.x()), static_cast<float>(T_world_cam.y()),
        static_cast<float>(T_world_cam.z()));
    for (std::size_t i = 0; i < n; i++) dirs_world[i] = R * dirs_cam_[i];
    // t along a direction with camera-frame x = 1 is the depth; the farthest
    // useful depth of any pixel is the range limit (|dir| >= 1).
    caster.castFan(origin, dirs_world.data(), n, 0.0f, static_cast<float>(cast_max_range),
                   depth.data());

    auto obs = mrpt::obs::CObservation3DRangeScan::Create();
    obs->sensorLabel = "CAM" + std::to_string(c);
    obs->timestamp = t[c];
    obs->hasRangeImage = true;
    obs->range_is_depth = true;
    obs->rangeUnits = static_cast<float>(units);
    obs->rangeImage_setSize(H, W);
    obs->cameraParams = intrinsics_;
    obs->cameraParamsIntensity = intrinsics_;
    obs->maxRange = static_cast<float>(params_.max_range_m);
    obs->stdError = static_cast<float>(params_.range_noise_sigma_m);
    obs->sensorPose = params_.mounts[c];
    for (int v = 0; v < H; v++)
    {
      for (int u = 0; u < W; u++)
      {
        const std::size_t i = static_cast<std::size_t>(v * W + u);
        uint16_t q = 0;  // 0 = invalid: no return or out of range, as the real sensor
        if (std::isfinite(depth[i]))
        {
          const double ray_norm = dirs_cam_[i].norm();
          double range = depth[i] * ray_norm;
          if (noise)
            range += (params_.range_noise_sigma_m + params_.range_noise_sigma_per_m * range) *
                     gauss(rng);
          if (range >= params_.min_range_m && range <= params_.max_range_m)
            q = static_cast<uint16_t>(std::lround(range / ray_norm / units));
        }
        obs->rangeImage(v, u) = q;
      }
    }
    out.push_back(obs);
  }
  return out;
}

}  // namespace voxplore::sim
