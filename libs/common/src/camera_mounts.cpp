#include <voxplore/common/camera_mounts.h>
#include <voxplore/common/config.h>

#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace voxplore::common
{
using mrpt::poses::CPose3D;

std::vector<CPose3D> cameraRing(double length_m, double width_m, double height_m, double vfov_rad)
{
  const double yaws_deg[] = {0, 40, -40, 90, -90, 140, -140, 180};
  const double hl = 0.5 * length_m, hw = 0.5 * width_m;
  std::vector<CPose3D> out;
  for (double yd : yaws_deg)
  {
    const double yaw = mrpt::DEG2RAD(yd);
    const double c = std::cos(yaw), s = std::sin(yaw);
    const double tx = std::abs(c) > 1e-9 ? hl / std::abs(c) : std::numeric_limits<double>::max();
    const double ty = std::abs(s) > 1e-9 ? hw / std::abs(s) : std::numeric_limits<double>::max();
    const double t = std::min(tx, ty);
    out.emplace_back(t * c, t * s, height_m, yaw, 0.5 * vfov_rad, 0.0);
  }
  return out;
}

bool mountsSymmetricUnderHalfTurn(const std::vector<CPose3D>& mounts)
{
  const CPose3D half_turn(0, 0, 0, M_PI, 0, 0);
  return std::all_of(mounts.begin(), mounts.end(), [&](const CPose3D& m) {
    const CPose3D t = half_turn + m;
    return std::any_of(mounts.begin(), mounts.end(), [&](const CPose3D& o) {
      const CPose3D d = o - t;  // t's frame to o's
      return d.translation().norm() <= 1e-3 &&
             std::abs(mrpt::math::wrapToPi(d.yaw())) <= mrpt::DEG2RAD(0.1) &&
             std::abs(mrpt::math::wrapToPi(d.pitch())) <= mrpt::DEG2RAD(0.1) &&
             std::abs(mrpt::math::wrapToPi(d.roll())) <= mrpt::DEG2RAD(0.1);
    });
  });
}

std::string cameraPoseKey(int i) { return "cam" + std::to_string(i) + "_pose"; }

void loadCameraMounts(
    const mrpt::config::CConfigFileBase& c, const std::string& s, int num_cameras,
    std::vector<CPose3D>& mounts)
{
  int given = 0;
  for (int i = 0; i < num_cameras; i++) given += c.keyExists(s, cameraPoseKey(i)) ? 1 : 0;
  if (given == 0)
  {
    requireValid(num_cameras == static_cast<int>(mounts.size()), c, s, "num_cameras",
                 "differs from the " + std::to_string(mounts.size()) +
                     " default cameras: give camN_pose = x y z yaw_deg pitch_deg roll_deg for "
                     "every camera");
    return;
  }
  std::vector<CPose3D> out(num_cameras);
  for (int i = 0; i < num_cameras; i++)
  {
    const std::string key = cameraPoseKey(i);
    if (!c.keyExists(s, key))
      throw std::runtime_error(configSourceName(c) + ": [" + s + "] " + key +
                               " missing: when any camN_pose is given, give all " +
                               std::to_string(num_cameras) + " (x y z yaw_deg pitch_deg roll_deg)");
    const auto v = parseNumberList(c.read_string(s, key, ""),
                                   configSourceName(c) + ": [" + s + "] " + key);
    requireValid(v.size() == 6, c, s, key, "expected 'x y z yaw_deg pitch_deg roll_deg'");
    out[i] = CPose3D(v[0], v[1], v[2], mrpt::DEG2RAD(v[3]), mrpt::DEG2RAD(v[4]),
                     mrpt::DEG2RAD(v[5]));
  }
  mounts = std::move(out);
}

void saveCameraMounts(
    mrpt::config::CConfigFileBase& c, const std::string& s, const std::vector<CPose3D>& mounts)
{
  for (std::size_t i = 0; i < mounts.size(); i++)
  {
    const auto& m = mounts[i];
    std::ostringstream os;
    os.precision(12);
    os << m.x() << " " << m.y() << " " << m.z() << " " << mrpt::RAD2DEG(m.yaw()) << " "
       << mrpt::RAD2DEG(m.pitch()) << " " << mrpt::RAD2DEG(m.roll());
    c.write(s, cameraPoseKey(static_cast<int>(i)), os.str());
  }
}

}  // namespace voxplore::common
