/* voxplore — trajectories in TUM format ("t x y z qx qy qz qw" per line). */
#pragma once

#include <mrpt/poses/CPose3D.h>

#include <fstream>
#include <string>
#include <vector>

namespace voxplore::common
{
/// @brief One timestamped pose.
struct StampedPose
{
  double t = 0;  ///< seconds
  mrpt::poses::CPose3D pose;
};

/// @brief Writes a TUM trajectory line by line (flushed, so a crash keeps what was written).
class TumWriter
{
 public:
  /// @throws std::runtime_error naming the path when it cannot be created.
  explicit TumWriter(const std::string& path);
  void write(double t, const mrpt::poses::CPose3D& pose);

 private:
  std::string path_;
  std::ofstream out_;
};

/// @brief Reads a TUM trajectory ('#' comments allowed).
/// @throws std::runtime_error naming the file and line on malformed input.
std::vector<StampedPose> readTum(const std::string& path);

}  // namespace voxplore::common
