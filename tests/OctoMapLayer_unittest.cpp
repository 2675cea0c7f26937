// OctoMap layer: unprojection equal to MRPT's, Bayes update states on a
// wall, our batched insertion equal to stock OctoMap, range truncation,
// invalid pixels, the start box, .bt output and the parameters.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <octomap/OcTree.h>
#include <unistd.h>
#include <voxplore/mapping/OctoMapLayer.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <random>

#include "test_worlds.h"

using namespace voxplore;
using mapping::OctoMapLayer;
using mapping::OctoMapParams;
using mapping::VoxelState;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

namespace
{
constexpr int kW = 64, kH = 48;

/// A synthetic O3D100-like depth image (40 x 30 deg), ranges in mm from `range_mm(r, c)`.
mrpt::obs::CObservation3DRangeScan makeScan(const CPose3D& sensor_pose, bool range_is_depth,
                                            const std::function<int(int, int)>& range_mm)
{
  mrpt::obs::CObservation3DRangeScan obs;
  obs.sensorLabel = "TEST_CAM";
  obs.hasRangeImage = true;
  obs.rangeImage_setSize(kH, kW);
  obs.range_is_depth = range_is_depth;
  obs.rangeUnits = 0.001f;
  const double fx = (kW / 2.0) / std::tan(mrpt::DEG2RAD(20.0));
  const double fy = (kH / 2.0) / std::tan(mrpt::DEG2RAD(15.0));
  obs.cameraParams.ncols = kW;
  obs.cameraParams.nrows = kH;
  obs.cameraParams.setIntrinsicParamsFromValues(fx, fy, (kW - 1) / 2.0, (kH - 1) / 2.0);
  obs.sensorPose = sensor_pose;
  for (int r = 0; r < kH; r++)
    for (int c = 0; c < kW; c++) obs.rangeImage(r, c) = static_cast<uint16_t>(range_mm(r, c));
  return obs;
}

using VoxelKey = std::array<uint16_t, 3>;

/// Every full-resolution voxel of a tree (coarse leaves expanded) with its
/// log-odds, sorted by key.
std::vector<std::pair<VoxelKey, float>> voxelValues(const octomap::OcTree& tree)
{
  std::vector<std::pair<VoxelKey, float>> out;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
  {
    const unsigned side = 1U << (tree.getTreeDepth() - it.getDepth());
    const auto k0 = it.getIndexKey();
    for (unsigned i = 0; i < side; i++)
      for (unsigned j = 0; j < side; j++)
        for (unsigned k = 0; k < side; k++)
          out.push_back({{static_cast<uint16_t>(k0[0] + i), static_cast<uint16_t>(k0[1] + j),
                          static_cast<uint16_t>(k0[2] + k)},
                         it->getLogOdds()});
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Number of full-resolution voxels in a given state (by stateAt at the centre).
std::size_t countState(const OctoMapLayer& layer, VoxelState state)
{
  std::size_t n = 0;
  const auto& t = layer.tree();
  for (const auto& [key, value] : voxelValues(t))
  {
    const Eigen::Vector3d c(t.keyToCoord(key[0]), t.keyToCoord(key[1]), t.keyToCoord(key[2]));
    n += layer.stateAt(c) == state;
  }
  return n;
}

/// True when every inner node holds the maximum log-odds of its children.
bool innerNodesConsistent(const octomap::OcTree& t, const octomap::OcTreeNode* n)
{
  if (!t.nodeHasChildren(n)) return true;
  float max_child = -std::numeric_limits<float>::max();
  for (unsigned i = 0; i < 8; i++)
    if (t.nodeChildExists(n, i))
    {
      const auto* c = t.getNodeChild(n, i);
      if (!innerNodesConsistent(t, c)) return false;
      max_child = std::max(max_child, c->getLogOdds());
    }
  return n->getLogOdds() == max_child;
}

using InsertFn = mapping::InsertStats (OctoMapLayer::*)(const mrpt::obs::CObservation3DRangeScan&,
                                                        const CPose3D&);
const std::vector<std::pair<const char*, InsertFn>> kInserters = {
    {"ours", &OctoMapLayer::insertScan}, {"stock", &OctoMapLayer::insertScanStock}};

/// The thesis room (12 x 8 m) with two tables and a cabinet, scanned by the 8-camera ring.
struct RoomScans
{
  sim::World world = test::boxRoom(12, 8, 2.5, CPose2D(3.0, 4.0, 0.3));
  std::vector<std::pair<CPose3D, std::vector<mrpt::obs::CObservation3DRangeScan::Ptr>>> stops;

  RoomScans()
  {
    world.mesh.addBox({5.0f, 2.0f, 0.375f}, {1.6f, 0.8f, 0.75f}, 0.2f);
    world.mesh.addBox({8.0f, 6.0f, 0.375f}, {1.2f, 1.2f, 0.75f});
    world.mesh.addBox({10.5f, 1.0f, 1.0f}, {0.6f, 1.5f, 2.0f});
    sim::RayCaster caster(world.mesh);
    sim::DepthCameraRig rig{sim::CameraRigParams{}};
    std::mt19937_64 rng(42);
    for (const CPose2D& p :
         {CPose2D(3.0, 4.0, 0.3), CPose2D(4.5, 4.5, 1.2), CPose2D(7.0, 3.0, -2.0)})
      stops.emplace_back(CPose3D(p), rig.scan(caster, CPose3D(p), mrpt::Clock::fromDouble(0), rng));
  }
};
}  // namespace

// ------------------------------------------------------------ unprojection

TEST(OctoMapLayer, UnprojectRaysEqualsMrptUnprojectInto)
{
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> range(300, 7000);
  const CPose3D T_world_robot(1.5, -2.0, 0.1, 0.7, 0.05, -0.03);
  const CPose3D sensor_pose(0.3, -0.2, 0.6, mrpt::DEG2RAD(-40.0), mrpt::DEG2RAD(15.0), 0.0);
  for (const bool is_depth : {true, false})
  {
    auto obs = makeScan(sensor_pose, is_depth,
                        [&](int r, int c) { return (r * 7 + c) % 11 == 0 ? 0 : range(rng); });
    const auto rays = mapping::unprojectRays(obs, T_world_robot);

    mrpt::maps::CSimplePointsMap ref;
    mrpt::obs::T3DPointsProjectionParams pp;
    pp.takeIntoAccountSensorPoseOnRobot = true;
    pp.robotPoseInTheWorld = T_world_robot;
    obs.unprojectInto(ref, pp);

    ASSERT_EQ(rays.endpoints_world.size(), ref.size()) << "range_is_depth=" << is_depth;
    ASSERT_GT(rays.invalid_dirs_world.size(), 200u);
    EXPECT_EQ(rays.endpoints_world.size() + rays.invalid_dirs_world.size(), std::size_t(kW * kH));
    for (std::size_t i = 0; i < ref.size(); i++)
    {
      float x, y, z;
      ref.getPoint(i, x, y, z);
      ASSERT_NEAR((rays.endpoints_world[i] - Eigen::Vector3d(x, y, z)).norm(), 0.0, 1e-4)
          << "point " << i << " range_is_depth=" << is_depth;
    }
    const CPose3D T_world_cam = T_world_robot + sensor_pose;
    EXPECT_NEAR(
        (rays.origin_world - Eigen::Vector3d(T_world_cam.x(), T_world_cam.y(), T_world_cam.z()))
            .norm(),
        0.0, 1e-12);
    for (const auto& d : rays.invalid_dirs_world) ASSERT_NEAR(d.norm(), 1.0, 1e-9);
  }
}

TEST(OctoMapLayer, RangeModeChangesTheGeometry)
{
  // Same raw values, different meaning: a corner pixel lies farther away as depth.
  const auto depth = makeScan(CPose3D(), true, [](int, int) { return 3000; });
  const auto range = makeScan(CPose3D(), false, [](int, int) { return 3000; });
  const auto rd = mapping::unprojectRays(depth, CPose3D());
  const auto rr = mapping::unprojectRays(range, CPose3D());
  EXPECT_NEAR(rd.endpoints_world.front().x(), 3.0, 1e-5);     // depth along the optical axis
  EXPECT_NEAR(rr.endpoints_world.front().norm(), 3.0, 1e-5);  // euclidean range
  EXPECT_GT(rd.endpoints_world.front().norm(), 3.1);
}

// ------------------------------------------------------------- Bayes update

TEST(OctoMapLayer, WallBecomesOccupiedRaysFreeBehindUnknown)
{
  // Camera 1 m above the floor facing +X; wall plane at world x = 3.025 (voxel centre).
  const CPose3D T_world_robot(0.012, 0.013, 0.0, 0.0, 0.0, 0.0);
  const auto obs = makeScan(CPose3D(0, 0, 1.012, 0, 0, 0), true, [](int, int) { return 3013; });
  for (const auto& [name, insert] : kInserters)
  {
    OctoMapLayer layer;
    const auto rays = mapping::unprojectRays(obs, T_world_robot);
    for (int i = 0; i < 4; i++)
    {
      const auto st = (layer.*insert)(obs, T_world_robot);
      EXPECT_EQ(st.rays, std::size_t(kW * kH)) << name;
      EXPECT_EQ(st.hits, std::size_t(kW * kH)) << name;
      EXPECT_GT(st.free_updates, 10000u) << name;
      EXPECT_GT(st.occ_updates, 1000u) << name;
      // 3 hits: p = 0.927 < 240/255; 4 hits: 0.966 > 240/255.
      const auto expected = i < 3 ? VoxelState::Unknown : VoxelState::Occupied;
      for (const auto& p : rays.endpoints_world) ASSERT_EQ(layer.stateAt(p), expected) << name << i;
    }
    for (const auto& p : rays.endpoints_world)
    {
      const Eigen::Vector3d o = rays.origin_world;
      for (const double f : {0.1, 0.5, 0.9})
        ASSERT_EQ(layer.stateAt(o + f * (p - o)), VoxelState::Free) << name;
      ASSERT_EQ(layer.stateAt(o + 1.1 * (p - o)), VoxelState::Unknown) << name;
    }
    EXPECT_TRUE(innerNodesConsistent(layer.tree(), layer.tree().getRoot())) << name;
    const auto occ = layer.occupiedVoxelCenters();
    ASSERT_FALSE(occ.empty());
    for (const auto& c : occ) ASSERT_NEAR(c.x(), 3.025, 1e-6) << name;
  }
}

TEST(OctoMapLayer, OurInsertionEqualsStockOnRealisticScans)
{
  const RoomScans room;
  // Case 1 as recorded. Case 2: invalid pixels clear space, a pruned start box
  // is already in the map (coarse leaves to expand or skip), and everything is
  // shifted so that the map straddles the octree centre (all key bits change).
  for (const bool second_case : {false, true})
  {
    SCOPED_TRACE(second_case ? "clearing + start box + shifted" : "plain");
    OctoMapParams params;
    params.invalid_free_range_m = second_case ? 3.0 : 0.0;
    const CPose3D shift = second_case ? CPose3D(-6.02, -4.03, 0, 0, 0, 0) : CPose3D();
    OctoMapLayer ours(params), stock(params);
    if (second_case)
      for (auto* layer : {&ours, &stock}) layer->setStartBoxFree(shift + room.stops[0].first);
    std::size_t invalid = 0;
    for (int repeat = 0; repeat < 2; repeat++)
      for (const auto& [pose, scans] : room.stops)
        for (const auto& obs : scans)
        {
          const auto a = ours.insertScan(*obs, shift + pose);
          const auto b = stock.insertScanStock(*obs, shift + pose);
          EXPECT_EQ(a.rays, b.rays);
          EXPECT_EQ(a.hits, b.hits);
          EXPECT_EQ(a.invalid, b.invalid);
          EXPECT_EQ(a.free_updates, b.free_updates);
          EXPECT_EQ(a.occ_updates, b.occ_updates);
          invalid += a.invalid;
        }
    EXPECT_GT(invalid, 0u) << "the room should leave some pixels without return";
    const auto va = voxelValues(ours.tree()), vb = voxelValues(stock.tree());
    ASSERT_GT(va.size(), 100000u);
    ASSERT_EQ(va.size(), vb.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < va.size(); i++)
      differing += va[i].first != vb[i].first || va[i].second != vb[i].second;
    EXPECT_EQ(differing, 0u);
    for (const auto s : {VoxelState::Free, VoxelState::Occupied})
    {
      const auto n = countState(ours, s);
      EXPECT_GT(n, 1000u);
      EXPECT_EQ(n, countState(stock, s));
    }
    EXPECT_TRUE(innerNodesConsistent(ours.tree(), ours.tree().getRoot()));
  }
}

TEST(OctoMapLayer, StockPathEqualsInsertPointCloud)
{
  const RoomScans room;
  OctoMapLayer stock, direct;
  const auto& [pose, scans] = room.stops.front();
  for (const auto& obs : scans)
  {
    stock.insertScanStock(*obs, pose);
    const auto rays = mapping::unprojectRays(*obs, pose);
    octomap::Pointcloud cloud;
    for (const auto& p : rays.endpoints_world) cloud.push_back(p.x(), p.y(), p.z());
    const auto& o = rays.origin_world;
    direct.mutableTree().insertPointCloud(cloud, octomap::point3d(o.x(), o.y(), o.z()),
                                   direct.params().max_range_m, false, false);
  }
  EXPECT_EQ(voxelValues(stock.tree()), voxelValues(direct.tree()));
}

// ----------------------------------------------------- truncation, invalid

TEST(OctoMapLayer, WallBeyondMaxRangeGivesNoOccupiedVoxels)
{
  OctoMapParams params;
  params.max_range_m = 4.0;
  const auto obs = makeScan(CPose3D(0, 0, 1.0, 0, 0, 0), true, [](int, int) { return 5000; });
  for (const auto& [name, insert] : kInserters)
  {
    OctoMapLayer layer(params);
    for (int i = 0; i < 5; i++)
    {
      const auto st = (layer.*insert)(obs, CPose3D());
      EXPECT_EQ(st.hits, 0u) << name;
      EXPECT_EQ(st.occ_updates, 0u) << name;
    }
    EXPECT_TRUE(layer.occupiedVoxelCenters().empty()) << name;
    for (const auto& [key, value] : voxelValues(layer.tree())) ASSERT_LT(value, 0.0f) << name;
    EXPECT_EQ(layer.stateAt({3.5, 0.01, 1.01}), VoxelState::Free) << name;
    EXPECT_EQ(layer.stateAt({4.2, 0.01, 1.01}), VoxelState::Unknown) << name;
    EXPECT_EQ(layer.stateAt({5.0, 0.01, 1.01}), VoxelState::Unknown) << name;
  }
}

TEST(OctoMapLayer, InvalidPixelsClearOnlyWhenEnabled)
{
  const auto obs = makeScan(CPose3D(0, 0, 1.0, 0, 0, 0), true, [](int, int) { return 0; });
  for (const auto& [name, insert] : kInserters)
  {
    OctoMapLayer off;
    const auto st = (off.*insert)(obs, CPose3D());
    EXPECT_EQ(st.invalid, std::size_t(kW * kH)) << name;
    EXPECT_EQ(st.rays, 0u) << name;
    EXPECT_EQ(off.numLeafNodes(), 0u) << name;

    OctoMapParams params;
    params.invalid_free_range_m = 2.0;
    OctoMapLayer on(params);
    for (int i = 0; i < 3; i++) EXPECT_EQ((on.*insert)(obs, CPose3D()).rays, std::size_t(kW * kH));
    EXPECT_EQ(on.stateAt({1.5, 0.01, 1.01}), VoxelState::Free) << name;
    EXPECT_EQ(on.stateAt({2.5, 0.01, 1.01}), VoxelState::Unknown) << name;
    EXPECT_TRUE(on.occupiedVoxelCenters().empty()) << name;
  }
}

// ---------------------------------------------------------------- start box

TEST(OctoMapLayer, StartBoxIsFreeAndRotatesWithTheRobot)
{
  {
    OctoMapLayer layer;  // 2.5 x 2.5 x 0.5 m at the origin: 50 x 50 x 10 voxel centres
    layer.setStartBoxFree(CPose3D());
    EXPECT_EQ(countState(layer, VoxelState::Free), 25000u);
    EXPECT_EQ(countState(layer, VoxelState::Occupied), 0u);
    EXPECT_TRUE(innerNodesConsistent(layer.tree(), layer.tree().getRoot()));
  }
  const CPose3D T(1.0, 2.0, 0.0, mrpt::DEG2RAD(30.0), 0, 0);
  OctoMapLayer layer;
  layer.setStartBoxFree(T);
  auto world = [&](double x, double y, double z)
  {
    mrpt::math::TPoint3D w;
    T.composePoint({x, y, z}, w);
    return Eigen::Vector3d(w.x, w.y, w.z);
  };
  for (const double x : {-1.15, 0.0, 1.15})
    for (const double y : {-1.15, 0.0, 1.15})
      for (const double z : {0.04, 0.25, 0.46})
        EXPECT_EQ(layer.stateAt(world(x, y, z)), VoxelState::Free);
  EXPECT_EQ(layer.stateAt(world(1.35, 0, 0.25)), VoxelState::Unknown);
  EXPECT_EQ(layer.stateAt(world(0, -1.35, 0.25)), VoxelState::Unknown);
  EXPECT_EQ(layer.stateAt(world(0, 0, 0.56)), VoxelState::Unknown);
  EXPECT_EQ(layer.stateAt(world(0, 0, -0.03)), VoxelState::Unknown);
  // Inside the axis-aligned box of the same centre but outside the rotated one, and vice versa.
  EXPECT_EQ(layer.stateAt({1.0 + 1.2, 2.0 + 1.2, 0.25}), VoxelState::Unknown);
  EXPECT_EQ(layer.stateAt(world(1.1, 1.1, 0.25)), VoxelState::Free);
  EXPECT_GT(std::abs(world(1.1, 1.1, 0.25).y() - 2.0), 1.25);
}

// -------------------------------------------------------------------- files

TEST(OctoMapLayer, WrittenBinaryLoadsInBt2vrmlAndOctomap)
{
  const RoomScans room;
  OctoMapLayer layer;
  layer.setStartBoxFree(room.stops.front().first);
  for (int i = 0; i < 4; i++)  // 4 hits make the walls occupied
    for (const auto& obs : room.stops.front().second)
      layer.insertScan(*obs, room.stops.front().first);
  std::size_t occupied_leaves = 0;
  for (auto it = layer.tree().begin_leafs(); it != layer.tree().end_leafs(); ++it)
    occupied_leaves += it->getOccupancy() > OctoMapParams::probOf(layer.params().th_occ);
  ASSERT_GT(occupied_leaves, 1000u);
  const auto dir = std::filesystem::temp_directory_path() / "voxplore_octomap_unittest";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "map.bt").string();
  layer.writeBinary(path);

  octomap::OcTree back(path);
  EXPECT_EQ(back.getNumLeafNodes(), layer.numLeafNodes());
  EXPECT_NEAR(back.getResolution(), 0.05, 1e-12);

  try
  {
    layer.writeBinary((dir / "no_such_dir" / "map.bt").string());
    ADD_FAILURE() << "writing into a missing directory must throw";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("no_such_dir/map.bt"), std::string::npos) << e.what();
  }

  if (!std::filesystem::exists("/usr/bin/bt2vrml"))
    GTEST_SKIP() << "*** /usr/bin/bt2vrml missing (Debian octomap-tools): .bt viewer check skipped";
  const std::string cmd = "/usr/bin/bt2vrml '" + path + "' > '" + path + ".log' 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream log(path + ".log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  const std::string expected = "Finished writing " + std::to_string(occupied_leaves) + " voxels";
  EXPECT_NE(text.find(expected), std::string::npos) << "bt2vrml said:\n" << text;
  EXPECT_GT(std::filesystem::file_size(path + ".wrl"), occupied_leaves * 10);
}

TEST(OctoMapLayer, WriteBinaryIsSilentAndEqualsOctomapsOwnWriter)
{
  const RoomScans room;
  OctoMapLayer layer;
  layer.setStartBoxFree(room.stops.front().first);
  for (int i = 0; i < 4; i++)
    for (const auto& obs : room.stops.front().second)
      layer.insertScan(*obs, room.stops.front().first);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("voxplore_octomap_silent_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string ours = (dir / "ours.bt").string(), stock = (dir / "stock.bt").string();

  // CaptureStderr redirects file descriptor 2: it sees octomap's fprintf(stderr) too.
  testing::internal::CaptureStderr();
  layer.writeBinary(ours);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(said, "") << "writeBinary printed to stderr";

  testing::internal::CaptureStderr();
  ASSERT_TRUE(layer.tree().writeBinaryConst(stock));
  const std::string stock_said = testing::internal::GetCapturedStderr();
  // Octomap's own writer (what we replaced), for the record: " done." today.
  std::cout << "octomap writeBinaryConst said: '" << stock_said << "'" << std::endl;

  const auto bytes = [](const std::string& p)
  {
    std::ifstream f(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  };
  EXPECT_GT(bytes(ours).size(), 1000u);
  EXPECT_EQ(bytes(ours), bytes(stock)) << "not the bytes of OcTree::writeBinaryConst";

  // Reads back through octomap's generic reader and its binary reader alike.
  octomap::OcTree back(0.1);
  ASSERT_TRUE(back.readBinary(ours));
  octomap::OcTree expected(0.1);
  ASSERT_TRUE(expected.readBinary(stock));
  EXPECT_TRUE(back == expected);
  EXPECT_EQ(back.getNumLeafNodes(), expected.getNumLeafNodes());
  EXPECT_EQ(back.size(), layer.tree().size());
  EXPECT_NEAR(back.getResolution(), layer.tree().getResolution(), 1e-12);
  std::size_t checked = 0;
  for (auto it = layer.tree().begin_leafs(); it != layer.tree().end_leafs(); ++it, ++checked)
  {
    const auto* n = back.search(it.getKey(), it.getDepth());
    ASSERT_NE(n, nullptr);
    EXPECT_EQ(back.isNodeOccupied(n), layer.tree().isNodeOccupied(*it));
  }
  EXPECT_EQ(checked, back.getNumLeafNodes());
  std::filesystem::remove_all(dir);
}

// --------------------------------------------------------------- parameters

TEST(OctoMapLayer, ParamsRoundTripAndBadValuesNameTheKey)
{
  OctoMapParams p;
  p.l_res_m = 0.08;
  p.th_free = 60;
  p.th_occ = 230;
  p.prob_hit = 0.8;
  p.prob_miss = 0.3;
  p.clamp_min = 0.12;
  p.clamp_max = 0.97;
  p.max_range_m = 6.5;
  p.invalid_free_range_m = 2.0;
  p.start_box_x_m = 2.0;
  p.start_box_y_m = 1.5;
  p.start_box_z_m = 0.4;
  mrpt::config::CConfigFileMemory mem;
  p.saveToConfigFile(mem, "octomap");
  OctoMapParams q;
  q.loadFromConfigFile(mem, "octomap");
  EXPECT_EQ(q.l_res_m, p.l_res_m);
  EXPECT_EQ(q.th_free, p.th_free);
  EXPECT_EQ(q.th_occ, p.th_occ);
  EXPECT_EQ(q.start_value, 128);
  EXPECT_EQ(q.prob_hit, p.prob_hit);
  EXPECT_EQ(q.prob_miss, p.prob_miss);
  EXPECT_EQ(q.clamp_min, p.clamp_min);
  EXPECT_EQ(q.clamp_max, p.clamp_max);
  EXPECT_EQ(q.max_range_m, p.max_range_m);
  EXPECT_EQ(q.invalid_free_range_m, p.invalid_free_range_m);
  EXPECT_EQ(q.start_box_x_m, p.start_box_x_m);
  EXPECT_EQ(q.start_box_y_m, p.start_box_y_m);
  EXPECT_EQ(q.start_box_z_m, p.start_box_z_m);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"l_res_m", "0"},        {"th_free", "-1"},
      {"th_free", "130"},      {"th_occ", "100"},
      {"th_occ", "256"},       {"start_value", "100"},
      {"prob_hit", "0.5"},     {"prob_hit", "1"},
      {"prob_miss", "0.5"},    {"prob_miss", "0"},
      {"clamp_min", "0.3"},    {"clamp_max", "0.9"},
      {"max_range_m", "0"},    {"invalid_free_range_m", "-1"},
      {"start_box_x_m", "-1"}, {"start_box_y_m", "-0.1"},
      {"start_box_z_m", "-2"}};
  for (const auto& [key, value] : bad)
  {
    mrpt::config::CConfigFileMemory cfg;
    OctoMapParams{}.saveToConfigFile(cfg, "octomap");
    cfg.write("octomap", key, value);
    OctoMapParams r;
    try
    {
      r.loadFromConfigFile(cfg, "octomap");
      ADD_FAILURE() << key << " = " << value << " was accepted";
    }
    catch (const std::exception& e)
    {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

// ------------------------------------------------------------ low obstacles

namespace
{
/// A 4.5 cm plate (a table's base) in an 8 x 6 m room, scanned by the ring
/// of 8 noisy cameras from four stops round it.
OctoMapLayer scanLowPlate(const OctoMapParams& params, bool with_plate)
{
  sim::World world = test::boxRoom(8, 6, 2.5, CPose2D(2.2, 3.0, 0));
  if (with_plate) world.mesh.addBox({4.0f, 3.0f, 0.0225f}, {0.5f, 0.5f, 0.045f});
  sim::RayCaster caster(world.mesh);
  sim::DepthCameraRig rig{sim::CameraRigParams{}};
  std::mt19937_64 rng(7);
  OctoMapLayer layer(params);
  for (const CPose2D& p : {CPose2D(2.2, 3.0, 0.0), CPose2D(4.0, 1.2, M_PI / 2),
                           CPose2D(5.8, 3.0, M_PI), CPose2D(4.0, 4.8, -M_PI / 2)})
    for (const auto& obs : rig.scan(caster, CPose3D(p), mrpt::Clock::fromDouble(0), rng))
      layer.insertScan(*obs, CPose3D(p));
  return layer;
}
}  // namespace

TEST(OctoMapLayer, LowObstacleCellsHoldThePlateAndNoFloor)
{
  const OctoMapLayer layer = scanLowPlate(OctoMapParams{}, true);
  // The voxel columns G is projected from (from 10 cm) cannot show a 4.5 cm
  // plate; the low obstacle cells must.
  const auto cells = layer.lowObstacles();
  std::size_t on_plate = 0;
  for (const auto& c : cells)
  {
    const double out_x = std::abs(c.x() - 4.0) - 0.25, out_y = std::abs(c.y() - 3.0) - 0.25;
    if (out_x < 0 && out_y < 0)
    {
      on_plate++;
      continue;
    }
    // Anything else is the plate's rim (its edge within the cell) or a wall
    // base (the cell whose border the wall's face lies on).
    const double wall = std::min({c.x(), 8 - c.x(), c.y(), 6 - c.y()});
    EXPECT_TRUE(std::max(out_x, out_y) < 0.05 || wall < 0.05)
        << "low obstacle cell (" << c.x() << ", " << c.y() << ") on the open floor";
  }
  EXPECT_GE(on_plate, 70u) << "of the plate's 100 cells";  // 100 % measured
  EXPECT_GT(layer.lowObstacleGrid().cells(), 5000u) << "the floor seen round the plate";
}

TEST(OctoMapLayer, LowObstaclesOffOrAbsentGiveNone)
{
  OctoMapParams off;
  off.low_obstacle_min_z_m = 0;
  EXPECT_TRUE(scanLowPlate(off, true).lowObstacles().empty());
  // Without the plate the floor's noise makes no obstacle off the walls.
  for (const auto& c : scanLowPlate(OctoMapParams{}, false).lowObstacles())
    EXPECT_LT(std::min({c.x(), 8 - c.x(), c.y(), 6 - c.y()}), 0.05)
        << "low obstacle cell (" << c.x() << ", " << c.y() << ") on the open floor";
}

// ----------------------------------------------------------------- journal

namespace
{
/// Keys whose voxel value differs between two voxelValues() lists (or is in one only).
std::vector<VoxelKey> changedKeys(const std::vector<std::pair<VoxelKey, float>>& a,
                                  const std::vector<std::pair<VoxelKey, float>>& b)
{
  std::vector<VoxelKey> out;
  std::size_t i = 0, j = 0;
  while (i < a.size() || j < b.size())
  {
    if (j == b.size() || (i < a.size() && a[i].first < b[j].first))
      out.push_back(a[i++].first);
    else if (i == a.size() || b[j].first < a[i].first)
      out.push_back(b[j++].first);
    else
    {
      if (a[i].second != b[j].second) out.push_back(a[i].first);
      ++i, ++j;
    }
  }
  return out;
}

bool inBox(const mapping::KeyBox& box, const VoxelKey& k)
{
  for (int a = 0; a < 3; ++a)
    if (k[a] < box.lo[a] || k[a] >= box.hi[a]) return false;
  return true;
}
}  // namespace

// The planner's projection visits again only what changedSince() names: it
// must hold every voxel a scan changed, whichever inserter, with clearing
// rays and the start box, and say "not known" where it cannot follow.
TEST(OctoMapLayer, TheJournalHoldsEveryChangedVoxel)
{
  const RoomScans room;
  for (const auto& [name, insert] : kInserters)
  {
    SCOPED_TRACE(name);
    OctoMapParams params;
    params.invalid_free_range_m = 3.0;
    OctoMapLayer layer(params);
    const mapping::MapRevision at_start = layer.revision();
    EXPECT_TRUE(layer.changedSince(at_start).value().empty()) << "nothing changed yet";
    auto before = voxelValues(layer.tree());
    mapping::MapRevision rev = layer.revision();
    layer.setStartBoxFree(room.stops[0].first);
    std::size_t changed_total = 0, box_volume_max = 0;
    const auto check = [&]
    {
      const auto after = voxelValues(layer.tree());
      const auto box = layer.changedSince(rev);
      ASSERT_TRUE(box.has_value());
      const auto changed = changedKeys(before, after);
      for (const auto& k : changed) ASSERT_TRUE(inBox(*box, k));
      changed_total += changed.size();
      std::size_t volume = 1;
      for (int a = 0; a < 3; ++a) volume *= static_cast<std::size_t>(box->hi[a] - box->lo[a]);
      box_volume_max = std::max(box_volume_max, volume);
      before = after;
      rev = layer.revision();
    };
    check();
    for (const auto& [pose, scans] : room.stops)
      for (const auto& obs : scans)
      {
        (layer.*insert)(*obs, pose);
        check();
      }
    EXPECT_GT(changed_total, 100000u);
    // One camera's box, not the world's: a box is a camera's view at most
    // 7 m deep, far less than the octree's 2^16 keys a side.
    EXPECT_LT(box_volume_max, 300u * 300u * 300u);
    // Since the start: everything, in one box.
    const auto all = layer.changedSince(at_start);
    ASSERT_TRUE(all.has_value());
    for (const auto& [k, v] : voxelValues(layer.tree())) ASSERT_TRUE(inBox(*all, k));

    // Not known: another map's revision, a revision from before mutableTree().
    OctoMapLayer other(params);
    EXPECT_FALSE(other.changedSince(layer.revision()).has_value());
    const mapping::MapRevision before_mutable = layer.revision();
    layer.mutableTree();
    EXPECT_FALSE(layer.changedSince(before_mutable).has_value());
    // A map moved in (the loop closure's rebuilt one) brings its own id.
    const mapping::MapRevision old_map = layer.revision();
    layer = std::move(other);
    EXPECT_FALSE(layer.changedSince(old_map).has_value());
  }
}

TEST(OctoMapLayer, TheJournalForgetsOnlyBeyondItsSize)
{
  // A start box of one voxel column: a journaled change that costs nothing.
  OctoMapParams params;
  params.start_box_x_m = params.start_box_y_m = params.start_box_z_m = 0.05;
  OctoMapLayer layer(params);
  const mapping::MapRevision first = layer.revision();
  for (std::size_t i = 0; i < OctoMapLayer::kJournalSize; ++i) layer.setStartBoxFree(CPose3D());
  EXPECT_EQ(layer.revision().rev, OctoMapLayer::kJournalSize);
  EXPECT_TRUE(layer.changedSince(first).has_value()) << "exactly kJournalSize changes are kept";
  layer.setStartBoxFree(CPose3D());
  EXPECT_FALSE(layer.changedSince(first).has_value());
  mapping::MapRevision recent = layer.revision();
  recent.rev -= 10;
  const auto box = layer.changedSince(recent);
  ASSERT_TRUE(box.has_value());
  EXPECT_FALSE(box->empty());
  EXPECT_TRUE(layer.changedSince(layer.revision()).value().empty()) << "nothing since now";
}
