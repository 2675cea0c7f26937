// Our outputs in MRPT's own tools (issue 14): observations2map builds real
// maps from our map.simplemap (the keyframes' thinned clouds), and that cloud
// changes nothing in our own mapping (our readers use the depth images).
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>
#include <voxplore/apps/ReplayApp.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/mapping/SlamIcp.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
std::string recorded()
{
  return test::sourceDir() + "/rawlogs/dlr_test_room/run.rawlog";
}
const char* kObservations2map = "/usr/bin/observations2map";
const char* kOctomapIni = "/usr/share/mrpt/config_files/icp-slam/icp-slam_demo_with_octomap.ini";

struct Stop
{
  mrpt::obs::CSensoryFrame::Ptr sf;
  mrpt::poses::CPose2D odometry;
  mrpt::Clock::time_point t;
};

std::vector<Stop> recordedStops(std::size_t n)
{
  std::vector<Stop> out;
  mapping::SlamIcp reader{mapping::SlamIcpParams{}};
  common::forEachRawlogEntry(
      recorded(),
      [&](const common::RawlogEntry& e)
      {
        out.push_back({e.observations, reader.odometryOf(e.actions.get(), *e.observations).value(),
                       mapping::allDepthObservationsOf(*e.observations).front()->timestamp});
        return out.size() < n;
      });
  return out;
}

std::unique_ptr<mapping::SlamIcp> runSlam(const std::vector<Stop>& stops, double tools_cell_m)
{
  mapping::SlamIcpParams p;
  p.cloud.tools_cloud_cell_m = tools_cell_m;
  auto slam = std::make_unique<mapping::SlamIcp>(p);
  for (const auto& s : stops) slam->processStop(*s.sf, s.odometry, s.t);
  return slam;
}

/// Centres of the occupied voxels at the finest depth (pruned leaves expanded).
std::vector<octomap::point3d> occupiedCentres(const octomap::OcTree& tree)
{
  std::vector<octomap::point3d> out;
  const unsigned depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
  {
    if (!tree.isNodeOccupied(*it)) continue;
    const unsigned side = 1U << (depth - it.getDepth());
    const auto k0 = it.getIndexKey();
    for (unsigned i = 0; i < side; i++)
      for (unsigned j = 0; j < side; j++)
        for (unsigned k = 0; k < side; k++)
          out.push_back(tree.keyToCoord(octomap::OcTreeKey(k0[0] + i, k0[1] + j, k0[2] + k)));
  }
  return out;
}

/// Share of `pts` within `tol_m` of a point of `ref`, and the 90th percentile distance.
struct Agreement
{
  double share = 0, p90_m = 0;
};
Agreement agreement(const std::vector<octomap::point3d>& pts,
                    const std::vector<octomap::point3d>& ref, double tol_m)
{
  mrpt::maps::CSimplePointsMap kd;
  for (const auto& p : ref) kd.insertPoint(p.x(), p.y(), p.z());
  std::vector<double> d;
  for (const auto& p : pts)
  {
    float cx, cy, cz, d2;
    kd.kdTreeClosestPoint3D(p.x(), p.y(), p.z(), cx, cy, cz, d2);
    d.push_back(std::sqrt(d2));
  }
  Agreement a;
  if (d.empty()) return a;
  a.share =
      static_cast<double>(std::count_if(d.begin(), d.end(), [&](double v) { return v <= tol_m; })) /
      static_cast<double>(d.size());
  std::sort(d.begin(), d.end());
  a.p90_m = d[static_cast<std::size_t>(0.9 * static_cast<double>(d.size() - 1))];
  return a;
}

std::vector<octomap::point3d> readXyzText(const std::string& path)
{
  std::vector<octomap::point3d> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);)
  {
    std::istringstream ss(line);
    float x, y, z;
    if (ss >> x >> y >> z) out.emplace_back(x, y, z);
  }
  return out;
}

}  // namespace

TEST(MrptTools, ToolsCloudChangesNothingInOurMapping)
{
  const auto stops = recordedStops(12);
  const auto with = runSlam(stops, 0.10), without = runSlam(stops, 0.0);
  ASSERT_EQ(with->simplemap().size(), without->simplemap().size());
  ASSERT_GT(with->simplemap().size(), 5u);
  for (std::size_t i = 0; i < stops.size(); i++)
    EXPECT_EQ(with->reports()[i].pose, without->reports()[i].pose) << "stop " << i;
  EXPECT_EQ(with->metaview().size(), without->metaview().size());
  const auto occ = with->octomap().occupiedVoxelCenters();
  EXPECT_EQ(occ, without->octomap().occupiedVoxelCenters());

  // Each keyframe: the 8 depth images as before, plus one tools cloud that
  // our readers do not see.
  for (std::size_t i = 0; i < with->simplemap().size(); i++)
  {
    const auto sf = with->simplemap().getAsPair(i).sf;
    std::size_t clouds = 0;
    for (const auto& o : *sf)
      if (auto s = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
        if (mapping::isToolsCloud(*s))
        {
          clouds++;
          EXPECT_TRUE(s->hasPoints3D);
          EXPECT_GT(s->points3D_x.size(), 100u);
          EXPECT_EQ(s->sensorPose, mrpt::poses::CPose3D());
        }
    EXPECT_EQ(clouds, 1u) << "keyframe " << i;
    EXPECT_EQ(mapping::allDepthObservationsOf(*sf).size(), 8u);
    EXPECT_EQ(mapping::depthScansOf(*sf).size(), 8u);
    const auto usable = mapping::usableDepthScans(*sf, with->params().cloud);
    EXPECT_EQ(usable.scans.size(), 8u);
    EXPECT_TRUE(usable.issues.empty()) << usable.issues.front().reason;
    EXPECT_EQ(without->simplemap().getAsPair(i).sf->size() + 1, sf->size());
  }
  // The loop-closure rebuild reads the depth images back from the keyframes:
  // the same map as built stop by stop.
  with->rebuildMaps();
  EXPECT_EQ(with->octomap().occupiedVoxelCenters(), occ);
}

TEST(MrptTools, Observations2mapBuildsOctreeAndPointsMapFromOurSimplemap)
{
  if (!fs::exists(kObservations2map))
    GTEST_SKIP() << "*** " << kObservations2map
                 << " missing (Debian mrpt-apps): MRPT tools check skipped";
  ASSERT_TRUE(fs::exists(kOctomapIni))
      << kOctomapIni << " missing (Debian mrpt-apps / mrpt-common)";
  const auto dir = test::tempPath("observations2map");
  fs::remove_all(dir);
  fs::create_directories(dir);
  apps::ReplayOptions o;
  o.config = test::sourceDir() + "/config/replay.ini";
  o.rawlog = recorded();
  o.out_dir = dir + "/replay";
  o.quiet = true;
  const auto s = apps::ReplayApp{}.execute(o);
  const auto simplemap = o.out_dir + "/map.simplemap";
  ASSERT_TRUE(fs::exists(simplemap));
  const std::size_t keyframes = test::loadSimplemap(simplemap).size();
  ASSERT_GT(keyframes, 0u);
  std::cout << "[ simplemap ] " << keyframes << " keyframes of " << s.stops << " stops, "
            << fs::file_size(simplemap) << " bytes (" << fs::file_size(simplemap) / keyframes
            << " per keyframe)" << std::endl;

  // MRPT's sample config, copied beside the outputs with one change: its
  // point map is a 2D-laser map (isPlanarMap = true), into which MRPT 2.5.8
  // inserts no CObservation3DRangeScan at all (measured), so it is made 3D.
  {
    std::string ini = test::readFile(kOctomapIni);
    const std::string planar = "isPlanarMap                 = true";
    const auto at = ini.find(planar);
    ASSERT_NE(at, std::string::npos) << kOctomapIni << " changed: no '" << planar << "'";
    ini.replace(at, planar.size(), "isPlanarMap                 = false");
    std::ofstream(dir + "/octomap.ini") << ini;
  }
  const auto log = dir + "/observations2map.log";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string cmd = "cd '" + dir + "' && " + kObservations2map + " octomap.ini '" +
                          simplemap + "' '" + dir + "/mrpt' > '" + log + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::readFile(log);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string text = test::readFile(log);
  EXPECT_EQ(text.find("Writing 0 nodes"), std::string::npos) << text;

  std::string bt, pts;
  for (const auto& e : fs::directory_iterator(dir))
  {
    const auto name = e.path().filename().string();
    if (name.rfind("mrpt", 0) != 0) continue;
    if (name.find("COctoMap") != std::string::npos && e.path().extension() == ".bt") bt = e.path();
    if (name.find("CSimplePointsMap") != std::string::npos && e.path().extension() == ".txt")
      pts = e.path();
  }
  ASSERT_FALSE(bt.empty()) << "no COctoMap .bt written; log:\n" << text;
  ASSERT_FALSE(pts.empty()) << "no CSimplePointsMap .txt written; log:\n" << text;

  octomap::OcTree theirs(bt);
  octomap::OcTree ours(o.out_dir + "/map.bt");
  const auto their_occ = occupiedCentres(theirs), our_occ = occupiedCentres(ours);
  const auto their_pts = readXyzText(pts);
  ASSERT_GT(their_occ.size(), 500u) << "MRPT's octree is (nearly) empty";
  ASSERT_GT(their_pts.size(), 1000u) << "MRPT's point map is (nearly) empty";

  // The tools cloud has no floor (z < [cloud] z_min_m): compare ours above it.
  const double z_min = 0.10, res_theirs = theirs.getResolution(), res_ours = ours.getResolution();
  std::vector<octomap::point3d> our_above;
  for (const auto& p : our_occ)
    if (p.z() > z_min + 0.5 * res_ours && p.z() < 2.0) our_above.push_back(p);
  // "Within a voxel": one of MRPT's voxels (the coarser grid, 0.15 m in its
  // sample config) between a voxel centre of theirs and one of ours.
  const double tol = res_theirs;
  const auto t2o = agreement(their_occ, our_occ, tol);
  const auto o2t = agreement(our_above, their_occ, tol);
  const auto p2o = agreement(their_pts, our_occ, res_ours);
  const auto p2o2 = agreement(their_pts, our_occ, 2 * res_ours);
  std::cout << "[ observations2map ] " << secs << " s; MRPT octree (res " << res_theirs << " m) "
            << their_occ.size() << " occupied voxels, " << theirs.size() << " nodes; points map "
            << their_pts.size() << " points; ours (res " << res_ours << " m) " << our_occ.size()
            << " occupied voxels, " << our_above.size() << " above z_min\n"
            << "  MRPT voxels within " << tol << " m of ours: " << t2o.share << " (p90 "
            << t2o.p90_m << " m); ours (above z_min) within " << tol
            << " m of MRPT's: " << o2t.share << " (p90 " << o2t.p90_m << " m); MRPT points within "
            << res_ours << " m of our voxel centres: " << p2o.share << ", within " << 2 * res_ours
            << " m: " << p2o2.share << " (p90 " << p2o.p90_m << " m)" << std::endl;
  // Measured on this run (49 keyframes): 0.990, 0.9997, 0.950 and 0.996.
  // Our .bt marks a voxel occupied only above th_occ (240/255, p = 0.94), so
  // about 5 % of MRPT's points (every return it was given) fall in voxels
  // ours keeps free or unknown; all but 0.4 % are within two of our voxels.
  EXPECT_GE(t2o.share, 0.97);
  EXPECT_GE(o2t.share, 0.97);
  EXPECT_GE(p2o.share, 0.90);
  EXPECT_GE(p2o2.share, 0.98);

  // MRPT's sample config as it is: its 2D-laser point map (isPlanarMap =
  // true) takes the keyframes' horizontal slices ([cloud] tools_slice_z_m).
  const std::string stock = dir + "/stock";
  fs::create_directories(stock);
  std::ofstream(stock + "/octomap.ini") << test::readFile(kOctomapIni);
  const auto log2 = stock + "/observations2map.log";
  const std::string cmd2 = "cd '" + stock + "' && " + kObservations2map + " octomap.ini '" +
                           simplemap + "' '" + stock + "/mrpt' > '" + log2 + "' 2>&1";
  ASSERT_EQ(std::system(cmd2.c_str()), 0) << test::readFile(log2);
  std::string pts2;
  for (const auto& e : fs::directory_iterator(stock))
    if (e.path().filename().string().find("CSimplePointsMap") != std::string::npos &&
        e.path().extension() == ".txt")
      pts2 = e.path();
  ASSERT_FALSE(pts2.empty()) << "no CSimplePointsMap .txt written; log:\n" << test::readFile(log2);
  const auto slice_pts = readXyzText(pts2);
  ASSERT_GT(slice_pts.size(), 1000u) << "the stock ini's 2D point map is (nearly) empty";
  // In the plane: each slice point against our occupied voxels above the floor.
  std::vector<octomap::point3d> slice_2d, ours_2d;
  double z_sum = 0;
  for (const auto& p : slice_pts)
  {
    slice_2d.emplace_back(p.x(), p.y(), 0.0f);
    z_sum += p.z();
  }
  for (const auto& p : our_above) ours_2d.emplace_back(p.x(), p.y(), 0.0f);
  const auto s2o = agreement(slice_2d, ours_2d, res_ours);
  std::cout << "[ observations2map, stock ini ] 2D point map " << slice_pts.size()
            << " points at mean z " << z_sum / static_cast<double>(slice_pts.size())
            << " m; within " << res_ours << " m of our occupied columns: " << s2o.share
            << " (p90 " << s2o.p90_m << " m)" << std::endl;
  EXPECT_GE(s2o.share, 0.95);
}
