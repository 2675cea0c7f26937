// Entropy scan rating (thesis 3.7, 4.5.4): known answers on synthetic maps,
// ours (rateScan) equal to the naive stock-OctoMap rating on a room map
// built by ray insertion, beam counts, bestRated and the parameters.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <octomap/OcTree.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/scan_rating.h>
#include <voxplore/sim/DepthCameraRig.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>

using namespace voxplore;
using exploration::rateScan;
using exploration::rateScanNaive;
using exploration::ScanRating;
using exploration::ScanRatingParams;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using octomap::OcTree;
using octomap::point3d;

namespace
{
double entropyOf(double p)
{
  return -(p * std::log(p) + (1 - p) * std::log(1 - p));
}

/// Sets every voxel of the box [lo, hi) to log-odds l.
void setBox(OcTree& t, const point3d& lo, const point3d& hi, float l)
{
  const double r = t.getResolution();
  for (double x = lo.x() + r / 2; x < hi.x(); x += r)
    for (double y = lo.y() + r / 2; y < hi.y(); y += r)
      for (double z = lo.z() + r / 2; z < hi.z(); z += r) t.setNodeValue(x, y, z, l);
}

/// rateScan on the portable walker (what CPUs without AVX2 run).
ScanRating rateScanPortable(const OcTree& t, const CPose2D& pose, const ScanRatingParams& p)
{
  setenv("VOXPLORE_SCAN_RATING_PORTABLE", "1", 1);
  const auto r = rateScan(t, pose, p);
  unsetenv("VOXPLORE_SCAN_RATING_PORTABLE");
  return r;
}

void expectSameRating(const ScanRating& fast, const ScanRating& naive, const std::string& what)
{
  EXPECT_EQ(fast.beams, naive.beams) << what;
  EXPECT_EQ(fast.voxels, naive.voxels) << what;
  EXPECT_EQ(fast.unknown_voxels, naive.unknown_voxels) << what;
  EXPECT_NEAR(fast.gain, naive.gain, 1e-9 * std::max(1.0, naive.gain)) << what;
}

/// One camera looking along the robot's +X from (0, 0, z) with a
/// width x height image.
ScanRatingParams oneCamera(double z, int width = 64, int height = 48)
{
  ScanRatingParams p;
  p.mounts = {CPose3D(0, 0, z, 0, 0, 0)};
  p.width_px = width;
  p.height_px = height;
  p.beam_reduction = 1;
  return p;
}

// ---------------------------------------------------------- a room by ray insertion
struct Box
{
  point3d lo, hi;
};

/// Distance along unit `d` from `o` to the first furniture box, the floor or
/// the room's walls and ceiling (o inside the room).
double castInRoom(const point3d& o, const point3d& d, const Box& room,
                  const std::vector<Box>& boxes)
{
  double best = 1e9;
  for (int i = 0; i < 3; i++)  // leaving the room box (walls, floor, ceiling)
  {
    if (d(i) > 0) best = std::min(best, double((room.hi(i) - o(i)) / d(i)));
    if (d(i) < 0) best = std::min(best, double((room.lo(i) - o(i)) / d(i)));
  }
  for (const Box& b : boxes)  // slab test
  {
    double t0 = 0, t1 = 1e9;
    for (int i = 0; i < 3 && t0 <= t1; i++)
    {
      if (std::abs(d(i)) < 1e-12)
      {
        if (o(i) < b.lo(i) || o(i) > b.hi(i)) t0 = 2e9;
        continue;
      }
      double a = (b.lo(i) - o(i)) / d(i), c = (b.hi(i) - o(i)) / d(i);
      if (a > c) std::swap(a, c);
      t0 = std::max(t0, a);
      t1 = std::min(t1, c);
    }
    if (t0 <= t1) best = std::min(best, t0);
  }
  return best;
}

/// An 8 x 6 x 2.2 m room with a table, a cabinet and a box, mapped at 5 cm
/// like voxplore-replay: 360 deg scans from a few stops at 0.6 m height,
/// noisy hits, floor returns (z < 0.10 m) dropped, 7 m range.
std::unique_ptr<OcTree> makeRoomMap()
{
  auto t = std::make_unique<OcTree>(0.05);
  t->setOccupancyThres(240 / 255.0);
  t->setProbHit(0.7);
  t->setProbMiss(0.4);
  t->setClampingThresMin(0.1192);
  t->setClampingThresMax(0.971);
  const Box room{point3d(-4, -3, 0), point3d(4, 3, 2.2f)};
  const std::vector<Box> furniture = {{point3d(1.0f, 0.5f, 0), point3d(2.2f, 1.3f, 0.75f)},
                                      {point3d(-3.9f, -2.9f, 0), point3d(-3.4f, -1.4f, 1.8f)},
                                      {point3d(-1.0f, 1.5f, 0), point3d(-0.4f, 2.1f, 0.5f)}};
  const std::vector<point3d> stops = {point3d(0, 0, 0.6f), point3d(-2, -1, 0.6f),
                                      point3d(2.5f, -1.5f, 0.6f), point3d(-1.5f, 2.4f, 0.6f)};
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (const point3d& o : stops)
  {
    octomap::Pointcloud cloud;
    for (double az = 0; az < 360; az += 1.5)
      for (double el = -40; el <= 10; el += 1.5)
      {
        const double a = az * M_PI / 180, e = el * M_PI / 180;
        const point3d d(float(std::cos(e) * std::cos(a)), float(std::cos(e) * std::sin(a)),
                        float(std::sin(e)));
        const double range = castInRoom(o, d, room, furniture) + noise(rng);
        const point3d hit = o + d * float(range);
        if (hit.z() >= 0.10f) cloud.push_back(hit);
      }
    t->insertPointCloud(cloud, o, 7.0);
  }
  return t;
}

const OcTree& roomMap()
{
  static const std::unique_ptr<OcTree> map = makeRoomMap();
  return *map;
}
}  // namespace

// ------------------------------------------------------------------- known answers
TEST(ScanRating, BeamStopsAtTheFirstOccupiedVoxelWhichCounts)
{
  // One pixel: its beam runs along +X from (0.01, 0.01, 0.51). All unknown
  // but an occupied voxel [1.00, 1.05) and a partly known one behind it.
  OcTree t(0.05);
  t.setNodeValue(1.025, 0.025, 0.525, octomap::logodds(0.97));
  t.setNodeValue(1.125, 0.025, 0.525, octomap::logodds(0.6));
  auto p = oneCamera(0.51, 1, 1);
  const CPose2D pose(0.01, 0.01, 0);
  for (const auto& r : {rateScan(t, pose, p), rateScanNaive(t, pose, p)})
  {
    EXPECT_EQ(r.beams, 1u);
    EXPECT_EQ(r.voxels, 21u);  // keys 0..20 along x: 20 unknown + the wall
    EXPECT_EQ(r.unknown_voxels, 20u);
    const double h_wall = entropyOf(octomap::probability(octomap::logodds(0.97)));
    EXPECT_NEAR(r.gain, 20 * std::log(2.0) + h_wall, 1e-12);
  }
  // Without the wall the beam runs its 7 m: 140 voxels + the end voxel's.
  OcTree open(0.05);
  const auto r = rateScan(open, pose, p);
  EXPECT_EQ(r.voxels, 141u);  // x keys of 0.01 .. 7.01
  EXPECT_EQ(r.unknown_voxels, r.voxels);
}

TEST(ScanRating, FacingUnknownSpaceOutratesFacingAKnownWall)
{
  // Known free half space x > -0.3 with a wall at x = 1 m; x < -0.3 unknown.
  OcTree t(0.1);
  t.setClampingThresMin(0.1192);
  setBox(t, point3d(-0.3f, -4, -4), point3d(1.0f, 4, 2), octomap::logodds(0.1192));
  setBox(t, point3d(1.0f, -4, -4), point3d(1.2f, 4, 2), octomap::logodds(0.971));
  const auto p = oneCamera(0.6);
  const CPose2D facing_wall(0, 0, 0), facing_unknown(0, 0, M_PI);
  const auto wall = rateScan(t, facing_wall, p);
  const auto unknown = rateScan(t, facing_unknown, p);
  EXPECT_GT(unknown.gain, 10 * wall.gain);
  EXPECT_EQ(wall.unknown_voxels, 0u);  // nothing behind the wall counts
  EXPECT_GT(unknown.unknown_voxels, 1000u);
  expectSameRating(wall, rateScanNaive(t, facing_wall, p), "facing wall");
  expectSameRating(unknown, rateScanNaive(t, facing_unknown, p), "facing unknown");
  const auto best = exploration::bestRated({wall, unknown});
  ASSERT_TRUE(best.has_value());
  EXPECT_EQ(*best, 1u);
}

TEST(ScanRating, AllKnownMapGainsOnlyFromPartlyKnownVoxels)
{
  // Every voxel within reach is known and certain (free p = 1e-30, walls
  // p = 1 - 1e-15: H ~ 1e-13 each), except each camera's own voxel, set to
  // p = 0.7, and one p = 0.7 voxel behind a wall. Gain: 8 H(0.7).
  OcTree t(0.1);
  t.setClampingThresMin(1e-30);
  t.setClampingThresMax(1 - 1e-15);
  setBox(t, point3d(-4, -4, -3), point3d(4, 4, 3), octomap::logodds(1e-30));
  for (float s : {-1.0f, 1.0f})
  {
    setBox(t, point3d(2.0f * s - 0.05f, -2.1f, -3), point3d(2.0f * s + 0.05f, 2.1f, 3),
           octomap::logodds(1 - 1e-15));
    setBox(t, point3d(-2.1f, 2.0f * s - 0.05f, -3), point3d(2.1f, 2.0f * s + 0.05f, 3),
           octomap::logodds(1 - 1e-15));
  }
  ScanRatingParams p;
  p.max_range_m = 2.9;  // stays inside the known box below the room's floor
  const CPose2D pose(0.13, -0.07, 0.3);
  octomap::KeySet cams;
  for (const auto& m : p.mounts)
  {
    const CPose3D c = CPose3D(pose) + m;
    const auto key = t.coordToKey(c.x(), c.y(), c.z());
    cams.insert(key);
    t.setNodeValue(key, octomap::logodds(0.7));
  }
  ASSERT_EQ(cams.size(), 8u);
  t.setNodeValue(3.0, 0.0, 0.55, octomap::logodds(0.7));  // behind the +X wall
  const double h07 = entropyOf(octomap::probability(octomap::logodds(0.7)));
  const auto r = rateScan(t, pose, p);
  EXPECT_EQ(r.unknown_voxels, 0u);
  EXPECT_GT(r.voxels, 1000u);
  EXPECT_NEAR(r.gain, 8 * h07, 1e-6);
  expectSameRating(r, rateScanNaive(t, pose, p), "all known");
}

TEST(ScanRating, VoxelsBehindAClosedWallNeverCount)
{
  // An occupied shell 1 m around the robot (also below and above); inside
  // unknown. Marking voxels outside the shell changes nothing.
  OcTree t(0.05);
  const float l_occ = octomap::logodds(0.97);
  setBox(t, point3d(-1.1f, -1.1f, -0.6f), point3d(1.1f, 1.1f, -0.5f), l_occ);
  setBox(t, point3d(-1.1f, -1.1f, 1.5f), point3d(1.1f, 1.1f, 1.6f), l_occ);
  for (float s : {-1.0f, 1.0f})
  {
    setBox(t, point3d(s - 0.05f, -1.1f, -0.6f), point3d(s + 0.05f, 1.1f, 1.6f), l_occ);
    setBox(t, point3d(-1.1f, s - 0.05f, -0.6f), point3d(1.1f, s + 0.05f, 1.6f), l_occ);
  }
  ScanRatingParams p;
  p.beam_reduction = 1;
  const CPose2D pose(0.02, 0.01, 0.4);
  const auto inside = rateScan(t, pose, p);
  // Interior: (1.9 m / 5 cm)^2 x 2 m / 5 cm voxels at most are unknown.
  EXPECT_LE(inside.unknown_voxels, 38u * 38u * 40u);
  EXPECT_GT(inside.unknown_voxels, 1000u);
  OcTree marked(t);
  setBox(marked, point3d(1.2f, -2, -1), point3d(3, 2, 2), octomap::logodds(0.6));
  const auto with_marks = rateScan(marked, pose, p);
  EXPECT_EQ(with_marks.voxels, inside.voxels);
  EXPECT_EQ(with_marks.gain, inside.gain);
  expectSameRating(with_marks, rateScanNaive(marked, pose, p), "closed shell");
  // Without the shell the same beams run their 7 m.
  EXPECT_GT(rateScan(OcTree(0.05), pose, p).voxels, 5 * inside.voxels);
}

TEST(ScanRating, BeamCountsPerReduction)
{
  // Every r-th pixel from (0, 0): ceil(64 / r) x ceil(48 / r) per camera.
  OcTree t(0.1);
  ScanRatingParams p;
  const std::vector<std::pair<int, std::size_t>> expected = {
      {1, 8u * 64 * 48}, {2, 8u * 32 * 24}, {3, 8u * 22 * 16}, {5, 8u * 13 * 10}};
  for (const auto& [r, n] : expected)
  {
    p.beam_reduction = r;
    EXPECT_EQ(rateScan(t, CPose2D(), p).beams, n) << "beam_reduction " << r;
    EXPECT_EQ(rateScanNaive(t, CPose2D(), p).beams, n) << "beam_reduction " << r;
  }
}

// ------------------------------------------------------------------ ours == naive
TEST(ScanRating, FastEqualsNaiveOnARoomMap)
{
  const OcTree& map = roomMap();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(-3.0, 3.0), uy(-2.0, 2.0), uyaw(-M_PI, M_PI);
  ScanRatingParams p;
  for (int i = 0; i < 6; i++)
  {
    p.beam_reduction = i < 1 ? 1 : 2;
    const CPose2D pose(ux(rng), uy(rng), uyaw(rng));
    const auto fast = rateScan(map, pose, p);
    const auto naive = rateScanNaive(map, pose, p);
    expectSameRating(fast, naive, "pose " + pose.asString());
    expectSameRating(rateScanPortable(map, pose, p), naive, "portable, pose " + pose.asString());
    EXPECT_GT(fast.voxels, fast.unknown_voxels);  // a mix of known and unknown
    EXPECT_GT(fast.unknown_voxels, 0u);
  }
}

TEST(ScanRating, FastEqualsNaiveWithManyDistinctValues)
{
  // ~80k voxels of random log-odds (more distinct values than ours interns:
  // the rest take the tree path), 13 % above th_occ.
  OcTree t(0.05);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> l(-2.0f, 3.5f);
  for (double x = -1.5; x < 1.5; x += 0.05)
    for (double y = -1.5; y < 1.5; y += 0.05)
      for (double z = 0.0; z < 1.1; z += 0.05)
        t.setNodeValue(x + 0.025, y + 0.025, z + 0.025, l(rng));
  ScanRatingParams p;
  p.beam_reduction = 1;
  for (const CPose2D& pose : {CPose2D(0.1, 0.2, 0.3), CPose2D(-0.7, 0.4, 2.0)})
  {
    const auto naive = rateScanNaive(t, pose, p);
    expectSameRating(rateScan(t, pose, p), naive, pose.asString());
    expectSameRating(rateScanPortable(t, pose, p), naive, "portable " + pose.asString());
  }
}

TEST(ScanRating, RatingsLeaveNothingBehind)
{
  // rateScan reuses per-thread scratch (a voxel window stamped per rating,
  // cleared every 63 ratings): 70 ratings alternating two maps and a small
  // and a large window give the first answers every time.
  const OcTree& room = roomMap();
  OcTree shell(0.05);
  setBox(shell, point3d(-1.1f, -1.1f, -0.6f), point3d(1.1f, 1.1f, 1.6f), octomap::logodds(0.3));
  ScanRatingParams near, far;
  near.beam_reduction = far.beam_reduction = 6;
  near.max_range_m = 2.0;
  const CPose2D pose(0.3, -0.2, 0.7);
  const ScanRating first[3] = {rateScan(room, pose, near), rateScan(room, pose, far),
                               rateScan(shell, pose, far)};
  expectSameRating(first[0], rateScanNaive(room, pose, near), "room, 2 m");
  expectSameRating(first[1], rateScanNaive(room, pose, far), "room, 7 m");
  expectSameRating(first[2], rateScanNaive(shell, pose, far), "shell, 7 m");
  for (int i = 0; i < 70; i++)
  {
    const ScanRating r = i % 3 == 0   ? rateScan(room, pose, near)
                         : i % 3 == 1 ? rateScan(room, pose, far)
                                      : rateScan(shell, pose, far);
    ASSERT_EQ(r.voxels, first[i % 3].voxels) << "rating " << i;
    ASSERT_EQ(r.gain, first[i % 3].gain) << "rating " << i;
  }
}

TEST(ScanRating, LongRangeFallsBackToTheNaiveRating)
{
  // Beyond ~12 m at 5 cm the window would exceed 32 M cells: the naive path.
  ScanRatingParams p;
  p.beam_reduction = 8;
  p.max_range_m = 20.0;
  const CPose2D pose(0.5, 0.5, 0.1);
  expectSameRating(rateScan(roomMap(), pose, p), rateScanNaive(roomMap(), pose, p), "20 m");
}

// --------------------------------------------------------------------- bestRated
TEST(ScanRating, BestRatedTiesAndZeros)
{
  using exploration::bestRated;
  auto ratings = [](std::vector<double> gains)
  {
    std::vector<ScanRating> out(gains.size());
    for (std::size_t i = 0; i < gains.size(); i++) out[i].gain = gains[i];
    return out;
  };
  EXPECT_FALSE(bestRated({}).has_value());
  EXPECT_FALSE(bestRated(ratings({0, 0, 0})).has_value());
  EXPECT_EQ(bestRated(ratings({1, 3, 2})), 1u);
  EXPECT_EQ(bestRated(ratings({0, 0, 0.5})), 2u);
  EXPECT_EQ(bestRated(ratings({1, 3, 3 * (1 + 1e-12), 2})), 1u);  // tie: lower index
  EXPECT_EQ(bestRated(ratings({1, 3 * (1 + 1e-12), 3, 2})), 1u);
  EXPECT_EQ(bestRated(ratings({1, 3, 3 * (1 + 1e-6)})), 2u);  // not a tie
}

// -------------------------------------------------------------------- parameters
TEST(ScanRating, DefaultMountsAreTheSimulatorRing)
{
  const ScanRatingParams p;
  const sim::CameraRigParams rig;
  ASSERT_EQ(p.mounts.size(), rig.mounts.size());
  for (std::size_t i = 0; i < p.mounts.size(); i++)
  {
    EXPECT_EQ(p.mounts[i].asString(), rig.mounts[i].asString()) << "camera " << i;
    EXPECT_LT((p.mounts[i].asVectorVal() - rig.mounts[i].asVectorVal()).norm(), 1e-12);
  }
  EXPECT_EQ(p.width_px, rig.width_px);
  EXPECT_EQ(p.height_px, rig.height_px);
  EXPECT_DOUBLE_EQ(p.hfov, rig.hfov);
  EXPECT_DOUBLE_EQ(p.vfov, rig.vfov);
}

TEST(ScanRating, ParamsRoundTrip)
{
  ScanRatingParams a;
  a.beam_reduction = 2;
  a.max_range_m = 5.5;
  a.th_occ = 230;
  a.width_px = 32;
  a.height_px = 24;
  a.hfov = mrpt::DEG2RAD(60.0);
  a.vfov = mrpt::DEG2RAD(45.0);
  a.count_z_min_m = 0.1;
  a.count_z_max_m = 0.5;
  a.mounts = {CPose3D(0.3, 0.1, 0.5, 0.2, 0.1, 0.0), CPose3D(-0.3, 0, 0.4, M_PI, 0.3, 0.05),
              CPose3D(0, 0.2, 0.45, 1.2, 0, 0)};
  mrpt::config::CConfigFileMemory mem;
  a.saveToConfigFile(mem, "scan_rating");
  ScanRatingParams b;
  common::loadChecked(b, mem, "scan_rating");
  EXPECT_EQ(b.beam_reduction, 2);
  EXPECT_DOUBLE_EQ(b.max_range_m, 5.5);
  EXPECT_EQ(b.th_occ, 230);
  EXPECT_EQ(b.width_px, 32);
  EXPECT_EQ(b.height_px, 24);
  EXPECT_NEAR(b.hfov, a.hfov, 1e-12);
  EXPECT_NEAR(b.vfov, a.vfov, 1e-12);
  EXPECT_DOUBLE_EQ(b.count_z_min_m, 0.1);
  EXPECT_DOUBLE_EQ(b.count_z_max_m, 0.5);
  EXPECT_TRUE(b.countBand());
  EXPECT_FALSE(ScanRatingParams().countBand()) << "off by default (the thesis)";
  ASSERT_EQ(b.mounts.size(), 3u);
  for (std::size_t i = 0; i < 3; i++)
    EXPECT_LT((b.mounts[i].asVectorVal() - a.mounts[i].asVectorVal()).norm(), 1e-9) << i;
  // The defaults round trip too (8 cameras written and read back).
  mrpt::config::CConfigFileMemory mem2;
  ScanRatingParams().saveToConfigFile(mem2, "s");
  ScanRatingParams c;
  common::loadChecked(c, mem2, "s");
  EXPECT_EQ(c.mounts.size(), 8u);
}

TEST(ScanRating, BadValuesNameTheKey)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"beam_reduction = 0", "beam_reduction"},
      {"max_range_m = -1", "max_range_m"},
      {"th_occ = 300", "th_occ"},
      {"width_px = 0", "width_px"},
      {"height_px = -4", "height_px"},
      {"hfov = 190", "hfov"},
      {"vfov = 0", "vfov"},
      {"num_cameras = 0", "num_cameras"},
      {"num_cameras = 3", "num_cameras"},  // no poses given for 3 cameras
      {"num_cameras = 2\ncam0_pose = 0 0 0.5 0 0 0", "cam1_pose"},
      {"num_cameras = 1\ncam0_pose = 0 0 0.5 0 0", "cam0_pose"},
      {"num_cameras = 1\ncam0_pose = 0 0 0.5 zero 0 0", "cam0_pose"},
      {"beam_reducton = 2", "beam_reducton"},  // misspelt key
  };
  for (const auto& [text, key] : cases)
  {
    mrpt::config::CConfigFileMemory mem("[scan_rating]\n" + text + "\n");
    ScanRatingParams p;
    try
    {
      common::loadChecked(p, mem, "scan_rating");
      ADD_FAILURE() << "no error for: " << text;
    }
    catch (const std::exception& e)
    {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos)
          << "'" << text << "' -> " << e.what();
    }
  }
}

TEST(ScanRating, BrokenParamsThrowWhenRating)
{
  OcTree t(0.1);
  ScanRatingParams p;
  p.mounts.clear();
  EXPECT_THROW(rateScan(t, CPose2D(), p), std::invalid_argument);
  EXPECT_THROW(rateScanNaive(t, CPose2D(), p), std::invalid_argument);
  p = ScanRatingParams();
  p.beam_reduction = 0;
  EXPECT_THROW(rateScan(t, CPose2D(), p), std::invalid_argument);
}


TEST(ScanRating, TheCountingBandLeavesOutTheUnknownBelowTheFloorAndAboveTheBand)
{
  // Free space 5 m ahead of a camera at 0.3 m, from the floor to 0.6 m
  // (what the robot's cameras map), unknown below the floor and above. The
  // thesis' rating counts the unknown voxels the beams cross below the
  // floor and above 0.6 m; with the counting band [0.10, 0.50] m (the band G
  // is projected from) every counted voxel is known: no unknown left.
  OcTree t(0.05);
  setBox(t, point3d(-0.5f, -3.0f, 0.0f), point3d(5.0f, 3.0f, 0.6f), t.getClampingThresMinLog());
  ScanRatingParams p = oneCamera(0.3);
  p.max_range_m = 4.0;
  const auto all = rateScan(t, CPose2D(), p);
  expectSameRating(all, rateScanNaive(t, CPose2D(), p), "no band");
  EXPECT_GT(all.unknown_voxels, 1000u);
  p.count_z_min_m = 0.10;
  p.count_z_max_m = 0.50;
  const auto band = rateScan(t, CPose2D(), p);
  expectSameRating(band, rateScanNaive(t, CPose2D(), p), "band");
  expectSameRating(rateScanPortable(t, CPose2D(), p), rateScanNaive(t, CPose2D(), p), "band, portable");
  EXPECT_EQ(band.unknown_voxels, 0u);
  EXPECT_GT(band.voxels, 100u);
  EXPECT_LT(band.voxels, all.voxels);
  EXPECT_EQ(band.beams, all.beams) << "the beams are the same; only the counting differs";
  // The free voxels in the band each count the clamped free entropy.
  EXPECT_NEAR(band.gain, double(band.voxels) * entropyOf(octomap::probability(t.getClampingThresMinLog())),
              1e-6 * band.gain);
  // On the room map (floor returns dropped: unknown below the floor) the band
  // rates the same with every walker and counts fewer unknown voxels.
  const OcTree& map = roomMap();
  ScanRatingParams q;
  q.beam_reduction = 2;
  const CPose2D pose(0.5, -0.5, 0.3);
  const auto room_all = rateScan(map, pose, q);
  q.count_z_min_m = 0.10;
  q.count_z_max_m = 0.50;
  const auto room_band = rateScan(map, pose, q);
  expectSameRating(room_band, rateScanNaive(map, pose, q), "room, band");
  expectSameRating(rateScanPortable(map, pose, q), rateScanNaive(map, pose, q), "room, band, portable");
  EXPECT_LT(room_band.unknown_voxels, room_all.unknown_voxels);
}

// rateScans (one window for a planning step's samples) against rateScan one
// pose at a time: the same voxels; the gain to rounding (the four-lane
// walker sums in another order), bit for bit on the portable walker. The
// poses lie within 1.5 m of each other, as a frontier's samples do, and a
// far one falls back to one window each.
TEST(ScanRating, OneWindowForManyPosesRatesAsOneByOne)
{
  const OcTree& map = roomMap();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.5, 2.0), uy(-1.0, 0.5), uyaw(-M_PI, M_PI);
  ScanRatingParams p;
  p.beam_reduction = 2;
  std::vector<CPose2D> poses;
  for (int i = 0; i < 12; i++) poses.emplace_back(ux(rng), uy(rng), uyaw(rng));
  for (const bool portable : {false, true})
  {
    if (portable) setenv("VOXPLORE_SCAN_RATING_PORTABLE", "1", 1);
    const auto batch = rateScans(map, poses, p);
    ASSERT_EQ(batch.size(), poses.size());
    for (std::size_t i = 0; i < poses.size(); i++)
    {
      const auto one = rateScan(map, poses[i], p);
      const std::string what = (portable ? "portable, pose " : "pose ") + poses[i].asString();
      expectSameRating(batch[i], one, what);
      if (portable)
      {
        EXPECT_EQ(batch[i].gain, one.gain) << what;
      }
      EXPECT_GT(batch[i].unknown_voxels, 0u) << what;
    }
    // Twice in a row, and with the counting band: the counted marks of one
    // rating do not leak into the next.
    ScanRatingParams band = p;
    band.count_z_min_m = 0.0;
    band.count_z_max_m = 1.0;
    const auto again = rateScans(map, poses, band);
    for (std::size_t i = 0; i < poses.size(); i++)
      expectSameRating(again[i], rateScan(map, poses[i], band), "band, " + poses[i].asString());
    if (portable) unsetenv("VOXPLORE_SCAN_RATING_PORTABLE");
  }
  // 40 m apart: beyond the shared window's limit, rated one by one.
  const std::vector<CPose2D> apart{CPose2D(0.5, 0.0, 0.0), CPose2D(40.0, 0.0, 0.0)};
  const auto far = rateScans(map, apart, p);
  ASSERT_EQ(far.size(), 2u);
  expectSameRating(far[0], rateScan(map, apart[0], p), "apart, first");
  expectSameRating(far[1], rateScan(map, apart[1], p), "apart, second");
  EXPECT_TRUE(rateScans(map, {}, p).empty());
}
