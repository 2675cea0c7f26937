#include <mrpt/math/CQuaternion.h>
#include <voxplore/common/config.h>
#include <voxplore/common/trajectory_io.h>

#include <iomanip>
#include <stdexcept>

namespace voxplore::common
{
TumWriter::TumWriter(const std::string& path) : path_(path), out_(path)
{
  if (!out_) throw std::runtime_error("cannot write trajectory file '" + path + "'");
  out_ << "# timestamp tx ty tz qx qy qz qw\n";
}

void TumWriter::write(double t, const mrpt::poses::CPose3D& pose)
{
  mrpt::math::CQuaternionDouble q;
  pose.getAsQuaternion(q);
  out_ << std::fixed << std::setprecision(6) << t << std::setprecision(6) << " " << pose.x()
       << " " << pose.y() << " " << pose.z() << std::setprecision(9) << " " << q.x() << " "
       << q.y() << " " << q.z() << " " << q.r() << "\n";
  out_.flush();
  if (!out_) throw std::runtime_error("write failed: '" + path_ + "'");
}

std::vector<StampedPose> readTum(const std::string& path)
{
  std::ifstream f(path);
  if (!f) throw std::runtime_error("trajectory file not found or unreadable: '" + path + "'");
  std::vector<StampedPose> out;
  std::string line;
  for (int lineno = 1; std::getline(f, line); lineno++)
  {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const auto v = parseNumberList(line, path + ":" + std::to_string(lineno));
    if (v.empty()) continue;
    if (v.size() != 8)
      throw std::runtime_error(path + ":" + std::to_string(lineno) +
                               ": expected 't x y z qx qy qz qw'");
    const mrpt::math::CQuaternionDouble q(v[7], v[4], v[5], v[6]);
    out.push_back({v[0], mrpt::poses::CPose3D(q, v[1], v[2], v[3])});
  }
  return out;
}

}  // namespace voxplore::common
