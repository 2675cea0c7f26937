#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/robot_cloud.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <unordered_set>
#include <vector>

namespace voxplore::mapping
{
void CloudParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_impossible_share, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tools_cloud_cell_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tools_slice_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(deskew, bool, c, s);
  common::requireValid(z_min_m < z_max_m, c, s, "z_min_m", "need z_min_m < z_max_m");
  common::requireValid(max_range_m > 0, c, s, "max_range_m", "must be positive");
  common::requireValid(max_impossible_share >= 0 && max_impossible_share <= 1, c, s,
                       "max_impossible_share", "must be in [0, 1]");
  common::requireValid(
      tools_cloud_cell_m == 0 || (tools_cloud_cell_m >= 0.01 && tools_cloud_cell_m <= 1.0), c, s,
      "tools_cloud_cell_m", "must be 0 (off) or in [0.01, 1] m");
  common::requireValid(tools_slice_z_m == 0 || (tools_slice_z_m > z_min_m && tools_slice_z_m < z_max_m),
                       c, s, "tools_slice_z_m", "must be 0 (off) or between z_min_m and z_max_m");
}

void CloudParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_impossible_share, c, s);
  MRPT_SAVE_CONFIG_VAR(tools_cloud_cell_m, c, s);
  MRPT_SAVE_CONFIG_VAR(tools_slice_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(deskew, c, s);
}

mrpt::obs::CObservation3DRangeScan::Ptr makeToolsCloud(
    const mrpt::maps::CSimplePointsMap& robot_cloud, double cell_m,
    mrpt::Clock::time_point timestamp)
{
  ASSERTMSG_(cell_m > 0, "makeToolsCloud: cell_m must be positive");
  auto obs = mrpt::obs::CObservation3DRangeScan::Create();
  obs->sensorLabel = kToolsCloudLabel;
  obs->timestamp = timestamp;
  obs->sensorPose = mrpt::poses::CPose3D();  // points3D are robot-frame (see the header)
  obs->hasRangeImage = false;
  const auto& xs = robot_cloud.getPointsBufferRef_x();
  const auto& ys = robot_cloud.getPointsBufferRef_y();
  const auto& zs = robot_cloud.getPointsBufferRef_z();
  std::unordered_set<std::uint64_t> cells;
  cells.reserve(xs.size() / 4 + 1);
  std::vector<std::size_t> keep;
  const double inv = 1.0 / cell_m;
  // 21 bits per axis: +-104 km at 0.1 m cells, far beyond any depth camera.
  const auto key = [inv](float v)
  {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v * inv)) + (1 << 20)) &
           0x1FFFFF;
  };
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    if (cells.insert((key(xs[i]) << 42) | (key(ys[i]) << 21) | key(zs[i])).second)
      keep.push_back(i);
  }
  obs->resizePoints3DVectors(keep.size());  // also the (unused, zero) pixel indices
  for (std::size_t j = 0; j < keep.size(); j++)
  {
    obs->points3D_x[j] = xs[keep[j]];
    obs->points3D_y[j] = ys[keep[j]];
    obs->points3D_z[j] = zs[keep[j]];
    obs->points3D_idxs_x[j] = 0;
    obs->points3D_idxs_y[j] = 0;
  }
  obs->hasPoints3D = !keep.empty();
  return obs;
}

mrpt::obs::CObservation2DRangeScan::Ptr makeToolsSlice(
    const mrpt::maps::CSimplePointsMap& robot_cloud, double z_m, double band_m, int rays,
    double max_range_m, mrpt::Clock::time_point timestamp)
{
  ASSERTMSG_(rays >= 2 && z_m > 0 && band_m > 0 && max_range_m > 0,
             "makeToolsSlice: need rays >= 2 and positive z_m, band_m, max_range_m");
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->sensorLabel = kToolsSliceLabel;
  scan->timestamp = timestamp;
  scan->sensorPose = mrpt::poses::CPose3D(0, 0, z_m, 0, 0, 0);
  scan->rightToLeft = true;
  // Ray i at -aperture/2 + i * aperture / (rays - 1): with this aperture the
  // rays are 2 pi / rays apart and the first and last do not coincide.
  const double step = 2.0 * M_PI / rays;
  scan->aperture = static_cast<float>(step * (rays - 1));
  scan->maxRange = static_cast<float>(max_range_m);
  scan->stdError = 0.01f;
  scan->resizeScan(static_cast<std::size_t>(rays));
  std::vector<float> best(static_cast<std::size_t>(rays), std::numeric_limits<float>::infinity());
  const auto& xs = robot_cloud.getPointsBufferRef_x();
  const auto& ys = robot_cloud.getPointsBufferRef_y();
  const auto& zs = robot_cloud.getPointsBufferRef_z();
  const double first = -0.5 * step * (rays - 1);
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    if (std::abs(zs[i] - z_m) > 0.5 * band_m) continue;
    const double r = std::hypot(xs[i], ys[i]);
    if (!(r > 0) || r > max_range_m) continue;
    const double a = std::atan2(ys[i], xs[i]);
    const long k = std::lround((a - first) / step);
    const auto bin = static_cast<std::size_t>(((k % rays) + rays) % rays);
    best[bin] = std::min(best[bin], static_cast<float>(r));
  }
  for (std::size_t i = 0; i < best.size(); i++)
  {
    const bool valid = std::isfinite(best[i]);
    scan->setScanRange(i, valid ? best[i] : static_cast<float>(max_range_m));
    scan->setScanRangeValidity(i, valid);
  }
  return scan;
}

bool isToolsCloud(const mrpt::obs::CObservation3DRangeScan& obs)
{
  return !obs.hasRangeImage && obs.sensorLabel == kToolsCloudLabel;
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> depthScansOf(const mrpt::obs::CSensoryFrame& sf)
{
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> out;
  for (const auto& o : sf)
    if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
      if (s->hasRangeImage) out.push_back(s);
  return out;
}

std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> allDepthObservationsOf(
    const mrpt::obs::CSensoryFrame& sf)
{
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> out;
  for (const auto& o : sf)
    if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
      if (!isToolsCloud(*s)) out.push_back(s);
  return out;
}

namespace
{
bool finite(double v) { return std::isfinite(v); }

/// Range (or depth) beyond which a return is impossible for this sensor; +inf
/// when the observation does not say (maxRange not finite or not positive).
double impossibleAbove(const mrpt::obs::CObservation3DRangeScan& obs)
{
  if (!(std::isfinite(obs.maxRange) && obs.maxRange > 0))
    return std::numeric_limits<double>::infinity();
  // 2 % and one quantisation step of tolerance for range noise and rounding.
  return 1.02 * obs.maxRange + obs.rangeUnits;
}

constexpr uint16_t kSaturated = 0xFFFF;

/// Structure of the observation (no pixel read). Empty when fine.
std::string structuralFault(const mrpt::obs::CObservation3DRangeScan& obs)
{
  std::ostringstream why;
  const auto& cam = obs.cameraParams;
  const auto& sp = obs.sensorPose;
  if (!obs.hasRangeImage)
    why << "no range image (hasRangeImage = false)";
  else if (obs.rangeImage.rows() <= 0 || obs.rangeImage.cols() <= 0)
    why << "empty range image";
  else if (!(finite(obs.rangeUnits) && obs.rangeUnits > 0))
    why << "rangeUnits = " << obs.rangeUnits << " (must be finite and > 0)";
  else if (!(finite(cam.fx()) && finite(cam.fy()) && cam.fx() > 0 && cam.fy() > 0 &&
             finite(cam.cx()) && finite(cam.cy())))
    why << "intrinsics fx = " << cam.fx() << ", fy = " << cam.fy() << ", cx = " << cam.cx()
        << ", cy = " << cam.cy() << " (need finite values, fx, fy > 0)";
  else if (cam.ncols != static_cast<uint32_t>(obs.rangeImage.cols()) ||
           cam.nrows != static_cast<uint32_t>(obs.rangeImage.rows()))
    why << "range image " << obs.rangeImage.cols() << " x " << obs.rangeImage.rows()
        << " px but intrinsics for " << cam.ncols << " x " << cam.nrows << " px";
  else
  {
    bool ok = finite(sp.x()) && finite(sp.y()) && finite(sp.z());
    const auto R = sp.getRotationMatrix();
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) ok = ok && finite(R(i, j));
    if (!ok) why << "sensorPose not finite: " << sp.asString();
  }
  return why.str();
}
}  // namespace

DepthScanCheck checkDepthScan(const mrpt::obs::CObservation3DRangeScan& obs, const CloudParams& params)
{
  DepthScanCheck chk;
  chk.reason = structuralFault(obs);
  if (!chk.usable()) return chk;
  const double limit = impossibleAbove(obs);
  const auto& img = obs.rangeImage;
  for (int r = 0; r < img.rows(); r++)
    for (int c = 0; c < img.cols(); c++)
    {
      const uint16_t v = img(r, c);
      if (v == 0) continue;
      chk.returns++;
      chk.impossible += v == kSaturated || v * static_cast<double>(obs.rangeUnits) > limit;
    }
  std::ostringstream why;
  if (chk.returns == 0)
    why << "no return in any of its " << img.rows() * img.cols() << " pixels";
  else if (chk.impossible > params.max_impossible_share * static_cast<double>(chk.returns))
    why << chk.impossible << " of " << chk.returns
        << " returns impossible (0xFFFF or beyond its maxRange = " << obs.maxRange
        << " m): more than max_impossible_share = " << params.max_impossible_share;
  chk.reason = why.str();
  return chk;
}

UsableScans usableDepthScans(const mrpt::obs::CSensoryFrame& sf, const CloudParams& params)
{
  UsableScans out;
  for (const auto& scan : allDepthObservationsOf(sf))
  {
    out.observations++;
    const auto chk = checkDepthScan(*scan, params);
    const std::string label = scan->sensorLabel.empty() ? "(no label)" : scan->sensorLabel;
    if (!chk.usable())
    {
      out.issues.push_back({label, chk.reason, true});
      continue;
    }
    if (chk.impossible == 0)
    {
      out.scans.push_back(scan);
      continue;
    }
    // A copy with the impossible returns set to 0 (no return): neither a
    // point nor a free-space ray. The original stays untouched (keyframes).
    auto clean = std::make_shared<mrpt::obs::CObservation3DRangeScan>(*scan);
    const double limit = impossibleAbove(*scan);
    auto& img = clean->rangeImage;
    for (int r = 0; r < img.rows(); r++)
      for (int c = 0; c < img.cols(); c++)
        if (img(r, c) == kSaturated || img(r, c) * static_cast<double>(clean->rangeUnits) > limit)
          img(r, c) = 0;
    out.issues.push_back({label,
                          std::to_string(chk.impossible) + " of " + std::to_string(chk.returns) +
                              " returns impossible (0xFFFF or beyond its maxRange): dropped",
                          false});
    out.scans.push_back(clean);
  }
  return out;
}

mrpt::poses::CPose2D motionOver(const mrpt::math::TTwist2D& v, double tau)
{
  const double th = v.omega * tau;
  if (std::abs(th) < 1e-9) return mrpt::poses::CPose2D(v.vx * tau, v.vy * tau, th);
  const double s = std::sin(th), c1 = 1.0 - std::cos(th);
  return mrpt::poses::CPose2D((v.vx * s - v.vy * c1) / v.omega, (v.vx * c1 + v.vy * s) / v.omega,
                              th);
}

std::size_t deskewScans(std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>& scans,
                        const mrpt::obs::CSensoryFrame& sf)
{
  const auto odo = sf.getObservationByClass<mrpt::obs::CObservationOdometry>();
  if (!odo || !odo->hasVelocities) return 0;
  const double t0 = mrpt::Clock::toDouble(odo->timestamp);
  std::size_t moved = 0;
  for (auto& scan : scans)
  {
    const double tau = mrpt::Clock::toDouble(scan->timestamp) - t0;
    if (tau >= 0) continue;
    auto copy = std::make_shared<mrpt::obs::CObservation3DRangeScan>(*scan);
    copy->sensorPose = mrpt::poses::CPose3D(motionOver(odo->velocityLocal, tau)) + scan->sensorPose;
    scan = copy;
    moved++;
  }
  return moved;
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
    // MRPT 2.5.8's unprojectInto also fills the observation's own points3D
    // (x, y, z, pixel indices). The scan lives on as a .simplemap keyframe:
    // free them (heaptrack, willowgarage: 110 MiB after 377 stops, growing
    // with every stop; the depth image is all the keyframe needs).
    std::vector<float>().swap(scan->points3D_x);
    std::vector<float>().swap(scan->points3D_y);
    std::vector<float>().swap(scan->points3D_z);
    std::vector<uint16_t>().swap(scan->points3D_idxs_x);
    std::vector<uint16_t>().swap(scan->points3D_idxs_y);
    scan->hasPoints3D = false;
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
