/* voxplore — scan rating: parameters, virtual beams and the choice of the
 * best-rated pose (thesis 4.5.4 "Scan Rating"). */
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>
#include <voxplore/common/camera_mounts.h>
#include <voxplore/common/config.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scan_rating_beams.h"

namespace voxplore::exploration
{
using mrpt::poses::CPose3D;


ScanRatingParams::ScanRatingParams() : mounts(common::cameraRing(1.2, 0.712, 0.60, vfov)) {}

void ScanRatingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                          const std::string& s)
{
  int num_cameras = static_cast<int>(mounts.size());
  MRPT_LOAD_CONFIG_VAR(beam_reduction, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(th_occ, int, c, s);
  MRPT_LOAD_CONFIG_VAR(width_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR(height_px, int, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(hfov, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(vfov, c, s);
  MRPT_LOAD_CONFIG_VAR(count_z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(count_z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(num_cameras, int, c, s);
  using common::requireValid;
  requireValid(beam_reduction >= 1, c, s, "beam_reduction", "must be >= 1");
  requireValid(max_range_m > 0, c, s, "max_range_m", "must be > 0");
  requireValid(th_occ >= 0 && th_occ <= 255, c, s, "th_occ", "must be in 0..255");
  requireValid(width_px > 0, c, s, "width_px", "must be > 0");
  requireValid(height_px > 0, c, s, "height_px", "must be > 0");
  requireValid(hfov > 0 && hfov < M_PI, c, s, "hfov", "must be in (0, 180) deg");
  requireValid(vfov > 0 && vfov < M_PI, c, s, "vfov", "must be in (0, 180) deg");
  requireValid(num_cameras > 0, c, s, "num_cameras", "need at least one camera");
  common::loadCameraMounts(c, s, num_cameras, mounts);
}

void ScanRatingParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                        const std::string& s) const
{
  const int num_cameras = static_cast<int>(mounts.size());
  MRPT_SAVE_CONFIG_VAR(beam_reduction, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(th_occ, c, s);
  MRPT_SAVE_CONFIG_VAR(width_px, c, s);
  MRPT_SAVE_CONFIG_VAR(height_px, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(hfov, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(vfov, c, s);
  MRPT_SAVE_CONFIG_VAR(count_z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(count_z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(num_cameras, c, s);
  common::saveCameraMounts(c, s, mounts);
}

namespace detail
{
void countBandKeys(const octomap::OcTree& V, const ScanRatingParams& p, uint32_t kz[2])
{
  const double half = V.getResolution() * double(1u << (V.getTreeDepth() - 1));
  const auto key = [&](double z) { return V.coordToKey(std::clamp(z, -half + 1e-9, half - 1e-9)); };
  kz[0] = key(p.count_z_min_m);
  kz[1] = key(p.count_z_max_m);
}

void checkRatingParams(const ScanRatingParams& p)
{
  auto require = [](bool ok, const char* what)
  {
    if (!ok) throw std::invalid_argument(std::string("ScanRatingParams: ") + what);
  };
  require(!p.mounts.empty(), "mounts is empty (need at least one camera)");
  require(p.beam_reduction >= 1, "beam_reduction must be >= 1");
  require(p.max_range_m > 0 && std::isfinite(p.max_range_m), "max_range_m must be > 0");
  require(p.width_px > 0 && p.height_px > 0, "width_px and height_px must be > 0");
  require(p.hfov > 0 && p.hfov < M_PI && p.vfov > 0 && p.vfov < M_PI,
          "hfov and vfov must be in (0, pi)");
  require(p.th_occ >= 0 && p.th_occ <= 255, "th_occ must be in 0..255");
  require(std::isfinite(p.count_z_min_m) && std::isfinite(p.count_z_max_m),
          "count_z_min_m and count_z_max_m must be finite");
}

void virtualBeams(const mrpt::poses::CPose2D& pose, const ScanRatingParams& p,
                  std::vector<VirtualBeam>& out)
{
  // MRPT depth-camera frame: +X forward, +Y left, +Z up; u grows to the right
  // (-Y), v grows down (-Z); same intrinsics as sim::CameraRigParams.
  const double fx = 0.5 * p.width_px / std::tan(0.5 * p.hfov);
  const double fy = 0.5 * p.height_px / std::tan(0.5 * p.vfov);
  const double cx = 0.5 * (p.width_px - 1), cy = 0.5 * (p.height_px - 1);
  const int r = p.beam_reduction;
  out.clear();
  out.reserve(static_cast<std::size_t>((p.width_px + r - 1) / r) *
              static_cast<std::size_t>((p.height_px + r - 1) / r) * p.mounts.size());
  const CPose3D T_world_robot(pose);  // robot on the floor, z = 0
  for (const CPose3D& T_robot_camera : p.mounts)
  {
    const CPose3D T_world_camera = T_world_robot + T_robot_camera;
    const auto R = T_world_camera.getRotationMatrix();
    const double tx = T_world_camera.x(), ty = T_world_camera.y(), tz = T_world_camera.z();
    const octomap::point3d origin(static_cast<float>(tx), static_cast<float>(ty),
                                  static_cast<float>(tz));
    for (int v = 0; v < p.height_px; v += r)
    {
      for (int u = 0; u < p.width_px; u += r)
      {
        // end = T_world_camera * (k (1, dy, dz)), k = max_range / |(1, dy, dz)|
        const double dy = (cx - u) / fx, dz = (cy - v) / fy;
        const double k = p.max_range_m / std::sqrt(1.0 + dy * dy + dz * dz);
        const double lx = k, ly = dy * k, lz = dz * k;
        const double ex = R(0, 0) * lx + R(0, 1) * ly + R(0, 2) * lz;
        const double ey = R(1, 0) * lx + R(1, 1) * ly + R(1, 2) * lz;
        const double ez = R(2, 0) * lx + R(2, 1) * ly + R(2, 2) * lz;
        out.push_back({origin, octomap::point3d(static_cast<float>(tx + ex),
                                                static_cast<float>(ty + ey),
                                                static_cast<float>(tz + ez))});
      }
    }
  }
}
}  // namespace detail

std::optional<std::size_t> bestRated(const std::vector<ScanRating>& ratings)
{
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < ratings.size(); i++)
  {
    const double g = ratings[i].gain;
    if (!(g > 0)) continue;  // 0 (nothing to learn) or NaN never wins
    if (!best)
    {
      best = i;
      continue;
    }
    const double gb = ratings[*best].gain;
    // A tie (within 1e-9 relative) keeps the lower index: the sampler's order.
    if (g > gb && g - gb > 1e-9 * std::max(g, gb)) best = i;
  }
  return best;
}

}  // namespace voxplore::exploration
