// Faults the running system must survive (issue 6), each injected here:
// garbage or missing depth cameras, stops without cameras, an empty
// metaview, ICP that does not converge, an open hall, an odometry jump,
// navigation faults (boxed in, unreachable waypoint, no path, limits),
// SIGINT mid-run for voxplore-explore and voxplore-replay, and bad output
// directories / configuration values for every app.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>
#include <voxplore/apps/ExploreApp.h>
#include <voxplore/apps/ReplayApp.h>
#include <voxplore/apps/SimApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/eval/map_accuracy.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/ground_truth.h>
#include <voxplore/sim/world_loading.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include "test_worlds.h"

using namespace voxplore;
using mrpt::obs::CObservation3DRangeScan;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
namespace fs = std::filesystem;

namespace
{
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string recorded() { return test::sourceDir() + "/rawlogs/dlr_test_room/run.rawlog"; }
std::string recordedGt() { return test::sourceDir() + "/rawlogs/dlr_test_room/trajectory_gt.tum"; }

/// One stop of the recorded dlr_test_room tour (fresh objects: safe to corrupt).
struct Stop
{
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr sf;
  CPose2D odometry;
  mrpt::Clock::time_point t;
};

std::vector<Stop> recordedStops(std::size_t n = 0)
{
  std::vector<Stop> out;
  mapping::SlamIcp reader{mapping::SlamIcpParams{}};
  common::forEachRawlogEntry(recorded(), [&](const common::RawlogEntry& e) {
    Stop s{e.actions, e.observations, {}, {}};
    s.odometry = reader.odometryOf(e.actions.get(), *e.observations).value();
    s.t = mapping::allDepthObservationsOf(*e.observations).front()->timestamp;
    out.push_back(s);
    return n == 0 || out.size() < n;
  });
  return out;
}

CObservation3DRangeScan& camera(const Stop& s, std::size_t i)
{
  return *mapping::allDepthObservationsOf(*s.sf).at(i);
}

void fill(CObservation3DRangeScan& o, uint16_t v)
{
  for (int r = 0; r < o.rangeImage.rows(); r++)
    for (int c = 0; c < o.rangeImage.cols(); c++) o.rangeImage(r, c) = v;
}

std::unique_ptr<mapping::SlamIcp> runSlam(const std::vector<Stop>& stops,
                                          const mapping::SlamIcpParams& p = {})
{
  auto slam = std::make_unique<mapping::SlamIcp>(p);
  for (const auto& s : stops) slam->processStop(*s.sf, s.odometry, s.t);
  return slam;
}

bool finite(const CPose2D& p)
{
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

/// Every metaview point finite and inside the room (with a margin).
bool metaviewSane(const mapping::Metaview& m)
{
  const auto& pts = m.points();
  for (std::size_t i = 0; i < pts.size(); i++)
  {
    float x, y, z;
    pts.getPoint(i, x, y, z);
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || std::abs(x) > 20 ||
        std::abs(y) > 20 || z < -1 || z > 3)
      return false;
  }
  return true;
}

double precisionAgainstGt(const mapping::OctoMapLayer& layer)
{
  static const auto gt_voxels = sim::occupiedVoxels(
      sim::loadWorld(test::sourceDir() + "/simulated_worlds/dlr_test_room.world").mesh, 0.05);
  const auto gt = common::readTum(recordedGt());
  return eval::mapPrecision(layer.occupiedVoxelCenters(), gt.front().pose, gt_voxels, 0.05).precision;
}

/// Writes `stops` as a rawlog (with the ground truth beside it) for voxplore-replay.
std::string writeRawlog(const std::vector<Stop>& stops, const std::string& name)
{
  const auto dir = test::tempPath(name);
  fs::create_directories(dir);
  {
    common::RawlogWriter w(dir + "/run.rawlog");
    for (const auto& s : stops) w.write(*s.actions, *s.sf);
  }
  fs::copy_file(recordedGt(), dir + "/trajectory_gt.tum", fs::copy_options::overwrite_existing);
  return dir + "/run.rawlog";
}

apps::ReplaySummary replay(const std::string& rawlog, const std::string& out,
                           const std::string& config = test::sourceDir() + "/config/replay.ini")
{
  apps::ReplayOptions o;
  o.config = config;
  o.rawlog = rawlog;
  o.out_dir = test::tempPath(out);
  o.quiet = true;
  return apps::ReplayApp{}.execute(o);
}

const apps::ReplaySummary& cleanReplay()
{
  static const apps::ReplaySummary s = replay(recorded(), "replay_clean");
  return s;
}

nlohmann::json readJson(const fs::path& p)
{
  std::ifstream f(p);
  return nlohmann::json::parse(f);
}

/// A camera fault: how to inject it and what the skip reason must say.
struct CameraFault
{
  const char* name;
  std::function<void(CObservation3DRangeScan&)> inject;
  const char* reason;
};

const std::vector<CameraFault>& cameraFaults()
{
  static const std::vector<CameraFault> faults = {
      {"all-zero range image", [](auto& o) { fill(o, 0); }, "no return"},
      {"all 65535", [](auto& o) { fill(o, 0xFFFF); }, "impossible"},
      {"beyond maxRange", [](auto& o) { fill(o, 20000); }, "impossible"},
      {"rangeUnits NaN", [](auto& o) { o.rangeUnits = static_cast<float>(kNaN); }, "rangeUnits"},
      {"rangeUnits inf", [](auto& o) { o.rangeUnits = static_cast<float>(kInf); }, "rangeUnits"},
      {"rangeUnits 0", [](auto& o) { o.rangeUnits = 0.0f; }, "rangeUnits"},
      {"rangeUnits negative", [](auto& o) { o.rangeUnits = -0.001f; }, "rangeUnits"},
      {"fx = 0", [](auto& o) { o.cameraParams.intrinsicParams(0, 0) = 0.0; }, "intrinsics"},
      {"fx NaN", [](auto& o) { o.cameraParams.intrinsicParams(0, 0) = kNaN; }, "intrinsics"},
      {"sensorPose x NaN",
       [](auto& o) { o.sensorPose = CPose3D(kNaN, 0, 0.6, 0, 0, 0); }, "sensorPose"},
      {"sensorPose yaw NaN",
       [](auto& o) { o.sensorPose = CPose3D(0.3, 0, 0.6, kNaN, 0, 0); }, "sensorPose"},
      {"image size not the intrinsics'",
       [](auto& o)
       {
         o.rangeImage_setSize(24, 32);
         fill(o, 2000);
       },
       "intrinsics for"},
      {"hasRangeImage = false", [](auto& o) { o.hasRangeImage = false; }, "no range image"},
  };
  return faults;
}
}  // namespace

// ===================================================== 1. faulty cameras

TEST(Faults, GarbageCameraIsSkippedNamedAndEqualsItsAbsence)
{
  // Stop 1 of the tour with camera 3 corrupted must give exactly the maps of
  // stop 1 without camera 3, and say which camera and why.
  constexpr std::size_t kCam = 3;
  for (const auto& fault : cameraFaults())
  {
    SCOPED_TRACE(fault.name);
    auto bad = recordedStops(3);
    const std::string label = camera(bad[1], kCam).sensorLabel;
    fault.inject(camera(bad[1], kCam));
    auto ref = recordedStops(3);
    ref[1].sf->eraseByLabel(label);
    const auto a = runSlam(bad);
    const auto b = runSlam(ref);

    const auto& rep = a->reports()[1];
    EXPECT_EQ(rep.cameras_used, 7u);
    ASSERT_EQ(rep.camera_issues.size(), 1u);
    EXPECT_EQ(rep.camera_issues[0].label, label);
    EXPECT_TRUE(rep.camera_issues[0].skipped);
    EXPECT_NE(rep.camera_issues[0].reason.find(fault.reason), std::string::npos)
        << rep.camera_issues[0].reason;
    ASSERT_EQ(rep.warnings.size(), 1u);
    EXPECT_NE(rep.warnings[0].find(label), std::string::npos) << rep.warnings[0];
    EXPECT_TRUE(rep.integrated);
    EXPECT_FALSE(rep.flagged) << rep.icp.reason;

    EXPECT_EQ(a->currentPose(), b->currentPose());
    EXPECT_EQ(a->metaview().size(), b->metaview().size());
    EXPECT_TRUE(metaviewSane(a->metaview()));
    EXPECT_EQ(a->octomap().numLeafNodes(), b->octomap().numLeafNodes());
    EXPECT_EQ(a->octomap().occupiedVoxelCenters(), b->octomap().occupiedVoxelCenters());
  }
}

TEST(Faults, MissingCameraIsReportedAndTheRestIsUsed)
{
  auto stops = recordedStops(3);
  const std::string label = camera(stops[1], 5).sensorLabel;
  stops[1].sf->eraseByLabel(label);
  const auto slam = runSlam(stops);
  const auto& rep = slam->reports()[1];
  EXPECT_EQ(rep.cameras_used, 7u);
  ASSERT_EQ(rep.camera_issues.size(), 1u);
  EXPECT_EQ(rep.camera_issues[0].label, label);
  EXPECT_NE(rep.camera_issues[0].reason.find("missing"), std::string::npos);
  EXPECT_TRUE(rep.icp.accepted) << rep.icp.reason;
  EXPECT_TRUE(slam->reports()[2].camera_issues.empty()) << "back at stop 2";
}

TEST(Faults, FewImpossiblePixelsAreDroppedNotTheCamera)
{
  // 5 % saturated pixels: the camera is used, those pixels are no return.
  auto bad = recordedStops(3), ref = recordedStops(3);
  auto& ob = camera(bad[1], 0);
  auto& orf = camera(ref[1], 0);
  std::size_t n = 0;
  for (int r = 0; r < ob.rangeImage.rows(); r++)
    for (int c = 0; c < ob.rangeImage.cols(); c += 20, n++)
    {
      ob.rangeImage(r, c) = 0xFFFF;
      orf.rangeImage(r, c) = 0;
    }
  const auto a = runSlam(bad);
  const auto b = runSlam(ref);
  const auto& rep = a->reports()[1];
  EXPECT_EQ(rep.cameras_used, 8u);
  ASSERT_EQ(rep.camera_issues.size(), 1u);
  EXPECT_FALSE(rep.camera_issues[0].skipped);
  EXPECT_NE(rep.camera_issues[0].reason.find("dropped"), std::string::npos);
  EXPECT_EQ(a->currentPose(), b->currentPose());
  EXPECT_EQ(a->octomap().occupiedVoxelCenters(), b->octomap().occupiedVoxelCenters());
  EXPECT_EQ(a->octomap().numLeafNodes(), b->octomap().numLeafNodes());
  // The keyframe keeps the cleaned image, not the saturated one.
  const auto kf_obs = mapping::allDepthObservationsOf(*a->simplemap().getAsPair(1).sf);
  for (const auto& o : kf_obs)
    for (int r = 0; r < o->rangeImage.rows(); r++)
      for (int c = 0; c < o->rangeImage.cols(); c++) ASSERT_NE(o->rangeImage(r, c), 0xFFFF);
}

TEST(Faults, OctoMapLayerAndMetaviewRefuseNonFiniteInput)
{
  // Directly, without SlamIcp's checks: nothing non-finite reaches OctoMap's
  // key computation (undefined behaviour) or the metaview's hash grid.
  const auto stops = recordedStops(1);
  const std::vector<std::pair<const char*, std::function<void(CObservation3DRangeScan&)>>> cases = {
      {"sensorPose NaN", [](auto& o) { o.sensorPose = CPose3D(kNaN, 0, 0.6, 0, 0, 0); }},
      {"rangeUnits NaN", [](auto& o) { o.rangeUnits = static_cast<float>(kNaN); }},
      {"rangeUnits inf", [](auto& o) { o.rangeUnits = static_cast<float>(kInf); }},
      {"rangeUnits negative", [](auto& o) { o.rangeUnits = -0.001f; }},
      {"fx = 0", [](auto& o) { o.cameraParams.intrinsicParams(0, 0) = 0.0; }},
  };
  for (const auto& [name, inject] : cases)
  {
    auto o = camera(stops[0], 0);  // a copy
    inject(o);
    for (const bool stock : {false, true})
    {
      mapping::OctoMapLayer layer;
      const auto st = stock ? layer.insertScanStock(o, CPose3D()) : layer.insertScan(o, CPose3D());
      EXPECT_EQ(layer.numLeafNodes(), 0u) << name << (stock ? " (stock)" : "");
      EXPECT_EQ(st.invalid, static_cast<std::size_t>(o.rangeImage.rows() * o.rangeImage.cols()))
          << name;
    }
  }
  // A robot pose far outside the octree, and a NaN query point.
  mapping::OctoMapLayer layer;
  const auto st = layer.insertScan(camera(stops[0], 0), CPose3D(1e30, 0, 0, 0, 0, 0));
  EXPECT_EQ(st.hits, 0u);
  EXPECT_EQ(layer.numLeafNodes(), 0u);
  EXPECT_EQ(layer.stateAt({kNaN, 0, 0}), mapping::VoxelState::Unknown);

  mapping::Metaview m;
  mrpt::maps::CSimplePointsMap cloud;
  cloud.insertPoint(1, 2, 0.5);
  cloud.insertPoint(static_cast<float>(kNaN), 2, 0.5);
  cloud.insertPoint(3, static_cast<float>(kInf), 0.5);
  EXPECT_EQ(m.insert(cloud, CPose2D(kNaN, 0, 0)), 0u);
  EXPECT_EQ(m.insert(cloud, CPose2D(0, 0, kInf)), 0u);
  EXPECT_EQ(m.insert(cloud, CPose2D()), 1u);
}

TEST(Faults, ReplayWithGarbageCamerasStaysWithinMillimetresOfTheCleanRun)
{
  // Every 3rd stop has one broken camera, every 6th a second one; faults
  // rotate through the whole list, and one stop lacks a camera.
  auto stops = recordedStops();
  const auto& faults = cameraFaults();
  std::size_t injected = 0, k = 0;
  for (std::size_t i = 1; i < stops.size(); i++)
  {
    if (i % 3 != 1) continue;
    const std::size_t cams = i % 6 == 1 ? 2 : 1;
    for (std::size_t c = 0; c < cams; c++, k++, injected++)
    {
      // MRPT's deserialisation "autofixes" a TCamera whose size differs from
      // the range image (keeping the old fx, cx): that fault cannot survive
      // a rawlog, it is covered in memory above.
      if (std::string(faults[k % faults.size()].name).rfind("image size", 0) == 0) k++;
      faults[k % faults.size()].inject(camera(stops[i], (i + 3 * c) % 8));
    }
  }
  const std::string missing = camera(stops[20], 6).sensorLabel;  // a copy: erasing frees it
  stops[20].sf->eraseByLabel(missing);
  injected++;
  const auto s = replay(writeRawlog(stops, "garbage_rawlog"), "replay_garbage");
  const auto& clean = cleanReplay();
  std::cout << "[ faults ] " << injected << " faulty cameras in " << s.stops
            << " stops: ATE RMSE " << s.ate_rmse_m * 1e3 << " mm (clean "
            << clean.ate_rmse_m * 1e3 << " mm), final yaw error " << s.final_yaw_error_deg
            << " deg, " << s.flagged << " flagged, " << s.warnings << " warnings\n";
  EXPECT_EQ(s.stops, 49u);
  EXPECT_EQ(s.skipped_cameras, injected);
  EXPECT_EQ(s.warnings, injected);
  EXPECT_EQ(s.flagged, 0u);
  EXPECT_EQ(s.integrated, 49u);
  EXPECT_LT(std::abs(s.ate_rmse_m - clean.ate_rmse_m), 0.003);
  const auto sum = readJson(test::tempPath("replay_garbage") + "/summary.json");
  EXPECT_EQ(sum["skipped_cameras"].get<std::size_t>(), injected);
  // Every output loads.
  octomap::OcTree tree(test::tempPath("replay_garbage") + "/map.bt");
  EXPECT_GT(tree.getNumLeafNodes(), 1000u);
}

// ============================================= 2. stops without usable data

TEST(Faults, StopWithoutCamerasKeepsThePredictionFlaggedAndOutOfTheMaps)
{
  auto stops = recordedStops(6);
  auto empty = std::make_shared<mrpt::obs::CSensoryFrame>();
  for (const auto& o : *stops[2].sf)
    if (!std::dynamic_pointer_cast<CObservation3DRangeScan>(o)) empty->insert(o);
  ASSERT_EQ(empty->size(), 1u) << "the odometry observation";
  stops[2].sf = empty;
  const auto slam = runSlam(stops);
  const auto clean = runSlam(recordedStops(6));
  const auto& rep = slam->reports()[2];
  EXPECT_TRUE(rep.flagged);
  EXPECT_FALSE(rep.integrated);
  EXPECT_EQ(rep.cameras_used, 0u);
  EXPECT_NE(rep.icp.reason.find("no usable depth image"), std::string::npos) << rep.icp.reason;
  EXPECT_EQ(rep.pose, rep.predicted);
  EXPECT_EQ(rep.metaview_added, 0u);
  EXPECT_EQ(rep.metaview_size, slam->reports()[1].metaview_size);
  EXPECT_EQ(slam->simplemap().size(), 5u) << "no keyframe for the stop without data";
  // Registration resumes at stop 3 and the trajectory ends where the clean one does.
  for (std::size_t i = 3; i < 6; i++) EXPECT_TRUE(slam->reports()[i].icp.accepted) << i;
  EXPECT_NEAR(slam->currentPose().distanceTo(clean->currentPose()), 0.0, 0.005);
}

TEST(Faults, NonFiniteOdometryCountsAsNoMotionAndIcpFindsThePose)
{
  auto stops = recordedStops(5);
  stops[2].odometry = CPose2D(kNaN, 0.0, 0.0);
  const auto slam = runSlam(stops);
  const auto clean = runSlam(recordedStops(5));
  const auto& rep = slam->reports()[2];
  ASSERT_EQ(rep.warnings.size(), 1u);
  EXPECT_NE(rep.warnings[0].find("odometry reading not finite"), std::string::npos);
  EXPECT_EQ(rep.predicted, slam->reports()[1].pose) << "no motion assumed";
  for (const auto& r : slam->reports()) EXPECT_TRUE(finite(r.pose)) << r.index;
  // The stops are 0.5 m apart: ICP (or the relocalisation) still finds stop 2.
  EXPECT_NEAR(rep.pose.distanceTo(clean->reports()[2].pose), 0.0, 0.01) << rep.icp.reason;
  EXPECT_TRUE(metaviewSane(slam->metaview()));
}

TEST(Faults, AllCamerasInvalidForTheFirstStopsThenTheMapStarts)
{
  // Stops 0-2 have no usable image (rangeUnits NaN everywhere): the map
  // frame is still stop 0, stops 1-2 keep odometry (flagged), stop 3 starts
  // the metaview from odometry (flagged, integrated), ICP runs from stop 4.
  auto stops = recordedStops();
  for (std::size_t i = 0; i < 3; i++)
    for (std::size_t c = 0; c < 8; c++) camera(stops[i], c).rangeUnits = static_cast<float>(kNaN);
  const auto rawlog = writeRawlog(stops, "first_invalid_rawlog");
  const auto s = replay(rawlog, "replay_first_invalid");
  std::cout << "[ faults ] first 3 stops blind: ATE " << s.ate_rmse_m * 1e3 << " mm, "
            << s.flagged << " flagged, " << s.integrated << " integrated\n";
  EXPECT_EQ(s.stops, 49u);
  EXPECT_EQ(s.flagged, 3u);
  EXPECT_EQ(s.integrated, 46u);
  EXPECT_EQ(s.skipped_cameras, 24u);
  EXPECT_LT(s.ate_rmse_m, 0.03);

  const auto slam = runSlam(std::vector<Stop>(stops.begin(), stops.begin() + 6));
  const auto& r = slam->reports();
  EXPECT_EQ(r[0].pose, CPose2D());
  EXPECT_FALSE(r[0].integrated);
  EXPECT_NE(r[1].icp.reason.find("no usable depth image"), std::string::npos);
  EXPECT_NE(r[3].icp.reason.find("metaview empty"), std::string::npos) << r[3].icp.reason;
  EXPECT_TRUE(r[3].flagged);
  EXPECT_TRUE(r[3].integrated);
  EXPECT_TRUE(r[4].icp.accepted) << r[4].icp.reason;
  for (const auto& rep : r) EXPECT_TRUE(finite(rep.pose));
}

// ==================================================== 3. ICP and the scene

TEST(Faults, IcpThatDoesNotConvergeIsRejectedNeverNaN)
{
  auto p = mapping::SlamIcpParams{};
  p.icp.max_iterations = 1;
  p.icp.coarse_iterations = 0;
  auto stops = recordedStops(12);
  // A 15 cm odometry error at stop 6: one Gauss-Newton step cannot absorb it.
  for (std::size_t i = 6; i < stops.size(); i++)
    stops[i].odometry = CPose2D(0.15, 0.0, 0.0) + stops[i].odometry;
  const auto slam = runSlam(stops, p);
  std::size_t not_converged = 0;
  for (const auto& r : slam->reports())
  {
    EXPECT_TRUE(finite(r.pose)) << r.index;
    if (r.index == 0) continue;
    EXPECT_EQ(r.flagged, !r.icp.accepted) << r.index;
    EXPECT_EQ(r.integrated, r.icp.accepted) << r.index;
    if (r.icp.accepted)
    {
      EXPECT_LE(r.icp.last_step_m, p.icp.max_unconverged_step_m) << r.index;
    }
    not_converged += r.icp.reason.find("did not converge") != std::string::npos;
  }
  EXPECT_GE(not_converged, 1u);
  EXPECT_TRUE(slam->reports()[6].flagged) << slam->reports()[6].icp.reason;
  EXPECT_TRUE(metaviewSane(slam->metaview()));
}

TEST(Faults, OpenHallStopIsFlaggedAndTheNextOneRegistersAgain)
{
  // A 60 x 60 m hall with one box: at (10, 0) nothing but floor is within
  // the cameras' 7 m.
  sim::World w;
  w.mesh.addQuad({-30, -30, 0}, {30, -30, 0}, {30, 30, 0}, {-30, 30, 0});
  w.mesh.addBox({2.5f, 0.0f, 0.5f}, {0.8f, 1.6f, 1.0f});
  w.mesh.addBox({-1.5f, 2.5f, 0.5f}, {1.0f, 0.6f, 1.0f}, 0.4f);
  sim::RayCaster caster(w.mesh);
  sim::DepthCameraRig rig{sim::CameraRigParams{}};
  std::mt19937_64 rng(7);
  mapping::SlamIcp slam{mapping::SlamIcpParams{}};
  const std::vector<CPose2D> truth = {CPose2D(0, 0, 0), CPose2D(12, 0, 0), CPose2D(0.2, 0.1, 0.05)};
  std::vector<mapping::StopReport> reps;
  for (std::size_t i = 0; i < truth.size(); i++)
  {
    mrpt::obs::CSensoryFrame sf;
    for (const auto& o : rig.scan(caster, CPose3D(truth[i]), mrpt::Clock::fromDouble(i), rng, false))
      sf.insert(o);
    const CPose2D odo = truth[i] + CPose2D(0.01 * double(i), 0, 0);  // a little odometry error
    reps.push_back(slam.processStop(sf, odo, mrpt::Clock::fromDouble(i)));
  }
  EXPECT_LT(reps[1].cloud_points, 50u);
  EXPECT_TRUE(reps[1].flagged);
  EXPECT_FALSE(reps[1].integrated);
  EXPECT_NE(reps[1].icp.reason.find("too few points"), std::string::npos) << reps[1].icp.reason;
  EXPECT_TRUE(finite(reps[1].pose));
  EXPECT_TRUE(reps[2].icp.accepted) << reps[2].icp.reason;
  EXPECT_NEAR(reps[2].pose.distanceTo(truth[2]), 0.0, 0.01);
}

// ========================================================= 4. odometry jump

namespace
{
struct JumpOutcome
{
  std::size_t flagged = 0, right = 0, wrong_integrated = 0, relocalized = 0, occupied = 0;
  double precision = 0;
};

/// Kidnap at stop `k`: odometry believes the robot 1 m further ahead and
/// turned by 30 deg more than it is (E in the robot frame at stop k), and
/// keeps the offset afterwards: r'_i = J + r_i with J = r_k + E - r_k, so the
/// robot-frame increments after the jump are unchanged.
JumpOutcome odometryJump(std::size_t k, const mapping::SlamIcpParams& p,
                         const mapping::SlamIcp& clean)
{
  auto stops = recordedStops();
  const CPose2D E(1.0, 0.0, mrpt::DEG2RAD(30.0));
  const CPose2D rk = stops[k].odometry;
  const CPose2D J = (rk + E) + (CPose2D() - rk);
  for (std::size_t i = k; i < stops.size(); i++) stops[i].odometry = J + stops[i].odometry;
  const auto slam = runSlam(stops, p);
  JumpOutcome o;
  for (std::size_t i = k; i < stops.size(); i++)
  {
    const auto& r = slam->reports()[i];
    const auto& c = clean.reports()[i];
    const bool right = r.pose.distanceTo(c.pose) < 0.05 &&
                       std::abs(mrpt::math::wrapToPi(r.pose.phi() - c.pose.phi())) < mrpt::DEG2RAD(1.0);
    o.flagged += r.flagged;
    o.right += right;
    o.relocalized += r.relocalized;
    o.wrong_integrated += r.integrated && !right;
    if (std::getenv("VOXPLORE_TEST_VERBOSE"))
      std::cout << "  stop " << i << ": " << (right ? "right" : "WRONG") << " pose " << r.pose
                << " clean " << c.pose << " pred " << r.predicted << " flagged " << r.flagged
                << " reason " << r.icp.reason << "\n";
  }
  EXPECT_TRUE(metaviewSane(slam->metaview()));
  o.precision = precisionAgainstGt(slam->octomap());
  o.occupied = slam->octomap().occupiedVoxelCenters().size();
  return o;
}
}  // namespace

TEST(Faults, OdometryJumpIsRelocalizedOrRejectedAndNeverCorruptsTheMap)
{
  constexpr std::size_t kJump = 20, kAfter = 49 - kJump;
  const auto clean = runSlam(recordedStops());
  const double prec_clean = precisionAgainstGt(clean->octomap());
  const std::size_t occ_clean = clean->octomap().occupiedVoxelCenters().size();

  // Default: ICP rejects the prediction, the relocalisation finds the pose.
  const auto on = odometryJump(kJump, mapping::SlamIcpParams{}, *clean);
  // Without relocalisation and without the confirmation of large
  // corrections: every later stop is rejected and stays out of the map.
  mapping::SlamIcpParams no_reloc;
  no_reloc.icp.relocalize = false;
  no_reloc.icp.confirm_large_corrections = false;
  const auto off = odometryJump(kJump, no_reloc, *clean);
  // Without relocalisation but with the confirmation: ICP found the jump
  // from the bad prediction; refused for its size, then confirmed by the
  // next stop.
  mapping::SlamIcpParams confirm_only;
  confirm_only.icp.relocalize = false;
  const auto confirmed = odometryJump(kJump, confirm_only, *clean);
  std::cout << "[ faults ] confirmation only: " << confirmed.flagged << " flagged, " << confirmed.right
            << " of " << kAfter << " later poses right, precision " << confirmed.precision << "\n";
  EXPECT_EQ(confirmed.wrong_integrated, 0u);
  EXPECT_LE(confirmed.flagged, 3u);
  EXPECT_GE(confirmed.right, kAfter - 2);
  EXPECT_GE(confirmed.precision, prec_clean - 0.01);
  std::cout << "[ faults ] odometry jump 1 m / 30 deg at stop " << kJump << ": relocalisation on: "
            << on.relocalized << " relocalized, " << on.right << " of " << kAfter
            << " later poses right, " << on.flagged << " flagged, map precision " << on.precision
            << ", " << on.occupied << " occupied voxels; off: " << off.flagged << " flagged, "
            << off.right << " right, precision " << off.precision << ", " << off.occupied
            << " occupied; clean: precision " << prec_clean << ", " << occ_clean << " occupied\n";
  EXPECT_EQ(on.wrong_integrated, 0u) << "a stop with a wrong pose entered the map";
  EXPECT_GE(on.relocalized, 1u);
  EXPECT_EQ(on.right, kAfter);
  EXPECT_GE(on.precision, prec_clean - 0.01);
  EXPECT_GT(on.occupied, occ_clean * 95 / 100);

  EXPECT_EQ(off.wrong_integrated, 0u);
  EXPECT_EQ(off.flagged, kAfter);
  EXPECT_GE(off.precision, prec_clean - 0.01);
  EXPECT_LT(off.occupied, occ_clean) << "the map stopped growing";
}

// ================================================ 5. navigation-level faults

namespace
{
/// A .world file in the test's scratch directory.
std::string writeWorld(const std::string& name, const std::string& elements, double sx, double sy,
                       double yaw_deg = 0)
{
  const auto path = test::tempPath(name + ".world");
  std::ofstream(path) << "{\"name\": \"" << name << "\", \"start\": {\"x\": " << sx
                      << ", \"y\": " << sy << ", \"yaw_deg\": " << yaw_deg
                      << "}, \"elements\": [" << elements << "]}";
  return path;
}

std::string wall(double x0, double y0, double x1, double y1, double thickness = 0.1)
{
  std::ostringstream os;
  os << "{\"type\": \"wall\", \"from\": [" << x0 << ", " << y0 << "], \"to\": [" << x1 << ", "
     << y1 << "], \"thickness\": " << thickness << ", \"height\": 2.0}";
  return os.str();
}

/// Four walls round [x0, x1] x [y0, y1] (free inside), thickness 0.1 m.
std::string room(double x0, double y0, double x1, double y1)
{
  return wall(x0 - 0.1, y0 - 0.05, x1 + 0.1, y0 - 0.05) + ", " +
         wall(x0 - 0.1, y1 + 0.05, x1 + 0.1, y1 + 0.05) + ", " +
         wall(x0 - 0.05, y0, x0 - 0.05, y1) + ", " + wall(x1 + 0.05, y0, x1 + 0.05, y1);
}

apps::ExploreOptions exploreOpts(const std::string& world, const std::string& out, int max_steps,
                                 double max_sim_time_s, const std::string& extra_ini = "")
{
  const auto ini = test::tempPath(out + ".ini");
  std::ofstream(ini) << "[explore]\nmax_steps = " << max_steps
                     << "\nmax_sim_time_s = " << max_sim_time_s
                     << "\nwrite_step_images = false\n"
                     << extra_ini;
  apps::ExploreOptions o;
  o.config = ini;
  o.world = world;
  o.out_dir = test::tempPath(out);
  o.quiet = true;
  return o;
}

bool isPlannerReason(const std::string& r)
{
  return r == "no frontier" || r == "no reachable frontier" || r == "all skipped";
}

/// The run ended by itself within its limits and wrote a consistent summary.
void expectExplicitEnd(const apps::ExploreSummary& s, const apps::ExploreOptions& o, int max_steps,
                       double max_sim_time_s)
{
  EXPECT_FALSE(s.termination_reason.empty());
  EXPECT_LE(s.steps, static_cast<std::size_t>(max_steps));
  EXPECT_LE(s.sim_time_s, max_sim_time_s + 0.11);  // one navigation period at most
  const auto sum = readJson(fs::path(o.out_dir) / "summary.json");
  EXPECT_EQ(sum["termination_reason"].get<std::string>(), s.termination_reason);
  EXPECT_EQ(common::readTum(o.out_dir + "/trajectory_est.tum").size(), s.stops);
}
}  // namespace

TEST(Faults, RobotBoxedInAClosetEndsWithAPlannerReason)
{
  // A closet 1.6 x 1.0 m round the 1.2 x 0.712 m omniRob.
  const auto world = writeWorld("closet", room(1.2, 1.5, 2.8, 2.5), 2.0, 2.0);
  const auto o = exploreOpts(world, "closet", 10, 600);
  const auto s = apps::ExploreApp{}.execute(o);
  std::cout << "[ faults ] boxed in: '" << s.termination_reason << "' after " << s.steps
            << " steps, " << s.stops << " stops, " << s.failed_drives << " failed drives, "
            << s.collisions << " collisions, path " << s.path_length_m << " m\n";
  expectExplicitEnd(s, o, 10, 600);
  EXPECT_TRUE(isPlannerReason(s.termination_reason)) << s.termination_reason;
  EXPECT_EQ(s.collisions, 0u);
  EXPECT_LT(s.path_length_m, 0.5);
}

TEST(Faults, RoomBehindANarrowGapIsUnreachableAndTheRunEnds)
{
  // Two rooms joined by a 0.4 m slit the cameras see through but the robot
  // cannot pass: no path leads to the far room (the planner's frontier
  // search only reaches cells the robot can reach, so it reports the
  // reachable space explored), and the robot never squeezes through.
  const std::string walls = room(0, 0, 8, 4) + ", " + wall(4, 0, 4, 1.8, 0.1) + ", " +
                            wall(4, 2.2, 4, 4, 0.1);
  const auto world = writeWorld("slit", walls, 1.5, 2.0);
  const auto o = exploreOpts(world, "slit", 12, 900);
  const auto s = apps::ExploreApp{}.execute(o);
  std::cout << "[ faults ] slit: '" << s.termination_reason << "' after " << s.steps << " steps, "
            << s.failed_drives << " failed drives, " << s.blacklisted << " blacklisted, "
            << s.collisions << " collisions, coverage " << s.coverage_2d << "\n";
  expectExplicitEnd(s, o, 12, 900);
  EXPECT_TRUE(isPlannerReason(s.termination_reason)) << s.termination_reason;
  EXPECT_EQ(s.collisions, 0u);
  // The far room is never reached (the reachable floor is the near room).
  for (const auto& p : common::readTum(o.out_dir + "/trajectory_gt.tum"))
    EXPECT_LT(p.pose.x(), 4.0);
}

TEST(Faults, UnreachableWaypointBehindALowCurbIsGivenUp)
{
  // A 6 cm curb across the room: below the planner's voxel columns (z_min
  // 0.10 m) and the navigator's lowest ray (0.10 m), but the footprint cannot
  // cross it. Without the low obstacle cells the drives beyond it fail; with
  // them (the default) the planner never plans across it. Either way the run
  // must end by itself on this side.
  const std::string elements =
      room(0, 0, 9, 4) + ", {\"type\": \"box\", \"center\": [4.5, 2.0, 0.03], \"size\": [0.2, 4.0, 0.06]}";
  const auto world = writeWorld("curb", elements, 2.0, 2.0);
  for (const bool low : {false, true})
  {
    SCOPED_TRACE(low ? "low obstacles" : "low obstacles off");
    const std::string name = low ? "curb_low" : "curb";
    const auto o = exploreOpts(world, name, 12, 900,
                               low ? "" : "[octomap]\nlow_obstacle_min_z_m = 0\n");
    const auto s = apps::ExploreApp{}.execute(o);
    std::cout << "[ faults ] " << name << ": '" << s.termination_reason << "' after " << s.steps
              << " steps, " << s.failed_drives << " failed drives, " << s.blacklisted
              << " blacklisted, " << s.collisions << " refused steps, sim " << s.sim_time_s << " s\n";
    expectExplicitEnd(s, o, 12, 900);
    if (low)
      EXPECT_EQ(s.failed_drives, 0u) << "the curb is in the planner's map";
    else
      EXPECT_GE(s.failed_drives, 1u);
    for (const auto& p : common::readTum(o.out_dir + "/trajectory_gt.tum"))
      EXPECT_LT(p.pose.x(), 4.5);
  }
}

TEST(Faults, StepAndSimTimeLimitsAlwaysHold)
{
  const std::string dlr = test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
  {
    const auto o = exploreOpts(dlr, "limit_steps", 2, 3600);
    const auto s = apps::ExploreApp{}.execute(o);
    EXPECT_EQ(s.termination_reason, "max_steps");
    EXPECT_EQ(s.steps, 2u);
    expectExplicitEnd(s, o, 2, 3600);
  }
  {
    // 12 s of simulated time ends inside the first drive (the limit holds
    // mid-drive); the maps so far are complete and loadable.
    const auto o = exploreOpts(dlr, "limit_time", 100, 12.0);
    const auto s = apps::ExploreApp{}.execute(o);
    EXPECT_EQ(s.termination_reason, "max_sim_time");
    EXPECT_LE(s.sim_time_s, 12.0 + 0.051);
    EXPECT_GT(s.path_length_m, 0.1) << "stopped while driving";
    expectExplicitEnd(s, o, 100, 12.0);
    octomap::OcTree tree(o.out_dir + "/map.bt");
    EXPECT_GT(tree.getNumLeafNodes(), 100u);
  }
}

// ============================================== 6. SIGINT mid-run (binaries)

namespace
{
/// Runs `argv` (absolute binary path first) with stdout and stderr to `log`.
pid_t spawn(const std::vector<std::string>& argv, const std::string& log)
{
  const pid_t pid = fork();
  if (pid == 0)
  {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

/// Waits until `ready()` or the child exits or `timeout_s`.
bool waitFor(pid_t pid, const std::function<bool()>& ready, double timeout_s)
{
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < timeout_s)
  {
    if (ready()) return true;
    int st;
    if (waitpid(pid, &st, WNOHANG) == pid) return false;  // exited early (reaped: test fails)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

/// Kills the child if it is still running (a failed wait must not leak it).
void stopChild(pid_t pid)
{
  int st = 0;
  if (waitpid(pid, &st, WNOHANG) == 0)
  {
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
  }
}

/// Exit code of the child (waits at most `timeout_s`, then kills it: -1).
int exitCode(pid_t pid, double timeout_s)
{
  const auto t0 = std::chrono::steady_clock::now();
  int st = 0;
  while (waitpid(pid, &st, WNOHANG) != pid)
  {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s)
    {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

}  // namespace

TEST(Faults, SigintStopsVoxploreExploreWithCompleteLoadableOutputs)
{
  const std::string bin = std::string(VOXPLORE_BIN_DIR) + "/voxplore-explore";
  if (!fs::exists(bin)) GTEST_SKIP() << "not built: " << bin;
  const auto out = test::tempPath("sigint_explore");
  fs::remove_all(out);
  const auto log = test::tempPath("sigint_explore.log");
  const pid_t pid =
      spawn({bin, "--config", test::sourceDir() + "/config/explore.ini", "--world",
             test::sourceDir() + "/simulated_worlds/dlr_test_room.world", "--out", out},
            log);
  ASSERT_GT(pid, 0);
  const bool ready = waitFor(pid, [&] { return fs::exists(out + "/steps/step_002.png"); }, 120);
  if (!ready) stopChild(pid);
  ASSERT_TRUE(ready) << test::readFile(log);
  kill(pid, SIGINT);
  const int code = exitCode(pid, 120);
  const std::string text = test::readFile(log);
  EXPECT_EQ(code, apps::kExitInterrupted) << text;
  EXPECT_NE(text.find("interrupted"), std::string::npos) << text;

  const auto sum = readJson(fs::path(out) / "summary.json");
  EXPECT_EQ(sum["termination_reason"].get<std::string>(), "interrupted");
  const auto stops = sum["stops"].get<std::size_t>();
  EXPECT_GE(stops, 2u);
  EXPECT_GE(sum["steps"].get<std::size_t>(), 2u);
  EXPECT_LT(sum["steps"].get<std::size_t>(), 15u) << "stopped early, not at the natural end";
  octomap::OcTree tree(out + "/map.bt");
  EXPECT_GT(tree.getNumLeafNodes(), 1000u);
  // Keyframes: the stops that entered the map (flagged ones do not).
  EXPECT_EQ(test::loadSimplemap(out + "/map.simplemap").size(), stops - sum["flagged_stops"].get<std::size_t>());
  // Held and kept stops: summary.json counts what stops.csv lists.
  {
    const auto rows = test::readCsv(out + "/stops.csv");
    EXPECT_EQ(rows.size(), stops);
    std::size_t held = 0, kept = 0;
    for (const auto& row : rows)
    {
      ASSERT_TRUE(row.count("icp_held") && row.count("odometry_kept")) << "stops.csv row without the columns";
      held += row.at("icp_held") == "1";
      kept += row.at("odometry_kept") == "1";
    }
    EXPECT_EQ(sum["held_stops"].get<std::size_t>(), held);
    EXPECT_EQ(sum["kept_stops"].get<std::size_t>(), kept);
  }
  std::size_t entries = 0;
  common::forEachRawlogEntry(out + "/run.rawlog", [&](const common::RawlogEntry&) {
    entries++;
    return true;
  });
  EXPECT_EQ(entries, stops);
  EXPECT_EQ(common::readTum(out + "/trajectory_gt.tum").size(), stops);
  EXPECT_EQ(common::readTum(out + "/trajectory_est.tum").size(), stops);
  mrpt::maps::CSimplePointsMap ply;
  EXPECT_TRUE(ply.loadFromPlyFile(out + "/metaview.ply"));
  EXPECT_GT(ply.size(), 1000u);
}

TEST(Faults, SigintStopsVoxploreReplayWithCompleteLoadableOutputs)
{
  const std::string bin = std::string(VOXPLORE_BIN_DIR) + "/voxplore-replay";
  if (!fs::exists(bin)) GTEST_SKIP() << "not built: " << bin;
  const auto out = test::tempPath("sigint_replay");
  fs::remove_all(out);
  const auto log = test::tempPath("sigint_replay.log");
  const pid_t pid = spawn({bin, "--config", test::sourceDir() + "/config/replay.ini", "--rawlog",
                           recorded(), "--out", out},
                          log);
  ASSERT_GT(pid, 0);
  const bool ready = waitFor(pid, [&] { return test::readFile(log).find("stop 3") != std::string::npos; }, 60);
  if (!ready) stopChild(pid);
  ASSERT_TRUE(ready) << test::readFile(log);
  kill(pid, SIGINT);
  const int code = exitCode(pid, 60);
  EXPECT_EQ(code, apps::kExitInterrupted) << test::readFile(log);
  const auto sum = readJson(fs::path(out) / "summary.json");
  EXPECT_EQ(sum["termination_reason"].get<std::string>(), "interrupted");
  const auto stops = sum["stops"].get<std::size_t>();
  EXPECT_GE(stops, 3u);
  EXPECT_LT(stops, 49u);
  octomap::OcTree tree(out + "/map.bt");
  EXPECT_GT(tree.getNumLeafNodes(), 100u);
  EXPECT_EQ(test::loadSimplemap(out + "/map.simplemap").size(), sum["integrated"].get<std::size_t>());
  EXPECT_EQ(common::readTum(out + "/trajectory_est.tum").size(), stops);
  EXPECT_TRUE(sum.contains("ate_rmse_m"));
}

// ==================================================== 7. bad output / config

TEST(Faults, UnwritableOutputDirectoryIsANamedErrorForEveryApp)
{
  // A path below a regular file cannot be created, even as root.
  const auto file = test::tempPath("not_a_dir");
  std::ofstream(file) << "x";
  const std::string bad = file + "/out";
  const auto dlr = test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
  auto expectNamed = [&](const std::function<void()>& f, const char* app)
  {
    try
    {
      f();
      ADD_FAILURE() << app << ": no error";
    }
    catch (const std::exception& e)
    {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << app << ": " << e.what();
    }
  };
  apps::ReplayOptions ro;
  ro.rawlog = recorded();
  ro.out_dir = bad;
  ro.quiet = true;
  expectNamed([&] { apps::ReplayApp{}.execute(ro); }, "voxplore-replay");
  apps::ExploreOptions eo;
  eo.world = dlr;
  eo.out_dir = bad;
  eo.quiet = true;
  expectNamed([&] { apps::ExploreApp{}.execute(eo); }, "voxplore-explore");
  apps::SimOptions so;
  so.world = dlr;
  so.waypoints = test::sourceDir() + "/simulated_worlds/dlr_test_room_tour.txt";
  so.out_dir = bad;
  so.quiet = true;
  expectNamed([&] { apps::SimApp{}.execute(so); }, "mrpt-sim");

  // The command lines exit non-zero with the directory in the message.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cmds = {
      {"voxplore-replay", {"--rawlog", recorded(), "--out", bad, "-q"}},
      {"voxplore-explore", {"--world", dlr, "--out", bad, "-q"}},
      {"mrpt-sim", {"--world", dlr, "--waypoints", so.waypoints, "--out", bad, "-q"}}};
  for (const auto& [app, args] : cmds)
  {
    const std::string bin = std::string(VOXPLORE_BIN_DIR) + "/" + app;
    if (!fs::exists(bin)) continue;
    std::vector<std::string> argv = {bin};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto log = test::tempPath(app + "_badout.log");
    const int code = exitCode(spawn(argv, log), 120);
    EXPECT_NE(code, 0) << app;
    EXPECT_NE(code, -1) << app << " hung";
    EXPECT_NE(test::readFile(log).find(bad), std::string::npos) << app << ": " << test::readFile(log);
  }
}

TEST(Faults, OutOfRangeAndMisorderedValuesAreNamedErrorsInEveryAppsConfig)
{
  // Through each app's own loading path: the message names the file and key.
  const auto dlr = test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
  struct Case
  {
    const char* app;
    const char* ini;
    const char* key;
  };
  const std::vector<Case> cases = {
      {"replay", "[octomap]\nl_res_m = -0.05\n", "l_res_m"},
      {"replay", "[octomap]\nth_free = 200\nth_occ = 100\n", "th_"},
      {"replay", "[cloud]\nz_min_m = 0.5\nz_max_m = 0.1\n", "z_min_m"},
      {"replay", "[icp]\nd_max_m = 0.1\nd_max_final_m = 0.2\n", "d_max_final_m"},
      {"replay", "[cloud]\nmax_impossible_share = 1.5\n", "max_impossible_share"},
      {"replay", "[icp]\nmax_unconverged_step_m = -1\n", "max_unconverged_step_m"},
      {"explore", "[cameras]\nnum_cameras = 0\n", "num_cameras"},
      {"explore", "[octomap]\nl_res_m = -0.05\n", "l_res_m"},
      {"explore", "[projection]\nth_free = 240\nth_occ = 70\n", "th_occ"},
      {"explore", "[sampling]\nth_f1_m = 0.1\nth_f2_m = 0.5\n", "th_f1_m"},
      {"explore", "[explore]\nband_z_min_m = 0.6\nband_z_max_m = 0.1\n", "band_z_max_m"},
      {"explore", "[explore]\nmax_sim_time_s = -5\n", "max_sim_time_s"},
      {"sim", "[cameras]\nnum_cameras = 0\n", "num_cameras"},
      {"sim", "[simulator]\ndt_s = -0.05\n", "dt_s"},
  };
  for (const auto& c : cases)
  {
    const auto ini = test::tempPath(std::string("bad_") + c.app + ".ini");
    std::ofstream(ini) << c.ini;
    std::string msg;
    try
    {
      if (std::string(c.app) == "replay")
      {
        apps::ReplayOptions o;
        o.config = ini;
        o.rawlog = recorded();
        o.out_dir = test::tempPath("bad_cfg_out");
        o.quiet = true;
        apps::ReplayApp{}.execute(o);
      }
      else if (std::string(c.app) == "explore")
      {
        apps::ExploreOptions o;
        o.config = ini;
        o.world = dlr;
        o.out_dir = test::tempPath("bad_cfg_out");
        o.quiet = true;
        apps::ExploreApp{}.execute(o);
      }
      else
      {
        apps::SimOptions o;
        o.config = ini;
        o.world = dlr;
        o.waypoints = test::sourceDir() + "/simulated_worlds/dlr_test_room_tour.txt";
        o.out_dir = test::tempPath("bad_cfg_out");
        o.quiet = true;
        apps::SimApp{}.execute(o);
      }
    }
    catch (const std::exception& e)
    {
      msg = e.what();
    }
    EXPECT_NE(msg.find(ini), std::string::npos) << c.app << " " << c.ini << ": " << msg;
    EXPECT_NE(msg.find(c.key), std::string::npos) << c.app << " " << c.ini << ": " << msg;
  }
}
