/* voxplore — tests of world loading: world files, meshes, HouseExpo floor
 * plans, primitives, inside-obstacle tests and the error messages. */

#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <voxplore/sim/tour.h>
#include <voxplore/sim/world_loading.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

using namespace voxplore::sim;
namespace fs = std::filesystem;
using Eigen::Vector3f;

namespace
{
const fs::path kWorldsDir = fs::path(VOXPLORE_SOURCE_DIR) / "simulated_worlds";
const fs::path kSharedDir = VOXPLORE_SHARED_WORLDS_DIR;
constexpr double kTourClearance = 0.9;  // m, from the tour segments to any solid

/// A fresh scratch folder for this test's files.
fs::path scratchDir()
{
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / "voxplore_WorldLoading" /
                       (std::string(info->test_suite_name()) + "." + info->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string writeFile(const fs::path& path, const std::string& text)
{
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::string readText(const fs::path& path)
{
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Message of the std::runtime_error `f` throws; fails the test when none is thrown.
template <typename F>
std::string errorOf(F&& f)
{
  try
  {
    f();
  }
  catch (const std::runtime_error& e)
  {
    return e.what();
  }
  ADD_FAILURE() << "expected a std::runtime_error";
  return {};
}

/// Signed volume enclosed by a closed mesh (positive when faces point outwards).
double signedVolume(const TriangleMesh& m)
{
  double v = 0;
  for (const auto& t : m.triangles)
  {
    const Eigen::Vector3d a = m.vertices[t[0]].cast<double>();
    const Eigen::Vector3d b = m.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = m.vertices[t[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

/// 2D distance from (x, y) to the footprint of a solid (0 inside).
double distanceToSolid(const Solid& s, double x, double y)
{
  const double dx = x - s.center.x(), dy = y - s.center.y();
  if (s.kind == Solid::Kind::Cylinder)
  {
    return std::max(0.0, std::hypot(dx, dy) - 0.5 * s.size.x());
  }
  const double c = std::cos(s.yaw_rad), sn = std::sin(s.yaw_rad);
  const double qx = std::max(0.0, std::abs(c * dx + sn * dy) - 0.5 * s.size.x());
  const double qy = std::max(0.0, std::abs(-sn * dx + c * dy) - 0.5 * s.size.y());
  return std::hypot(qx, qy);
}

std::vector<fs::path> simulatedWorldFiles()
{
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(kWorldsDir))
  {
    if (e.path().extension() == ".world")
    {
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The integer after "key": in a JSON text, or -1.
long jsonInt(const std::string& text, const std::string& key)
{
  std::smatch m;
  const std::regex re("\"" + key + "\"\\s*:\\s*(\\d+)");
  return std::regex_search(text, m, re) ? std::stol(m[1]) : -1;
}

#define SKIP_WITHOUT_SHARED_WORLDS()                                                            \
  if (!fs::is_directory(kSharedDir))                                                            \
  {                                                                                             \
    GTEST_SKIP() << "\n*** SKIPPED: shared worlds folder " << kSharedDir                        \
                 << " is missing: the tests on turtlebot3_house, aws_small_house,\n"            \
                 << "*** willowgarage and HouseExpo did NOT run (see shared/worlds/README.md)"; \
  }
}  // namespace

// --- (a) the project's simulated worlds ------------------------------------

TEST(SimulatedWorlds, EachLoadsWithFiniteGeometryAndAFreeStart)
{
  const auto files = simulatedWorldFiles();
  ASSERT_GE(files.size(), 3u) << "expected dlr_test_room, office, long_corridor in " << kWorldsDir;
  for (const auto& path : files)
  {
    SCOPED_TRACE(path.string());
    const World w = loadWorld(path.string());
    EXPECT_EQ(w.name, path.stem().string());
    EXPECT_EQ(w.source_path, path.string());
    EXPECT_GT(w.mesh.numTriangles(), 12u);
    EXPECT_EQ(w.mesh.firstNonFiniteVertex(), -1);
    EXPECT_FALSE(w.solids.empty());
    for (const double z : {0.05, 0.3, 0.6})
    {
      EXPECT_FALSE(w.insideObstacle(w.start.x(), w.start.y(), z)) << "start " << w.start;
    }
    EXPECT_NEAR(w.mesh.bounds().min().z(), 0.0, 1e-6);
    EXPECT_TRUE(fs::exists(kWorldsDir / (w.name + "_tour.txt"))) << "every world has a tour";
  }
}

TEST(SimulatedWorlds, KnownLayouts)
{
  const World room = loadWorld((kWorldsDir / "dlr_test_room.world").string());
  EXPECT_NEAR(room.start.x(), 2.0, 1e-9);
  EXPECT_NEAR(room.start.y(), 4.0, 1e-9);
  EXPECT_TRUE(room.insideObstacle(-0.07, 4.0, 1.0));  // west wall
  EXPECT_TRUE(room.insideObstacle(12.07, 4.0, 1.0));  // east wall
  EXPECT_FALSE(room.insideObstacle(11.9, 7.0, 1.0));  // free corner
  EXPECT_TRUE(room.insideObstacle(5.0, 4.0, 0.73));   // meeting table top
  EXPECT_FALSE(room.insideObstacle(5.0, 4.0, 0.3));   // under the table, between its legs
  for (const Solid& s : room.solids)
  {
    const double d = distanceToSolid(s, room.start.x(), room.start.y());
    EXPECT_GE(d, 1.5 - 1e-6) << "start clearance, solid at " << s.center.transpose();
  }
  const World corridor = loadWorld((kWorldsDir / "long_corridor.world").string());
  EXPECT_EQ(corridor.solids.size(), 4u) << "walls only";
  EXPECT_TRUE(corridor.insideObstacle(15.0, -0.05, 1.0));
  EXPECT_TRUE(corridor.insideObstacle(30.05, 1.25, 1.0));
  EXPECT_FALSE(corridor.insideObstacle(29.9, 1.25, 1.0));
  const World office = loadWorld((kWorldsDir / "office.world").string());
  EXPECT_FALSE(office.insideObstacle(2.5, -0.075, 1.0)) << "doorway S1 open";
  EXPECT_TRUE(office.insideObstacle(1.55, -0.075, 1.0)) << "doorway S1 jamb";
  EXPECT_FALSE(office.insideObstacle(7.5, 2.575, 1.0)) << "doorway N2 open";
}

TEST(SimulatedWorlds, ToursKeepClearOfObstacles)
{
  for (const auto& path : simulatedWorldFiles())
  {
    SCOPED_TRACE(path.string());
    const World w = loadWorld(path.string());
    const auto tour = loadWaypointsFile((kWorldsDir / (w.name + "_tour.txt")).string());
    Eigen::Vector2d prev(w.start.x(), w.start.y());
    double length = 0;
    for (const Waypoint& wp : tour)
    {
      const Eigen::Vector2d next(wp.x, wp.y);
      const double len = (next - prev).norm();
      const int steps = std::max(1, static_cast<int>(len / 0.01));
      for (int k = 0; k <= steps; ++k)
      {
        const Eigen::Vector2d p = prev + (next - prev) * (double(k) / steps);
        for (const Solid& s : w.solids)
        {
          ASSERT_GE(distanceToSolid(s, p.x(), p.y()), kTourClearance - 1e-3)
              << "segment to (" << wp.x << ", " << wp.y << ") passes " << p.transpose()
              << " near the solid at " << s.center.transpose();
        }
      }
      length += len;
      prev = next;
    }
    if (w.name == "dlr_test_room")
    {
      EXPECT_GE(length, 15.0);
      EXPECT_LE(length, 25.0) << "its recording goes into git: keep it short";
    }
  }
}

TEST(SimulatedWorlds, StartArgumentOverridesTheFile)
{
  const auto path = (kWorldsDir / "long_corridor.world").string();
  const World w = loadWorld(path, mrpt::poses::CPose2D(10, 1, 0.5));
  EXPECT_DOUBLE_EQ(w.start.x(), 10.0);
  EXPECT_DOUBLE_EQ(w.start.phi(), 0.5);
}

// --- (b) worlds made by others (../shared/worlds) ---------------------------

TEST(SharedWorlds, MeshesLoadWithTheirTriangleCounts)
{
  SKIP_WITHOUT_SHARED_WORLDS();
  for (const char* rel : {"turtlebot3_house/turtlebot3_house_flat.obj",
                          "aws_small_house/small_house_flat_collision.obj",
                          "willowgarage/willowgarage_flat_collision.obj"})
  {
    const fs::path obj = kSharedDir / rel;
    SCOPED_TRACE(obj.string());
    ASSERT_TRUE(fs::exists(obj));
    const World w = loadWorld(obj.string());
    EXPECT_EQ(w.name, obj.stem().string());
    EXPECT_EQ(w.mesh.firstNonFiniteVertex(), -1);
    EXPECT_DOUBLE_EQ(w.start.x(), 0.0);
    const long expected = jsonInt(readText(fs::path(obj).replace_extension(".json")), "triangles");
    ASSERT_GT(expected, 0) << "metadata json without a triangle count";
    EXPECT_EQ(static_cast<long>(w.mesh.numTriangles()), expected + 2) << "+2: the ground plane";
    WorldLoadOptions no_ground;
    no_ground.add_ground_plane = false;
    EXPECT_EQ(static_cast<long>(loadWorld(obj.string(), {}, no_ground).mesh.numTriangles()),
              expected);
  }
}

TEST(SharedWorlds, TurtlebotHouseBoundsMatchItsMetadata)
{
  SKIP_WITHOUT_SHARED_WORLDS();
  const auto b =
      loadMeshFile((kSharedDir / "turtlebot3_house/turtlebot3_house_flat.obj").string()).bounds();
  EXPECT_NEAR(b.min().x(), -7.575, 2e-3);
  EXPECT_NEAR(b.max().x(), 7.578, 2e-3);
  EXPECT_NEAR(b.min().y(), -5.35, 2e-3);
  EXPECT_NEAR(b.max().z(), 2.5, 2e-3);
}

TEST(SharedWorlds, HouseExpoFloorPlansLoad)
{
  SKIP_WITHOUT_SHARED_WORLDS();
  int loaded = 0;
  for (const auto& e : fs::directory_iterator(kSharedDir / "houseexpo"))
  {
    if (e.path().extension() != ".json")
    {
      continue;
    }
    SCOPED_TRACE(e.path().string());
    const World w = loadWorld(e.path().string(), mrpt::poses::CPose2D(1, 2, 0));
    ASSERT_EQ(w.free_space_outlines.size(), 1u);
    const std::size_t n = w.free_space_outlines[0].size();
    EXPECT_GT(n, 20u);
    EXPECT_EQ(w.mesh.numTriangles(), 2 * n + 2) << "two per wall quad, two for the ground";
    EXPECT_NEAR(w.mesh.bounds().max().z(), 2.5, 1e-6);
    EXPECT_DOUBLE_EQ(w.start.y(), 2.0);
    EXPECT_TRUE(w.insideObstacle(-1.0, -1.0, 1.0)) << "outside the plan";
    ++loaded;
  }
  EXPECT_EQ(loaded, 2);
  const World plan =
      loadFloorPlan((kSharedDir / "houseexpo/0004d52d1aeeb8ae6de39d6bd993e992.json").string());
  EXPECT_FALSE(plan.insideObstacle(2.5, 1.2, 1.0)) << "in the storage room";
  EXPECT_TRUE(plan.insideObstacle(2.87, 4.5, 1.0)) << "in the 0.1 m wall at x = 2.82..2.93";
  EXPECT_FALSE(plan.insideObstacle(2.87, 3.3, 1.0)) << "in the doorway of that wall";
}

// --- (c) errors name the file -------------------------------------------------

TEST(WorldLoadingErrors, MissingAndEmptyFiles)
{
  const fs::path dir = scratchDir();
  for (const char* name : {"nowhere.world", "nowhere.obj", "nowhere.json"})
  {
    const std::string msg = errorOf([&] { loadWorld((dir / name).string()); });
    EXPECT_NE(msg.find(name), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  }
  for (const char* name : {"empty.world", "empty.obj", "empty.json"})
  {
    const std::string path = writeFile(dir / name, "");
    const std::string msg = errorOf([&] { loadWorld(path); });
    EXPECT_EQ(msg.rfind(path, 0), 0u) << "starts with the path: " << msg;
    EXPECT_NE(msg.find("empty"), std::string::npos) << msg;
  }
}

TEST(WorldLoadingErrors, MalformedWorldFiles)
{
  const fs::path dir = scratchDir();
  struct Case
  {
    const char* file;
    const char* text;
    std::vector<const char*> expected;  // substrings of the message
  };
  const std::vector<Case> cases = {
      {"syntax.world", "{\"elements\": [ {\"type\": \"box\",, ] }", {"malformed JSON", "byte"}},
      {"not_object.world", "[1, 2]", {"JSON object"}},
      {"no_elements.world", "{\"start\": {\"x\": 1, \"y\": 1}}", {"'elements'"}},
      {"unknown_type.world",
       R"({"elements": [{"type": "box", "center": [0,0,1], "size": [1,1,1]}, {"type": "sofa"}]})",
       {"elements[1]", "unknown element type 'sofa'"}},
      {"missing_field.world",
       R"({"elements": [{"type": "box", "center": [0,0,1]}]})",
       {"elements[0] (box)", "missing required field 'size'"}},
      {"wrong_type.world",
       R"({"elements": [{"type": "wall", "from": [0,0], "to": "far"}]})",
       {"elements[0] (wall)", "'to'", "array of 2 numbers"}},
      {"misspelt.world",
       R"({"elements": [{"type": "wall", "from": [0,0], "to": [1,0], "heigth": 2}]})",
       {"elements[0] (wall)", "unknown field 'heigth'"}},
      {"bad_start.world", R"({"start": {"x": 1}, "elements": []})", {"start", "'y'"}},
      {"no_geometry.world", R"({"elements": []})", {"no geometry"}},
      {"bad_mesh.world",
       R"({"elements": [{"type": "mesh", "file": "absent.obj"}]})",
       {"elements[0] (mesh)", "absent.obj", "does not exist"}},
  };
  for (const auto& c : cases)
  {
    const std::string path = writeFile(dir / c.file, c.text);
    const std::string msg = errorOf([&] { loadWorld(path); });
    EXPECT_EQ(msg.rfind(path, 0), 0u) << "starts with the path: " << msg;
    for (const char* s : c.expected)
    {
      EXPECT_NE(msg.find(s), std::string::npos) << "'" << s << "' not in: " << msg;
    }
  }
}

TEST(WorldLoadingErrors, BadMeshes)
{
  const fs::path dir = scratchDir();
  const std::string nan_obj =
      writeFile(dir / "nan_vertex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 1 1\nf 1 2 3\nf 2 3 4\n");
  std::string msg = errorOf([&] { loadMeshFile(nan_obj); });
  EXPECT_EQ(msg.rfind(nan_obj, 0), 0u) << msg;
  EXPECT_NE(msg.find("vertex"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not finite"), std::string::npos) << msg;

  const std::string no_faces = writeFile(dir / "no_faces.obj", "# nothing\nv 0 0 0\nv 1 0 0\n");
  msg = errorOf([&] { loadWorld(no_faces); });
  EXPECT_EQ(msg.rfind(no_faces, 0), 0u) << msg;

  const std::string garbage = writeFile(dir / "garbage.stl", "this is not a mesh\n");
  msg = errorOf([&] { loadWorld(garbage); });
  EXPECT_EQ(msg.rfind(garbage, 0), 0u) << msg;
}

TEST(WorldLoadingErrors, BadFloorPlans)
{
  const fs::path dir = scratchDir();
  const std::string two = writeFile(dir / "two_verts.json", R"({"verts": [[0, 0], [1, 0]]})");
  std::string msg = errorOf([&] { loadWorld(two); });
  EXPECT_EQ(msg.rfind(two, 0), 0u) << msg;
  EXPECT_NE(msg.find("at least 3"), std::string::npos) << msg;

  const std::string no_verts = writeFile(dir / "no_verts.json", R"({"id": "x"})");
  msg = errorOf([&] { loadFloorPlan(no_verts); });
  EXPECT_NE(msg.find("'verts'"), std::string::npos) << msg;

  const std::string bad_vert = writeFile(dir / "bad_vert.json", R"({"verts": [[0,0],[1,0],[1]]})");
  msg = errorOf([&] { loadFloorPlan(bad_vert); });
  EXPECT_NE(msg.find("verts[2]"), std::string::npos) << msg;
}

// --- world files: relative paths and furniture --------------------------------

TEST(WorldFile, RelativeMeshAndFloorPlanPathsAndFurniture)
{
  const fs::path dir = scratchDir();
  fs::create_directories(dir / "meshes");
  writeFile(dir / "meshes" / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  writeFile(dir / "plan.json", R"({"verts": [[0,0],[4,0],[4,3],[0,3]]})");
  const std::string path = writeFile(dir / "composed.world", R"({
    "name": "composed", "start": {"x": 2, "y": 1.5, "yaw_deg": 90}, "ground_plane": false,
    "elements": [
      {"type": "mesh", "file": "meshes/tri.obj", "translation": [10, 0, 0], "yaw_deg": 90, "scale": 2},
      {"type": "floorplan", "file": "plan.json", "wall_height": 3},
      {"type": "table", "center": [2, 1.5], "size": [1.6, 0.8], "height": 0.75},
      {"type": "chair", "center": [1, 1.5], "yaw_deg": 0}]})");
  const World w = loadWorld(path);
  EXPECT_EQ(w.name, "composed");
  EXPECT_NEAR(w.start.phi(), M_PI / 2, 1e-12);
  // mesh 1 + floor plan 4 quads + table 5 boxes + chair 6 boxes (12 triangles each)
  EXPECT_EQ(w.mesh.numTriangles(), 1u + 8u + 12u * 11u);
  EXPECT_EQ(w.solids.size(), 11u);
  EXPECT_TRUE(w.mesh.vertices[1].isApprox(Vector3f(10, 2, 0), 1e-6f)) << "scaled, turned, moved";
  ASSERT_EQ(w.free_space_outlines.size(), 1u);
  EXPECT_NEAR(w.mesh.bounds().max().z(), 3.0, 1e-6);
  EXPECT_TRUE(w.insideObstacle(2.0, 1.5, 0.73)) << "table top";
  EXPECT_FALSE(w.insideObstacle(2.0, 1.5, 0.5)) << "under the table";
  EXPECT_TRUE(w.insideObstacle(2.0 - 0.8 + 0.075, 1.5 - 0.4 + 0.075, 0.3)) << "table leg";
  EXPECT_TRUE(w.insideObstacle(1.0, 1.5, 0.43)) << "seat";
  EXPECT_TRUE(w.insideObstacle(1.0 - 0.2, 1.5, 0.8)) << "backrest on the chair's -X side";
  EXPECT_FALSE(w.insideObstacle(1.0 + 0.2, 1.5, 0.8)) << "nothing in front of the chair";
  EXPECT_TRUE(w.insideObstacle(5.0, 1.0, 1.0)) << "outside the floor plan";
}

// --- (d) primitives -----------------------------------------------------------

TEST(TriangleMesh, BoxVolumeBoundsAndOrientation)
{
  TriangleMesh m;
  m.addBox({1, 2, 3}, {2, 4, 6});
  EXPECT_EQ(m.numTriangles(), 12u);
  EXPECT_NEAR(signedVolume(m), 48.0, 1e-4) << "positive: faces point outwards";
  EXPECT_TRUE(m.bounds().min().isApprox(Vector3f(0, 0, 0)));
  EXPECT_TRUE(m.bounds().max().isApprox(Vector3f(2, 4, 6)));
  TriangleMesh turned;
  turned.addBox({0, 0, 0}, {2, 4, 6}, static_cast<float>(M_PI / 2));
  EXPECT_NEAR(turned.bounds().max().x(), 2.0, 1e-5);
  EXPECT_NEAR(turned.bounds().max().y(), 1.0, 1e-5);
  EXPECT_NEAR(signedVolume(turned), 48.0, 1e-4);
}

TEST(TriangleMesh, CylinderBoundsAndVolume)
{
  TriangleMesh m;
  const int n = 24;
  m.addCylinder({1, -1}, 0.5f, 0.2f, 1.2f, n);
  EXPECT_EQ(m.numTriangles(), 4u * n);
  const auto b = m.bounds();
  EXPECT_TRUE(b.min().isApprox(Vector3f(0.5f, -1.5f, 0.2f), 1e-5f)) << b.min().transpose();
  EXPECT_TRUE(b.max().isApprox(Vector3f(1.5f, -0.5f, 1.2f), 1e-5f)) << b.max().transpose();
  const double polygon_area = 0.5 * n * 0.25 * std::sin(2 * M_PI / n);
  EXPECT_NEAR(signedVolume(m), polygon_area * 1.0, 1e-4);
}

TEST(TriangleMesh, AppendQuadBoundsAndNonFinite)
{
  TriangleMesh m;
  EXPECT_TRUE(m.empty());
  EXPECT_TRUE(m.bounds().isEmpty());
  m.addQuad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  EXPECT_GT(signedVolume(m), -1.0);  // open: no volume, only checks indices
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  T.translate(Vector3f(0, 0, 5));
  TriangleMesh big;
  big.append(m, T, 3.0f);
  big.append(m);
  EXPECT_EQ(big.numTriangles(), 4u);
  EXPECT_TRUE(big.bounds().max().isApprox(Vector3f(3, 3, 5)));
  EXPECT_EQ(big.firstNonFiniteVertex(), -1);
  big.vertices[5].y() = std::numeric_limits<float>::infinity();
  EXPECT_EQ(big.firstNonFiniteVertex(), 5);
}

TEST(Solid, ContainsIsStrictAndHonoursYaw)
{
  Solid box;
  box.center = {0, 0, 1};
  box.size = {2, 0.5, 2};
  box.yaw_rad = static_cast<float>(M_PI / 4);
  const float r = 0.9f / std::sqrt(2.0f);
  EXPECT_TRUE(box.contains({r, r, 1}));  // 0.9 m along the box's long axis
  EXPECT_FALSE(box.contains({0.9f, 0, 1}));
  EXPECT_FALSE(box.contains({0, 0, 2.0f})) << "on the top face: not strictly inside";
  EXPECT_FALSE(box.contains({0, 0, -0.01f}));
  Solid cyl;
  cyl.kind = Solid::Kind::Cylinder;
  cyl.center = {1, 1, 1.5f};
  cyl.size = {1, 1, 1};
  EXPECT_TRUE(cyl.contains({1.3f, 1.3f, 1.1f}));
  EXPECT_FALSE(cyl.contains({1.4f, 1.4f, 1.5f})) << "outside the radius";
  EXPECT_FALSE(cyl.contains({1, 1, 0.9f})) << "below z0";
}

TEST(World, InsideObstacleWithAHouseExpoOutline)
{
  World w;
  EXPECT_FALSE(w.insideObstacle(100, 100, 1)) << "no outlines, no solids: all free";
  // a 4 x 3 room with a 0.1 m wall notch from the top at x = 2
  w.free_space_outlines.push_back(
      {{0, 0}, {4, 0}, {4, 3}, {2.05, 3}, {2.05, 1.5}, {1.95, 1.5}, {1.95, 3}, {0, 3}});
  EXPECT_FALSE(w.insideObstacle(1, 1, 0.5));
  EXPECT_FALSE(w.insideObstacle(2, 1, 0.5)) << "below the notch";
  EXPECT_TRUE(w.insideObstacle(2, 2, 0.5)) << "in the notch";
  EXPECT_TRUE(w.insideObstacle(-0.1, 1, 0.5));
  EXPECT_TRUE(w.insideObstacle(4.1, 2, 0.5));
  Solid pillar;
  pillar.kind = Solid::Kind::Cylinder;
  pillar.center = {3, 1, 1};
  pillar.size = {0.4f, 0.4f, 2};
  w.solids.push_back(pillar);
  EXPECT_TRUE(w.insideObstacle(3.1, 1, 0.5));
}

TEST(WorldLoading, GroundPlaneCoversBoundsPlusMargin)
{
  World w;
  w.mesh.addBox({0, 0, 1}, {2, 4, 2});
  addGroundPlane(w, 1.5);
  ASSERT_EQ(w.mesh.numTriangles(), 14u);
  const auto b = w.mesh.bounds();
  EXPECT_TRUE(b.min().isApprox(Vector3f(-2.5f, -3.5f, 0)));
  EXPECT_TRUE(b.max().isApprox(Vector3f(2.5f, 3.5f, 2)));
  const auto& t = w.mesh.triangles.back();
  const Vector3f n = (w.mesh.vertices[t[1]] - w.mesh.vertices[t[0]])
                         .cross(w.mesh.vertices[t[2]] - w.mesh.vertices[t[0]]);
  EXPECT_GT(n.z(), 0) << "the floor faces up";
}

// --- (e) start poses ------------------------------------------------------------

TEST(WorldLoading, ParseStartPose)
{
  const auto p = parseStartPose("1,2,90");
  EXPECT_DOUBLE_EQ(p.x(), 1.0);
  EXPECT_DOUBLE_EQ(p.y(), 2.0);
  EXPECT_NEAR(p.phi(), M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(parseStartPose("-1.5, 0.25").phi(), 0.0);
  EXPECT_NEAR(parseStartPose(" 3 , 4 , -45 ").phi(), -M_PI / 4, 1e-12);
  for (const char* bad : {"", "1", "1,2,3,4", "a,b", "1,2,", "1,,2", "1,2,nan", "1;2;3", "1,2x"})
  {
    EXPECT_THROW(parseStartPose(bad), std::runtime_error) << "'" << bad << "'";
  }
}

// --- (d) inputs found by fuzzing (fuzz/corpus/*/crash_*) ------------------------

TEST(WorldLoadingErrors, FuzzFindingsAreNamedErrors)
{
  const fs::path dir = scratchDir();
  // nlohmann throws out_of_range (not parse_error) for a number beyond double
  // range; it escaped as a non-runtime_error without the file name.
  const std::string overflow =
      writeFile(dir / "overflow.world", R"({"start": {"x": 16e308, "y": 0}, "elements": []})");
  std::string msg = errorOf([&] { loadWorld(overflow); });
  EXPECT_EQ(msg.rfind(overflow, 0), 0u) << msg;
  EXPECT_NE(msg.find("malformed JSON"), std::string::npos) << msg;

  // Finite doubles beyond float range made infinite (float) mesh vertices.
  const std::string plan =
      writeFile(dir / "huge.json", R"({"verts": [[0, 0], [1e308, 0], [0, 1]]})");
  msg = errorOf([&] { loadWorld(plan); });
  EXPECT_EQ(msg.rfind(plan, 0), 0u) << msg;
  EXPECT_NE(msg.find("verts[1]"), std::string::npos) << msg;
  EXPECT_NE(msg.find("float range"), std::string::npos) << msg;

  const std::string cylinder = writeFile(
      dir / "huge.world",
      R"({"elements": [{"type": "cylinder", "center": [0, 0], "radius": 1e300, "z": [0, 1]}]})");
  msg = errorOf([&] { loadWorld(cylinder); });
  EXPECT_EQ(msg.rfind(cylinder, 0), 0u) << msg;
  EXPECT_NE(msg.find("elements[0] (cylinder)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not finite"), std::string::npos) << msg;
}

TEST(WorldFile, ParsingTextEqualsLoadingTheFile)
{
  const std::string path = (kWorldsDir / "dlr_test_room.world").string();
  const std::string text = readText(path);
  const World from_file = loadWorldFile(path);
  const World from_text = parseWorldFile(text, path);
  EXPECT_EQ(from_text.name, from_file.name);
  EXPECT_EQ(from_text.mesh.numTriangles(), from_file.mesh.numTriangles());
  EXPECT_EQ(from_text.solids.size(), from_file.solids.size());
  EXPECT_EQ(from_text.start.x(), from_file.start.x());
  EXPECT_EQ(from_text.start.y(), from_file.start.y());
  EXPECT_EQ(from_text.start.phi(), from_file.start.phi());
  const World plan = parseFloorPlan(R"({"verts": [[0, 0], [4, 0], [4, 3], [0, 3]]})", "plan.json");
  EXPECT_EQ(plan.mesh.numTriangles(), 2u * 4u + 2u) << "4 wall quads and the ground";
  EXPECT_EQ(errorOf([] { parseFloorPlan("{", "text.json"); }).rfind("text.json", 0), 0u);
}
