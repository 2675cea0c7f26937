/* voxplore tests — small worlds built in code, data paths, and file readers. */
#pragma once

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>
#include <voxplore/sim/World.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace voxplore::test
{
/// Project source directory (compile definition).
inline std::string sourceDir() { return VOXPLORE_SOURCE_DIR; }
/// ../shared/worlds beside the checkout (may be missing).
inline std::string sharedWorldsDir() { return VOXPLORE_SHARED_WORLDS_DIR; }

/// @brief A path for a scratch file or directory, unique to this test
///        process (ctest runs the tests of one binary as parallel processes).
inline std::string tempPath(const std::string& name)
{
  const auto dir = std::filesystem::temp_directory_path() /
                   ("voxplore_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

/// @brief The whole file, byte for byte (empty when it cannot be read).
inline std::string readFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// @brief A .simplemap (plain or gzip) as MRPT loads it.
/// @throws std::exception from MRPT on a bad file.
/// The rows of a CSV file with a header line (stops.csv, coverage.csv), each
/// as column name -> text; no quoting (our CSVs have none).
inline std::vector<std::map<std::string, std::string>> readCsv(const std::string& path)
{
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  std::vector<std::string> head;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) head.push_back(c);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(f, line))
  {
    std::stringstream ls(line);
    std::map<std::string, std::string> row;
    std::size_t i = 0;
    for (std::string c; i < head.size() && std::getline(ls, c, ','); i++) row[head[i]] = c;
    rows.push_back(row);
  }
  return rows;
}

inline mrpt::maps::CSimpleMap loadSimplemap(const std::string& path)
{
  mrpt::maps::CSimpleMap sm;
  mrpt::io::CFileGZInputStream in(path);
  mrpt::serialization::archiveFrom(in) >> sm;
  return sm;
}

/// @brief A closed box room [0, sx] x [0, sy] x [0, sz] built from six
///        inward-facing planes (two triangles each), robot start at `start`.
inline sim::World boxRoom(float sx, float sy, float sz, const mrpt::poses::CPose2D& start)
{
  sim::World w;
  w.name = "box_room";
  w.source_path = "<box_room>";
  using V = Eigen::Vector3f;
  auto& m = w.mesh;
  m.addQuad(V(0, 0, 0), V(sx, 0, 0), V(sx, sy, 0), V(0, sy, 0));          // floor
  m.addQuad(V(0, 0, sz), V(0, sy, sz), V(sx, sy, sz), V(sx, 0, sz));      // ceiling
  m.addQuad(V(0, 0, 0), V(0, sy, 0), V(0, sy, sz), V(0, 0, sz));          // x = 0
  m.addQuad(V(sx, 0, 0), V(sx, 0, sz), V(sx, sy, sz), V(sx, sy, 0));      // x = sx
  m.addQuad(V(0, 0, 0), V(0, 0, sz), V(sx, 0, sz), V(sx, 0, 0));          // y = 0
  m.addQuad(V(0, sy, 0), V(sx, sy, 0), V(sx, sy, sz), V(0, sy, sz));      // y = sy
  w.start = start;
  return w;
}

/// @brief Distance of a point to the nearest face plane of the box room.
inline double distanceToBoxRoom(const Eigen::Vector3d& p, double sx, double sy, double sz)
{
  return std::min({std::abs(p.x()), std::abs(p.x() - sx), std::abs(p.y()), std::abs(p.y() - sy),
                   std::abs(p.z()), std::abs(p.z() - sz)});
}

}  // namespace voxplore::test
