// voxplore-replay on the recorded dlr_test_room tour: trajectory and map
// accuracy against ground truth, ICP against odometry only, outputs, and
// errors for bad input.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>
#include <voxplore/apps/ReplayApp.h>
#include <voxplore/apps/SimApp.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/eval/map_accuracy.h>
#include <voxplore/mapping/OctoMapLayer.h>
#include <voxplore/sim/ground_truth.h>
#include <voxplore/sim/world_loading.h>

#include <filesystem>
#include <fstream>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
std::string tmp(const std::string& name) { return test::tempPath(name); }
std::string recorded() { return test::sourceDir() + "/rawlogs/dlr_test_room/run.rawlog"; }

apps::ReplayOptions replayOpts(const std::string& out)
{
  apps::ReplayOptions o;
  o.config = test::sourceDir() + "/config/replay.ini";
  o.rawlog = recorded();
  o.out_dir = tmp(out);
  o.quiet = true;
  return o;
}

std::string errorOf(const apps::ReplayOptions& o)
{
  try
  {
    apps::ReplayApp{}.execute(o);
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
  return {};
}

// One replay shared by the accuracy tests (it takes a few seconds).
const apps::ReplaySummary& icpRun()
{
  static const apps::ReplaySummary s = apps::ReplayApp{}.execute(replayOpts("replay_icp"));
  return s;
}
}  // namespace

TEST(Replay, DlrTestRoomTrajectoryWithinThreeCentimetres)
{
  const auto& s = icpRun();
  ASSERT_TRUE(s.has_ground_truth);
  EXPECT_EQ(s.stops, 49u);
  EXPECT_EQ(s.flagged, 0u);
  EXPECT_LT(s.ate_rmse_m, 0.03);
  EXPECT_LT(s.final_yaw_error_deg, 1.0);
  std::cout << "[ replay ] ICP on: ATE RMSE " << s.ate_rmse_m << " m, max " << s.ate_max_m
            << " m, final yaw error " << s.final_yaw_error_deg << " deg, metaview "
            << s.metaview_points << " points, " << s.mean_stop_ms << " ms/stop\n";
}

TEST(Replay, OdometryOnlyIsClearlyWorse)
{
  auto o = replayOpts("replay_noicp");
  o.icp = false;
  const auto off = apps::ReplayApp{}.execute(o);
  const auto& on = icpRun();
  std::cout << "[ replay ] ICP off: ATE RMSE " << off.ate_rmse_m << " m, final yaw error "
            << off.final_yaw_error_deg << " deg\n";
  EXPECT_GT(off.ate_rmse_m, 3.0 * on.ate_rmse_m);
  EXPECT_GT(off.ate_rmse_m, 0.05);
  EXPECT_GT(off.final_yaw_error_deg, 2.0 * on.final_yaw_error_deg);
}

TEST(Replay, MapPrecisionAgainstGroundTruthVoxels)
{
  icpRun();
  const auto world = sim::loadWorld(test::sourceDir() + "/simulated_worlds/dlr_test_room.world");
  const auto gt_voxels = sim::occupiedVoxels(world.mesh, 0.05);
  octomap::OcTree tree(tmp("replay_icp") + "/map.bt");
  mapping::OctoMapParams p;
  mapping::OctoMapLayer layer(p);
  layer.tree().swapContent(tree);
  const auto occ = layer.occupiedVoxelCenters();
  ASSERT_GT(occ.size(), 1000u);
  const auto gt_traj = common::readTum(test::sourceDir() + "/rawlogs/dlr_test_room/trajectory_gt.tum");
  const auto prec = eval::mapPrecision(occ, gt_traj.front().pose, gt_voxels, 0.05);
  std::cout << "[ replay ] map precision " << prec.precision << " (" << prec.near_surface << " / "
            << prec.occupied << " occupied voxels within one voxel of a true surface)\n";
  EXPECT_GE(prec.precision, 0.9);
}

TEST(Replay, WritesLoadableOutputs)
{
  icpRun();
  const auto dir = tmp("replay_icp");
  for (const char* f : {"map.bt", "map.simplemap", "metaview.ply", "trajectory_est.tum", "stops.csv",
                        "params.ini", "summary.json"})
    EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / f)) << f;
  mrpt::maps::CSimpleMap sm;
  mrpt::io::CFileGZInputStream in(dir + "/map.simplemap");
  auto arch = mrpt::serialization::archiveFrom(in);
  arch >> sm;
  EXPECT_EQ(sm.size(), 49u);
  EXPECT_EQ(common::readTum(dir + "/trajectory_est.tum").size(), 49u);
  std::ifstream csv(dir + "/stops.csv");
  std::size_t lines = 0;
  for (std::string l; std::getline(csv, l);) lines++;
  EXPECT_EQ(lines, 50u);  // header + 49 stops
  if (fs::exists("/usr/bin/bt2vrml"))
  {
    fs::copy_file(dir + "/map.bt", tmp("bt2vrml_check.bt"), fs::copy_options::overwrite_existing);
    EXPECT_EQ(std::system(("bt2vrml '" + tmp("bt2vrml_check.bt") + "' > /dev/null 2>&1").c_str()), 0);
    EXPECT_TRUE(fs::exists(tmp("bt2vrml_check.bt.wrl")));
  }
}

TEST(Replay, BadInputsAreNamedErrors)
{
  auto o = replayOpts("replay_bad");
  o.rawlog = "/nonexistent/run.rawlog";
  EXPECT_NE(errorOf(o).find("/nonexistent/run.rawlog"), std::string::npos);

  o = replayOpts("replay_bad");
  o.config = tmp("bad_replay.ini");
  std::ofstream(o.config) << "[icp]\nd_maxx_m = 0.4\n";
  const auto msg = errorOf(o);
  EXPECT_NE(msg.find("d_maxx_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad_replay.ini"), std::string::npos) << msg;

  o = replayOpts("replay_bad");
  o.config = tmp("bad_section.ini");
  std::ofstream(o.config) << "[icpp]\nenabled = true\n";
  EXPECT_NE(errorOf(o).find("icpp"), std::string::npos);
}

TEST(Replay, LaserOnlyRawlogSaysThereAreNoDepthImages)
{
  const std::string laser = "/usr/share/mrpt/datasets/localization_demo.rawlog";
  if (!fs::exists(laser)) GTEST_SKIP() << "MRPT datasets (mrpt-common) not installed: " << laser;
  auto o = replayOpts("replay_laser");
  o.rawlog = laser;
  const auto msg = errorOf(o);
  EXPECT_NE(msg.find("localization_demo.rawlog"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no CObservation3DRangeScan"), std::string::npos) << msg;
  EXPECT_NE(msg.find("CObservation2DRangeScan"), std::string::npos) << msg;
}

TEST(Replay, TruncatedRawlogKeepsTheMapSoFar)
{
  const auto cut = tmp("cut.rawlog");
  fs::copy_file(recorded(), cut, fs::copy_options::overwrite_existing);
  // the recorded rawlog may be gzip-compressed: cut the decompressed stream instead
  {
    mrpt::io::CFileGZInputStream in(recorded());
    std::string data;
    char buf[65536];
    for (std::size_t n; (n = in.Read(buf, sizeof(buf))) > 0;) data.append(buf, n);
    std::ofstream(cut, std::ios::binary).write(data.data(), static_cast<std::streamsize>(data.size() / 2));
  }
  auto o = replayOpts("replay_cut");
  o.rawlog = cut;
  const auto msg = errorOf(o);
  EXPECT_NE(msg.find("cut.rawlog"), std::string::npos) << msg;
  EXPECT_NE(msg.find("entry"), std::string::npos) << msg;
  EXPECT_TRUE(fs::is_regular_file(o.out_dir + "/map.bt")) << msg;
  EXPECT_GT(common::readTum(o.out_dir + "/trajectory_est.tum").size(), 10u);
}

TEST(Replay, LongCorridorDegeneracyKeepsOdometryAlongTheAxis)
{
  // Thesis fig. 5.8: in a featureless corridor ICP shortens the trajectory.
  // With the degeneracy check the corridor axis is detected and odometry is
  // trusted along it.
  apps::SimOptions sim;
  sim.world = test::sourceDir() + "/simulated_worlds/long_corridor.world";
  sim.waypoints = test::sourceDir() + "/simulated_worlds/long_corridor_tour.txt";
  sim.config = test::sourceDir() + "/config/sim.ini";
  sim.out_dir = tmp("corridor_sim");
  sim.seed = 1;
  sim.quiet = true;
  apps::SimApp{}.execute(sim);

  auto o = replayOpts("corridor_on");
  o.rawlog = sim.out_dir + "/run.rawlog";
  const auto on = apps::ReplayApp{}.execute(o);
  const auto cfg_off = tmp("corridor_off.ini");
  std::ofstream(cfg_off) << "[icp]\ndegeneracy_check = false\n";
  o.config = cfg_off;
  o.out_dir = tmp("corridor_off");
  const auto off = apps::ReplayApp{}.execute(o);
  o.config.clear();
  o.icp = false;
  o.out_dir = tmp("corridor_odo");
  const auto odo = apps::ReplayApp{}.execute(o);
  std::cout << "[ corridor ] degeneracy check: " << on.degenerate << " of " << on.stops
            << " stops degenerate, ATE " << on.ate_rmse_m << " m, final error " << on.final_xy_error_m
            << " m; without: ATE " << off.ate_rmse_m << " m, final " << off.final_xy_error_m
            << " m; odometry only: ATE " << odo.ate_rmse_m << " m, final " << odo.final_xy_error_m
            << " m\n";
  EXPECT_GT(on.degenerate, on.stops / 3);
  EXPECT_EQ(off.degenerate, 0u);
  EXPECT_LT(on.ate_rmse_m, 0.05);
  EXPECT_LT(on.ate_rmse_m, 0.5 * off.ate_rmse_m);
  EXPECT_LT(on.final_xy_error_m, off.final_xy_error_m);
}
