/* voxplore — tests of the world ground truth: occupied voxels, reachable floor, top view. */

#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/ground_truth.h>

#include "test_worlds.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <set>
#include <tuple>

using namespace voxplore::sim;
using Eigen::Vector3d;
using Eigen::Vector3f;

namespace
{
using Key = std::tuple<int, int, int>;

Key key(const VoxelIndex& v)
{
  return {v.x(), v.y(), v.z()};
}

/// A closed room: inner faces at x = 0 and `sx`, y = 0 and `sy`; walls
/// 0.125 m thick and 2 m high; floor quad under all of it.
void addRoom(TriangleMesh& m, float sx, float sy)
{
  const float t = 0.125f;
  m.addQuad({-t, -t, 0}, {sx + t, -t, 0}, {sx + t, sy + t, 0}, {-t, sy + t, 0});
  m.addBox({-t / 2, sy / 2, 1}, {t, sy + 2 * t, 2});
  m.addBox({sx + t / 2, sy / 2, 1}, {t, sy + 2 * t, 2});
  m.addBox({sx / 2, -t / 2, 1}, {sx, t, 2});
  m.addBox({sx / 2, sy + t / 2, 1}, {sx, t, 2});
}

/// Two 3 x 3 m rooms side by side (x in [0, 3] and [3.125, 6.125]) joined by
/// a doorway of width `door_m` centred at y = 1.5 in the partition wall.
World twoRooms(float door_m)
{
  World w;
  w.name = "two_rooms";
  addRoom(w.mesh, 6.125f, 3);
  const float t = 0.125f, lower = 1.5f - door_m / 2, upper = 3 - (1.5f + door_m / 2);
  w.mesh.addBox({3 + t / 2, lower / 2, 1}, {t, lower, 2});
  w.mesh.addBox({3 + t / 2, 3 - upper / 2, 1}, {t, upper, 2});
  w.start = mrpt::poses::CPose2D(1.5, 1.5, 0);
  return w;
}

int countSet(const FloorGrid& g)
{
  return static_cast<int>(std::count(g.cells.begin(), g.cells.end(), 1));
}

bool cellAt(const FloorGrid& g, double x, double y)
{
  const int ix = static_cast<int>(std::floor((x - g.origin.x()) / g.res_m));
  const int iy = static_cast<int>(std::floor((y - g.origin.y()) / g.res_m));
  return g.inside(ix, iy) && g.at(ix, iy) != 0;
}

/// Minimum centre-to-centre distance from cell (x, y) to a set cell of `g` (brute force).
double nearestSetCell(const FloorGrid& g, int x, int y)
{
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (g.at(i, j)) best = std::min(best, std::hypot(i - x, j - y) * g.res_m);
  return best;
}
}  // namespace

TEST(OccupiedVoxels, BoxWithFacesMidVoxelGivesItsShell)
{
  TriangleMesh m;
  // Faces at 0.125 and 2.375 (x, y), 0.125 and 1.375 (z): mid-voxel at res 0.25.
  m.addBox({1.25f, 1.25f, 0.75f}, {2.25f, 2.25f, 1.25f});
  const auto vox = occupiedVoxels(m, 0.25);
  EXPECT_EQ(vox.size(), std::size_t(10 * 10 * 6 - 8 * 8 * 4));  // 344
  const std::set<Key> s = [&]
  {
    std::set<Key> out;
    for (const auto& v : vox) out.insert(key(v));
    return out;
  }();
  EXPECT_EQ(s.size(), vox.size()) << "unique";
  EXPECT_TRUE(std::is_sorted(vox.begin(), vox.end(),
                             [](const auto& a, const auto& b) { return key(a) < key(b); }));
  EXPECT_TRUE(s.count({0, 0, 0}) && s.count({9, 9, 5}) && s.count({4, 0, 3}));
  EXPECT_FALSE(s.count({4, 4, 2}));  // interior
  for (const auto& v : vox)
  {
    ASSERT_TRUE(v.minCoeff() >= 0 && v.x() <= 9 && v.y() <= 9 && v.z() <= 5);
  }

  // Restricted to z in [0, 0.6]: layers 0, 1, 2 only.
  const auto low = occupiedVoxels(m, 0.25, 0.0, 0.6);
  EXPECT_EQ(low.size(), std::size_t(100 + 2 * 36));
  for (const auto& v : low) EXPECT_LE(v.z(), 2);
}

TEST(OccupiedVoxels, FarApartTrianglesAreSortedAndUnique)
{
  // 30 km apart at 1 cm: indices beyond the 21-bit packed sort key. Vertex
  // coordinates are multiples of 2^-8 (exact in float at 30 km).
  const float x = 30000.0f, d = 0.00390625f;
  TriangleMesh m;
  m.addTriangle({x + d, d, d}, {x + 2 * d, d, d}, {x + d, 2 * d, d});
  m.addTriangle({-2 * d, d, d}, {-d, d, d}, {-2 * d, 2 * d, d});
  m.addTriangle({-2 * d, d, d}, {-d, d, d}, {-2 * d, 2 * d, d});  // duplicate
  const auto vox = occupiedVoxels(m, 0.01);
  ASSERT_EQ(vox.size(), 2u);
  EXPECT_EQ(vox[0], VoxelIndex(-1, 0, 0));
  EXPECT_EQ(vox[1], VoxelIndex(3000000, 0, 0));
}

TEST(OccupiedVoxels, DegenerateTrianglesMarkTheirSegmentOrPoint)
{
  TriangleMesh m;
  // A zero-area triangle along the segment (0.05, 0.05, 0.05) -> (0.35, 0.05, 0.05).
  m.addTriangle({0.05f, 0.05f, 0.05f}, {0.35f, 0.05f, 0.05f}, {0.2f, 0.05f, 0.05f});
  m.addTriangle({0.55f, 0.55f, 0.55f}, {0.55f, 0.55f, 0.55f}, {0.55f, 0.55f, 0.55f});  // a point
  const auto vox = occupiedVoxels(m, 0.1);
  const std::vector<VoxelIndex> expected{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {5, 5, 5}};
  ASSERT_EQ(vox.size(), expected.size());
  for (std::size_t i = 0; i < vox.size(); ++i) EXPECT_EQ(vox[i], expected[i]) << i;
}

TEST(OccupiedVoxels, RandomTrianglesMatchDenseSampling)
{
  // Every voxel holding a sample point of the triangle must be reported, and
  // every reported voxel must lie within one sample spacing of a sample.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-1, 1);
  const double res = 0.1;
  for (int trial = 0; trial < 20; ++trial)
  {
    Vector3d p[3];
    for (auto& q : p) q = Vector3d(coord(rng), coord(rng), coord(rng));
    TriangleMesh m;
    m.addTriangle(p[0].cast<float>(), p[1].cast<float>(), p[2].cast<float>());
    for (auto& q : p) q = q.cast<float>().cast<double>();
    const auto vox = occupiedVoxels(m, res);
    std::set<Key> got;
    for (const auto& v : vox) got.insert(key(v));

    const int n = 300;
    const double spacing = ((p[1] - p[0]).norm() + (p[2] - p[0]).norm()) / n;
    std::set<Key> inner, dilated;
    for (int i = 0; i <= n; ++i)
    {
      for (int j = 0; i + j <= n; ++j)
      {
        const Vector3d q = p[0] + (p[1] - p[0]) * (double(i) / n) + (p[2] - p[0]) * (double(j) / n);
        const Eigen::Array3d f = q.array() / res;
        inner.insert({int(std::floor(f.x())), int(std::floor(f.y())), int(std::floor(f.z()))});
        const Eigen::Array3d lo = ((q.array() - spacing) / res).floor();
        const Eigen::Array3d hi = ((q.array() + spacing) / res).floor();
        for (int x = int(lo.x()); x <= int(hi.x()); ++x)
          for (int y = int(lo.y()); y <= int(hi.y()); ++y)
            for (int z = int(lo.z()); z <= int(hi.z()); ++z) dilated.insert({x, y, z});
      }
    }
    for (const auto& k : inner) ASSERT_TRUE(got.count(k)) << "trial " << trial << ": missed voxel";
    for (const auto& k : got) ASSERT_TRUE(dilated.count(k)) << "trial " << trial << ": extra voxel";
  }
}

TEST(ReachableFreeFloor, ClosedBoxRoom)
{
  World w;
  addRoom(w.mesh, 4, 3);
  const CollisionChecker checker(w, 0.03, 0.645);
  const double res = 0.05, r = 0.3;
  const auto rf = reachableFreeFloor(w, checker, mrpt::poses::CPose2D(2, 1.5, 0), r, res);
  const double ideal = (4 - 2 * r) * (3 - 2 * r);
  const double tolerance = 2 * ((4 - 2 * r) + (3 - 2 * r)) * res;  // one cell around the border
  EXPECT_NEAR(rf.reachable_area_m2, ideal, tolerance);
  EXPECT_LE(rf.reachable_area_m2, ideal + 1e-9) << "discretisation must stay conservative";
  EXPECT_NEAR(rf.free_floor_area_m2, 4.0 * 3.0, 2 * (4 + 3) * res);
  EXPECT_TRUE(cellAt(rf.obstacle, -0.01, 1.5));  // the wall's inner face
  EXPECT_TRUE(cellAt(rf.obstacle, -0.14, 1.5) || cellAt(rf.obstacle, -0.11, 1.5));  // outer face
  EXPECT_FALSE(cellAt(rf.obstacle, -0.3, 1.5));
  EXPECT_FALSE(cellAt(rf.obstacle, 2, 1.5));
  EXPECT_TRUE(cellAt(rf.reachable, 0.4, 0.4));
  EXPECT_FALSE(cellAt(rf.reachable, 0.2, 1.5));
  EXPECT_TRUE(cellAt(rf.free_floor, 0.05, 1.5));    // floor beside the wall the body sweeps
  EXPECT_FALSE(cellAt(rf.free_floor, 0.05, 0.05));  // a corner a disc cannot sweep
  EXPECT_FALSE(cellAt(rf.free_floor, -0.3, 1.5));   // outside the room
  // The grid covers the mesh bounds plus one cell.
  EXPECT_NEAR(rf.obstacle.origin.x(), -0.125 - res, 1e-6);
  EXPECT_GE(rf.obstacle.origin.x() + rf.obstacle.nx * res, 4.125 + res - 1e-6);
}

// A room open to the south on a wide ground plane: without a region the
// reachable floor leaks out into the yard; with the obstacle bounds as the
// region only the floor inside the building's extent counts.
TEST(ReachableFreeFloor, RegionKeepsAnOpenBuildingsFloorInside)
{
  World w;
  const float t = 0.125f, sx = 4, sy = 3;
  w.mesh.addQuad({-10, -10, 0}, {14, -10, 0}, {14, 13, 0}, {-10, 13, 0});  // the yard's floor
  w.mesh.addBox({-t / 2, sy / 2, 1}, {t, sy + 2 * t, 2});                  // west
  w.mesh.addBox({sx + t / 2, sy / 2, 1}, {t, sy + 2 * t, 2});              // east
  w.mesh.addBox({sx / 2, sy + t / 2, 1}, {sx, t, 2});                      // north; south open
  const CollisionChecker checker(w, 0.03, 0.645);
  const Eigen::AlignedBox2d b = obstacleBounds(checker);
  EXPECT_NEAR(b.min().x(), -0.125, 1e-4);
  EXPECT_NEAR(b.max().x(), 4.125, 1e-4);
  EXPECT_NEAR(b.min().y(), -0.125, 1e-4);
  EXPECT_NEAR(b.max().y(), 3.125, 1e-4);
  const mrpt::poses::CPose2D start(2, 1.5, 0);
  const auto leak = reachableFreeFloor(w, checker, start, 0.3, 0.05);
  const auto in = reachableFreeFloor(w, checker, start, 0.3, 0.05, &b);
  EXPECT_GT(leak.free_floor_area_m2, 100.0) << "out into the yard";
  EXPECT_TRUE(cellAt(leak.free_floor, 2.0, -5.0));
  EXPECT_FALSE(cellAt(in.free_floor, 2.0, -5.0));
  EXPECT_FALSE(cellAt(in.free_floor, 2.0, -0.2)) << "outside the bounds";
  EXPECT_TRUE(cellAt(in.free_floor, 2.0, -0.05));
  EXPECT_TRUE(cellAt(in.free_floor, 2.0, 1.5));
  EXPECT_NEAR(in.free_floor_area_m2, 4.0 * 3.125, 2 * (4 + 3) * 0.05);
  // A closed room is the same with its bounds as the region.
  World closed;
  addRoom(closed.mesh, 4, 3);
  const CollisionChecker cc(closed, 0.03, 0.645);
  const Eigen::AlignedBox2d cb = obstacleBounds(cc);
  EXPECT_NEAR(reachableFreeFloor(closed, cc, start, 0.3, 0.05).free_floor_area_m2,
              reachableFreeFloor(closed, cc, start, 0.3, 0.05, &cb).free_floor_area_m2, 1e-9);
}

TEST(ReachableFreeFloor, NarrowDoorwayBlocksTheSecondRoom)
{
  for (const float door : {0.4f, 1.0f})
  {
    const World w = twoRooms(door);
    const CollisionChecker checker(w, 0.03, 0.645);
    const auto rf = reachableFreeFloor(w, checker, w.start, 0.3);
    const double one_room = 2.4 * 2.4;
    EXPECT_TRUE(cellAt(rf.reachable, 1.5, 1.5));
    if (door < 0.5f)
    {
      EXPECT_FALSE(cellAt(rf.reachable, 4.6, 1.5)) << "0.4 m doorway";
      EXPECT_NEAR(rf.reachable_area_m2, one_room, 0.6);
      EXPECT_FALSE(cellAt(rf.free_floor, 4.6, 1.5));
    }
    else
    {
      EXPECT_TRUE(cellAt(rf.reachable, 4.6, 1.5)) << "1.0 m doorway";
      EXPECT_TRUE(cellAt(rf.reachable, 3.06, 1.5)) << "in the doorway";
      EXPECT_GT(rf.reachable_area_m2, 2 * one_room - 1.2);
      EXPECT_TRUE(cellAt(rf.free_floor, 4.6, 1.5));
    }
  }
}

TEST(ReachableFreeFloor, UnreachableStartGivesEmptyResult)
{
  const World w = twoRooms(1.0f);
  const CollisionChecker checker(w, 0.03, 0.645);
  const auto rf = reachableFreeFloor(w, checker, mrpt::poses::CPose2D(0.1, 1.5, 0), 0.3);
  EXPECT_EQ(rf.reachable_area_m2, 0.0);
  EXPECT_EQ(rf.free_floor_area_m2, 0.0);
  EXPECT_EQ(countSet(rf.reachable), 0);
  EXPECT_GT(countSet(rf.obstacle), 0);
  const auto outside = reachableFreeFloor(w, checker, mrpt::poses::CPose2D(50, 50, 0), 0.3);
  EXPECT_EQ(outside.reachable_area_m2, 0.0);
}

TEST(ReachableFreeFloor, MatchesBruteForceOnClutteredRoom)
{
  World w;
  addRoom(w.mesh, 3, 2.5);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> x(0.3, 2.7), y(0.3, 2.2), s(0.05, 0.4), yaw(0, 3);
  for (int i = 0; i < 6; ++i)
    w.mesh.addBox({float(x(rng)), float(y(rng)), 0.3f}, {float(s(rng)), float(s(rng)), 0.6f},
                  float(yaw(rng)));
  const CollisionChecker checker(w, 0.03, 0.645);
  const double res = 0.1, r = 0.25;
  const auto rf = reachableFreeFloor(w, checker, mrpt::poses::CPose2D(0.35, 0.35, 0), r, res);
  ASSERT_GT(rf.reachable_area_m2, 0);
  const FloorGrid& g = rf.obstacle;
  for (int iy = 0; iy < g.ny; ++iy)
  {
    for (int ix = 0; ix < g.nx; ++ix)
    {
      const bool clear = nearestSetCell(g, ix, iy) > r;
      if (rf.reachable.at(ix, iy))
      {
        ASSERT_TRUE(clear) << ix << "," << iy;
        for (int dy = -1; dy <= 1; ++dy)  // closed under 8-neighbourhood among clear cells
        {
          for (int dx = -1; dx <= 1; ++dx)
          {
            if (g.inside(ix + dx, iy + dy) && nearestSetCell(g, ix + dx, iy + dy) > r)
            {
              ASSERT_TRUE(rf.reachable.at(ix + dx, iy + dy)) << ix + dx << "," << iy + dy;
            }
          }
        }
      }
      const bool free = !g.at(ix, iy) && nearestSetCell(rf.reachable, ix, iy) <= r;
      ASSERT_EQ(rf.free_floor.at(ix, iy) != 0, free) << ix << "," << iy;
    }
  }
}

TEST(TopView, WritesPngOfTheExpectedSize)
{
  World w;
  addRoom(w.mesh, 4, 3);                                // bounds 4.25 x 3.25 m
  w.mesh.addBox({1, 1, 0.25f}, {0.5f, 0.5f, 0.5f});     // low obstacle: dark
  w.mesh.addBox({3, 2, 1.0f}, {0.6f, 0.6f, 0.2f});      // overhang above the robot: blue
  w.mesh.addBox({3.2f, 2, 0.15f}, {0.1f, 0.1f, 0.3f});  // low box under the overhang: grey
  w.mesh.addQuad({2, 2.61f, 0}, {3, 2.61f, 0}, {3, 2.61f, 2}, {2, 2.61f, 2});  // thin wall
  const RayCaster caster(w.mesh);
  const std::string path =
      voxplore::test::tempPath("voxplore_topview_test.png");
  std::remove(path.c_str());
  const std::vector<mrpt::poses::CPose2D> traj{{2, 0.5, 0}, {2.5, 0.5, 0}, {3.5, 1.0, 0}};
  writeTopView(w, caster, path, 20.0, traj);
  ASSERT_TRUE(std::filesystem::exists(path));

  mrpt::img::CImage img;
  ASSERT_TRUE(img.loadFromFile(path));
  EXPECT_EQ(img.getWidth(), 85u);   // 4.25 m * 20 px/m
  EXPECT_EQ(img.getHeight(), 65u);  // 3.25 m * 20 px/m
  EXPECT_TRUE(img.isColor());
  const auto px = [&](double x, double y)
  {
    const int u = int((x + 0.125) * 20), v = int((3.125 - y) * 20);
    return Eigen::Vector3i(img.at<uint8_t>(u, v, 0), img.at<uint8_t>(u, v, 1),
                           img.at<uint8_t>(u, v, 2));
  };
  EXPECT_GT(px(0.5, 2.5).minCoeff(), 200) << "floor is light";
  EXPECT_LT(px(1, 1).maxCoeff(), 160) << "low obstacle is dark";
  const Eigen::Vector3i blue = px(3, 2), red = px(3.0, 0.75);
  EXPECT_GT(std::abs(blue[0] - blue[2]), 60) << "overhang is blue (channel order aside)";
  EXPECT_LT(px(3.2, 2).maxCoeff(), 160) << "what the robot hits under an overhang is dark";
  EXPECT_LT(px(2.5, 2.61).maxCoeff(), 160) << "a zero-thickness wall is drawn";
  EXPECT_GT(std::abs(red[0] - red[2]), 100) << "trajectory is red (channel order aside)";
  // Image row 0 is north: the low obstacle (south-west) is in the lower half.
  EXPECT_LT(px(1, 1).maxCoeff(), px(1, 2.2).maxCoeff());

  EXPECT_THROW(writeTopView(w, caster, "/nonexistent_dir/x/top.png", 20.0), std::runtime_error);
  std::remove(path.c_str());
}

TEST(OccupiedVoxels, FacesOnGridPlanesAreNotLostToRounding)
{
  // 4.0 / 0.05 rounds to 79.999...: a face at x = 4 must still mark voxels
  // (both neighbours: voxels are closed boxes), as must every face of the box.
  TriangleMesh m;
  m.addBox({5.0f, 0.25f, 0.9f}, {2.0f, 0.5f, 1.8f});  // x in [4, 6], y in [0, 0.5], z in [0, 1.8]
  const auto vox = occupiedVoxels(m, 0.05);
  std::set<int> xs_at_mid;
  for (const auto& v : vox)
    if (v.y() == 5 && v.z() == 18) xs_at_mid.insert(v.x());
  EXPECT_EQ(xs_at_mid, (std::set<int>{79, 80, 119, 120}));
  // 2 x (40 x 10 + 40 x 36 + 10 x 36) face voxels, doubled across each face plane,
  // minus nothing: every face lies on a grid plane.
  EXPECT_GT(vox.size(), 2u * (40 * 10 + 40 * 36 + 10 * 36));
}
