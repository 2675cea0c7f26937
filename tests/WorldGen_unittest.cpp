// voxplore-worldgen (issue 10): procedural buildings are connected for the
// compact robot, their doors have the widths asked for (as the simulator's
// collision checker sees them), one seed gives one file byte for byte, and
// every layout loads in mrpt-sim and voxplore-explore.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <voxplore/apps/ExploreApp.h>
#include <voxplore/apps/SimApp.h>
#include <voxplore/apps/WorldGenApp.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/Robot.h>
#include <voxplore/sim/ground_truth.h>
#include <voxplore/sim/world_loading.h>
#include <voxplore/sim/worldgen.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "test_worlds.h"

using namespace voxplore;
namespace fs = std::filesystem;

namespace
{
/// A fresh scratch directory of this test process (test::tempPath).
std::string tmpDir(const std::string& name)
{
  const std::string d = test::tempPath("worldgen_" + name);
  fs::remove_all(d);
  return d;
}

/// Generates seed `seed` into a fresh folder and loads it back.
sim::World generateAndLoad(const sim::WorldGenParams& p, uint64_t seed, sim::GeneratedBuilding& b)
{
  b = sim::generateBuilding(p, seed);
  const fs::path dir = tmpDir("gen_" + p.layout + "_" + std::to_string(seed));
  fs::create_directories(dir);
  std::ofstream(dir / "building.world") << sim::buildingWorldJson(b);
  return sim::loadWorld((dir / "building.world").string());
}

sim::WorldGenParams withLayout(const std::string& layout)
{
  sim::WorldGenParams p;
  p.layout = layout;
  return p;
}

const char* kLayouts[] = {"corridor", "ring", "branching", "hall"};
}  // namespace

TEST(WorldGen, EveryBuildingIsConnectedForTheCompactRobot)
{
  // The compact robot's planner circle (its circumradius plus sqrt(2) l_res):
  // every room and corridor centre must be reachable from the start.
  const sim::RobotParams compact = sim::RobotParams::compact();
  const double r = compact.footprint().circumradius() + std::sqrt(2.0) * 0.05;
  for (const char* layout : kLayouts)
    for (const uint64_t seed : {11u, 12u})
    {
      sim::GeneratedBuilding b;
      const sim::World w = generateAndLoad(withLayout(layout), seed, b);
      const sim::CollisionChecker checker(w, 0.03, compact.height_m);
      const sim::ReachableFloor rf = sim::reachableFreeFloor(w, checker, w.start, r);
      std::size_t rooms = 0;
      for (const sim::GenRegion& reg : b.regions)
      {
        if (reg.kind == sim::GenRegion::Kind::Hall) continue;  // desk islands may stand at its centre
        rooms += reg.kind == sim::GenRegion::Kind::Room;
        const Eigen::Vector2d c = reg.rects.front().center();
        const int ix = static_cast<int>(std::floor((c.x() - rf.reachable.origin.x()) / rf.reachable.res_m));
        const int iy = static_cast<int>(std::floor((c.y() - rf.reachable.origin.y()) / rf.reachable.res_m));
        ASSERT_TRUE(rf.reachable.inside(ix, iy));
        EXPECT_TRUE(rf.reachable.at(ix, iy))
            << layout << " seed " << seed << ": " << reg.name << " at (" << c.x() << ", " << c.y()
            << ") is not reachable for the compact robot";
      }
      EXPECT_GE(rooms, 3u) << layout << " seed " << seed;
      EXPECT_GE(b.floor_area_m2, 0.5 * b.params.min_floor_m2) << layout;
      EXPECT_LE(b.floor_area_m2, 1.1 * b.params.max_floor_m2) << layout;
    }
}

TEST(WorldGen, DoorsHaveTheWidthsAskedForAsTheCheckerSeesThem)
{
  for (const auto& [lo, hi] : {std::pair{0.85, 1.0}, std::pair{0.70, 0.75}})
  {
    sim::WorldGenParams p = withLayout("mixed");
    p.door_width_min_m = lo;
    p.door_width_max_m = hi;
    for (const uint64_t seed : {21u, 22u, 23u, 24u})
    {
      sim::GeneratedBuilding b;
      const sim::World w = generateAndLoad(p, seed, b);
      const sim::CollisionChecker checker(w, 0.03, 0.645);
      std::size_t checked = 0;
      for (const sim::GenDoor& d : b.doors)
      {
        if (d.wide) continue;  // the hall's openings
        EXPECT_GE(d.width_m, lo - 1e-9);
        EXPECT_LE(d.width_m, hi + 1e-9);
        // A probe through the wall, its length across the wall, its width along it:
        // 1 cm narrower than the door passes, 1 cm wider touches a jamb.
        const mrpt::poses::CPose2D across(d.center.x(), d.center.y(), d.along_x ? M_PI / 2 : 0.0);
        const double len = p.wall_thickness_m + 0.3;
        EXPECT_FALSE(checker.collides(across, sim::Footprint{len, d.width_m - 0.01}))
            << "seed " << seed << ": door at (" << d.center.x() << ", " << d.center.y()
            << ") narrower than " << d.width_m;
        EXPECT_TRUE(checker.collides(across, sim::Footprint{len, d.width_m + 0.01}))
            << "seed " << seed << ": door at (" << d.center.x() << ", " << d.center.y()
            << ") wider than " << d.width_m;
        checked++;
      }
      EXPECT_GE(checked, 3u);
    }
  }
}

TEST(WorldGen, SameSeedSameFilesByteForByte)
{
  const auto a = tmpDir("det_a"), b = tmpDir("det_b"), c = tmpDir("det_c");
  apps::WorldGenOptions o;
  o.seed = 5;
  o.config = VOXPLORE_SOURCE_DIR "/config/worldgen.ini";
  o.topview = false;
  o.out_dir = a;
  apps::WorldGenApp{}.execute(o);
  o.out_dir = b;
  apps::WorldGenApp{}.execute(o);
  o.seed = 6;
  o.out_dir = c;
  apps::WorldGenApp{}.execute(o);
  for (const char* f : {"building.world", "building.json"})
  {
    EXPECT_FALSE(test::readFile(fs::path(a) / f).empty());
    EXPECT_EQ(test::readFile(fs::path(a) / f), test::readFile(fs::path(b) / f)) << f;
    EXPECT_NE(test::readFile(fs::path(a) / f), test::readFile(fs::path(c) / f)) << f;
  }
  // The ground truth parses and tells the layout, the area and the doors.
  const auto truth = nlohmann::json::parse(test::readFile(fs::path(a) / "building.json"));
  EXPECT_EQ(truth.at("seed").get<int>(), 5);
  EXPECT_GT(truth.at("floor_area_m2").get<double>(), 100.0);
  EXPECT_FALSE(truth.at("doors").empty());
}

TEST(WorldGen, EveryLayoutLoadsInMrptSimAndVoxploreExplore)
{
  for (const char* layout : kLayouts)
  {
    apps::WorldGenOptions g;
    g.seed = 31;
    g.layout = layout;
    g.topview = false;
    g.out_dir = tmpDir(std::string("apps_") + layout);
    const auto s = apps::WorldGenApp{}.execute(g);
    EXPECT_EQ(s.layout, layout);

    // mrpt-sim: one metre along the corridor from the start.
    const sim::World w = sim::loadWorld(s.world_path);
    const double yaw = w.start.phi();
    const fs::path wps = fs::path(g.out_dir) / "tour.txt";
    std::ofstream(wps) << w.start.x() + std::cos(yaw) << " " << w.start.y() + std::sin(yaw) << "\n";
    apps::SimOptions so;
    so.world = s.world_path;
    so.waypoints = wps.string();
    so.out_dir = (fs::path(g.out_dir) / "sim").string();
    so.quiet = true;
    const auto sim_summary = apps::SimApp{}.execute(so);
    EXPECT_GE(sim_summary.stops, 2u) << layout;
    EXPECT_EQ(sim_summary.collisions, 0u) << layout;

    // voxplore-explore: one planning step, both robots.
    for (const char* robot : {"omnirob", "compact"})
    {
      apps::ExploreOptions eo;
      eo.config = VOXPLORE_SOURCE_DIR "/config/explore.ini";
      eo.world = s.world_path;
      eo.robot = robot;
      eo.max_steps = 1;
      eo.quiet = true;
      eo.out_dir = (fs::path(g.out_dir) / (std::string("explore_") + robot)).string();
      const auto es = apps::ExploreApp{}.execute(eo);
      EXPECT_EQ(es.termination_reason, "max_steps") << layout << " " << robot;
      EXPECT_GE(es.stops, 2u) << layout << " " << robot;
      EXPECT_EQ(es.collisions, 0u) << layout << " " << robot;
    }
  }
}

TEST(WorldGen, LookAlikeRoomsAndAFeaturelessStretch)
{
  sim::WorldGenParams p = withLayout("corridor");
  p.look_alike_rooms = true;
  p.featureless_corridor_m = 20;
  const sim::GeneratedBuilding b = sim::generateBuilding(p, 41);
  // Rooms: one size (the last of each band takes the rest).
  std::map<std::pair<long, long>, int> sizes;
  int rooms = 0;
  for (const sim::GenRegion& r : b.regions)
    if (r.kind == sim::GenRegion::Kind::Room)
    {
      rooms++;
      sizes[{std::lround(r.rects[0].width() * 100), std::lround(r.rects[0].height() * 100)}]++;
    }
  int most = 0;
  for (const auto& [k, n] : sizes) most = std::max(most, n);
  EXPECT_GE(most, rooms - 2) << "look-alike rooms must share one size";
  // The featureless stretch: the corridor runs 20 m past the last room, with
  // no door and no furniture along it.
  double rooms_end = 0, corridor_end = 0;
  for (const sim::GenRegion& r : b.regions)
    (r.kind == sim::GenRegion::Kind::Room ? rooms_end : corridor_end) =
        std::max(r.kind == sim::GenRegion::Kind::Room ? rooms_end : corridor_end, r.rects[0].x1);
  EXPECT_NEAR(corridor_end - rooms_end, 20.0, 1e-6);
  for (const sim::GenDoor& d : b.doors) EXPECT_LT(d.center.x(), rooms_end);
  for (const sim::GenItem& it : b.items) EXPECT_LT(it.center.x(), rooms_end);
}

TEST(WorldGen, BadParametersAreErrorsNamingTheKey)
{
  mrpt::config::CConfigFileMemory ini;
  ini.write("worldgen", "door_width_min_m", "1.2");
  ini.write("worldgen", "door_width_max_m", "1.0");
  sim::WorldGenParams p;
  try
  {
    p.loadFromConfigFile(ini, "worldgen");
    FAIL() << "min > max must be an error";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("door_width_min_m"), std::string::npos) << e.what();
  }
  const fs::path bad = fs::path(tmpDir("bad_ini")) / "bad.ini";
  fs::create_directories(bad.parent_path());
  std::ofstream(bad) << "[worldgen]\nlayuot = ring\n";
  apps::WorldGenOptions o;
  o.seed = 1;
  o.config = bad.string();
  o.out_dir = tmpDir("bad_out");
  try
  {
    apps::WorldGenApp{}.execute(o);
    FAIL() << "a misspelt key must be an error";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("layuot"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad.ini"), std::string::npos) << e.what();
  }
  o.config.clear();
  o.layout = "castle";
  EXPECT_THROW(apps::WorldGenApp{}.execute(o), std::exception);
}
