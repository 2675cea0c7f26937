#include <mrpt/obs/CObservation3DRangeScan.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/robot_cloud.h>

#include <cmath>

namespace voxplore::mapping
{
void CloudParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  common::requireValid(z_min_m < z_max_m, c, s, "z_min_m", "need z_min_m < z_max_m");
  common::requireValid(max_range_m > 0, c, s, "max_range_m", "must be positive");
}

void CloudParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> depthScansOf(const mrpt::obs::CSensoryFrame& sf)
{
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> out;
  for (const auto& o : sf)
    if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
      if (s->hasRangeImage) out.push_back(s);
  return out;
}

RobotCloud buildRobotCloud(
    const std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& scans, const CloudParams& params)
{
  RobotCloud rc;
  mrpt::maps::CSimplePointsMap cam_pts;
  mrpt::obs::T3DPointsProjectionParams pp;
  pp.takeIntoAccountSensorPoseOnRobot = true;  // robot frame: each camera's sensorPose applied
  const double max_range2 = params.max_range_m * params.max_range_m;
  for (const auto& scan : scans)
  {
    rc.cameras++;
    const auto& img = scan->rangeImage;
    std::size_t valid = 0;
    for (int r = 0; r < img.rows(); r++)
      for (int c = 0; c < img.cols(); c++) valid += img(r, c) != 0;
    rc.valid_pixels += valid;
    rc.invalid_pixels += static_cast<std::size_t>(img.rows() * img.cols()) - valid;

    cam_pts.clear();
    scan->unprojectInto(cam_pts, pp);  // skips zero (invalid) ranges
    const auto& sp = scan->sensorPose;
    const auto& xs = cam_pts.getPointsBufferRef_x();
    const auto& ys = cam_pts.getPointsBufferRef_y();
    const auto& zs = cam_pts.getPointsBufferRef_z();
    for (std::size_t i = 0; i < xs.size(); i++)
    {
      const float x = xs[i], y = ys[i], z = zs[i];
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      {
        rc.dropped_other++;
        continue;
      }
      const double dx = x - sp.x(), dy = y - sp.y(), dz = z - sp.z();
      if (dx * dx + dy * dy + dz * dz > max_range2 || z > params.z_max_m)
      {
        rc.dropped_other++;
        continue;
      }
      if (z < params.z_min_m)
      {
        rc.dropped_floor++;
        continue;
      }
      rc.points.insertPointFast(x, y, z);
    }
  }
  rc.points.mark_as_modified();
  return rc;
}

}  // namespace voxplore::mapping
