/* voxplore — tests of the footprint-true reachable floor (issue 10): doors,
 * corridors, turning, the floor seen from the reachable set, and agreement
 * with the exact collision checker. */

#include <gtest/gtest.h>
#include <voxplore/sim/footprint_reach.h>
#include <voxplore/sim/ground_truth.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace voxplore::sim;

namespace
{
constexpr float kWall = 0.15f, kHeight = 2.5f;
const Footprint kOmniRob{1.2, 0.712};

/// An axis-aligned wall (box) over [x0, x1] x [y0, y1], 2.5 m high.
void wall(World& w, float x0, float y0, float x1, float y1)
{
  w.mesh.addBox({0.5f * (x0 + x1), 0.5f * (y0 + y1), 0.5f * kHeight}, {x1 - x0, y1 - y0, kHeight});
}

/// The floor under [x0, x1] x [y0, y1].
void floorQuad(World& w, float x0, float y0, float x1, float y1)
{
  w.mesh.addQuad({x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0});
}

/// Two 4 x 4 m rooms side by side, the partition x in [4, 4.15] with a door
/// of width `door_m` centred at y = 2; start in the west room facing east.
World twoRoomsWithDoor(float door_m)
{
  World w;
  w.name = "door";
  floorQuad(w, -kWall, -kWall, 8.15f + kWall, 4 + kWall);
  wall(w, -kWall, -kWall, 8.15f + kWall, 0);     // south
  wall(w, -kWall, 4, 8.15f + kWall, 4 + kWall);  // north
  wall(w, -kWall, 0, 0, 4);                      // west
  wall(w, 8.15f, 0, 8.15f + kWall, 4);           // east
  wall(w, 4, 0, 4 + kWall, 2 - door_m / 2);      // partition below the door
  wall(w, 4, 2 + door_m / 2, 4 + kWall, 4);      // ... above it
  w.start = mrpt::poses::CPose2D(2, 2, 0);
  return w;
}

/// A 4 x 4 m room with two dead-end corridors 4 m long leaving its east
/// wall: free width `narrow_m` centred at y = 1, `wide_m` centred at y = 3.
World roomWithCorridors(float narrow_m, float wide_m)
{
  World w;
  w.name = "corridors";
  floorQuad(w, -kWall, -kWall, 8 + kWall, 4 + kWall);
  wall(w, -kWall, -kWall, 4 + kWall, 0);
  wall(w, -kWall, 4, 4 + kWall, 4 + kWall);
  wall(w, -kWall, 0, 0, 4);
  const float a0 = 1 - narrow_m / 2, a1 = 1 + narrow_m / 2;
  const float b0 = 3 - wide_m / 2, b1 = 3 + wide_m / 2;
  wall(w, 4, 0, 4 + kWall, a0);  // east wall of the room, around the two mouths
  wall(w, 4, a1, 4 + kWall, b0);
  wall(w, 4, b1, 4 + kWall, 4);
  for (const auto& [lo, hi] : {std::pair<float, float>{a0, a1}, {b0, b1}})
  {
    wall(w, 4, lo - kWall, 8, lo);
    wall(w, 4, hi, 8, hi + kWall);
    wall(w, 8, lo - kWall, 8 + kWall, hi + kWall);
  }
  w.start = mrpt::poses::CPose2D(2, 2, 0);
  return w;
}

/// A closed straight corridor of free width `width_m`, 6 m long, along x.
World closedCorridor(float width_m)
{
  World w;
  w.name = "corridor";
  floorQuad(w, -kWall, -kWall, 6 + kWall, width_m + kWall);
  wall(w, -kWall, -kWall, 6 + kWall, 0);
  wall(w, -kWall, width_m, 6 + kWall, width_m + kWall);
  wall(w, -kWall, 0, 0, width_m);
  wall(w, 6, 0, 6 + kWall, width_m);
  w.start = mrpt::poses::CPose2D(3, width_m / 2, 0);
  return w;
}

/// A 4 x 4 m room; its east wall has a 0.5 m gap at y = 2 into a closed
/// 2 x 4 m room; a 4 x 1.85 m room lies behind its solid north wall.
World roomsBehindGapAndWall()
{
  World w;
  w.name = "gap";
  floorQuad(w, -kWall, -kWall, 6.15f + kWall, 6 + kWall);
  wall(w, -kWall, -kWall, 6.15f + kWall, 0);
  wall(w, -kWall, 0, 0, 6);
  wall(w, 4, 0, 4 + kWall, 1.75f);
  wall(w, 4, 2.25f, 4 + kWall, 4);
  wall(w, 6.15f, 0, 6.15f + kWall, 4);
  wall(w, 4, 4, 6.15f + kWall, 4 + kWall);   // north of the gap room
  wall(w, -kWall, 4, 4 + kWall, 4 + kWall);  // solid north wall of the start room
  wall(w, 4, 4 + kWall, 4 + kWall, 6);       // east of the walled room
  wall(w, -kWall, 6, 4 + kWall, 6 + kWall);  // north of the walled room
  w.start = mrpt::poses::CPose2D(2, 2, 0);
  return w;
}

bool cellAt(const FloorGrid& g, double x, double y)
{
  const int ix = static_cast<int>(std::floor((x - g.origin.x()) / g.res_m));
  const int iy = static_cast<int>(std::floor((y - g.origin.y()) / g.res_m));
  return g.inside(ix, iy) && g.at(ix, iy) != 0;
}

/// The simulator's checker: geometry between 3 cm and the omniRob's height.
CollisionChecker checkerOf(const World& w)
{
  return CollisionChecker(w, 0.03, 0.645);
}
}  // namespace

class DoorWidth : public ::testing::TestWithParam<float>
{
};

TEST_P(DoorWidth, RoomBehindTheDoorIsReachableForTheRectangleNotForItsCircle)
{
  const World w = twoRoomsWithDoor(GetParam());
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  const ReachableFloor circle =
      reachableFreeFloor(w, checker, w.start, kOmniRob.circumradius(), 0.05);
  for (const auto& [x, y] : {std::pair{6.0, 2.0}, {7.2, 1.0}, {6.0, 3.0}, {5.0, 2.0}})
  {
    EXPECT_TRUE(cellAt(r.reachable, x, y)) << "door " << GetParam() << " at " << x << ", " << y;
    EXPECT_TRUE(cellAt(r.free_floor, x, y)) << x << ", " << y;
    EXPECT_FALSE(cellAt(circle.reachable, x, y)) << x << ", " << y;
  }
  EXPECT_TRUE(cellAt(circle.reachable, 2.0, 2.0));
  // Through the door lengthwise (yaw 0) but never sideways (yaw 90 deg).
  const int ix = static_cast<int>(std::floor((4.075 - r.reachable.origin.x()) / 0.05));
  const int iy = static_cast<int>(std::floor((2.0 - r.reachable.origin.y()) / 0.05));
  EXPECT_TRUE(r.reachableAt(ix, iy, 0));
  EXPECT_FALSE(r.reachableAt(ix, iy, r.yaw_bins / 2));
  EXPECT_GT(r.free_floor_area_m2, 28.0);  // both rooms, 32 m^2 of floor
}

INSTANTIATE_TEST_SUITE_P(FootprintReach, DoorWidth, ::testing::Values(0.85f, 0.9f, 1.0f));

TEST(FootprintReach, DoorNarrowerThanTheRectangleKeepsItOut)
{
  const World w = twoRoomsWithDoor(0.70f);  // the omniRob is 0.712 m wide
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  EXPECT_TRUE(cellAt(r.reachable, 2.0, 2.0));
  for (const auto& [x, y] : {std::pair{6.0, 2.0}, {7.2, 1.0}, {5.0, 2.0}})
    EXPECT_FALSE(cellAt(r.reachable, x, y)) << x << ", " << y;
}

TEST(FootprintReach, CorridorNarrowerThanTheRectangleIsUnreachable)
{
  const World w = roomWithCorridors(0.65f, 0.80f);
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  for (const double x : {5.0, 6.0, 7.3})
  {
    EXPECT_TRUE(cellAt(r.reachable, x, 3.0)) << "0.80 m corridor at x = " << x;
    EXPECT_FALSE(cellAt(r.reachable, x, 1.0)) << "0.65 m corridor at x = " << x;
  }
  // The body never enters the narrow corridor: only its mouth can be seen.
  EXPECT_FALSE(cellAt(r.swept, 5.0, 1.0));
  EXPECT_FALSE(cellAt(r.free_floor, 7.5, 1.0));  // 3.5 m past the reachable centres' reach
}

TEST(FootprintReach, RobotThatFitsButCannotTurnNeverReachesYaw90)
{
  const World w = closedCorridor(0.8f);
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  const FloorGrid& g = r.reachable;
  int reachable_cells = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
    {
      reachable_cells += g.at(ix, iy);
      for (int k = 0; k < r.yaw_bins; ++k)
      {
        const int off = std::min(k, r.yaw_bins - k);  // bins from yaw 0
        if (r.reachableAt(ix, iy, k))
        {
          EXPECT_LE(off, 2) << "bin " << k;
        }
      }
    }
  EXPECT_GT(reachable_cells * 0.05 * 0.05, 0.2);  // it drives along the corridor
  EXPECT_TRUE(cellAt(g, 1.0, 0.4));
  EXPECT_TRUE(cellAt(g, 5.0, 0.4));
  // Control: in a 2 m wide corridor it turns in place.
  const World wide = closedCorridor(2.0f);
  const CollisionChecker wide_checker = checkerOf(wide);
  const FootprintReach rw = footprintReachableFloor(wide, wide_checker, wide.start, kOmniRob);
  const int sx = static_cast<int>(std::floor((3.0 - rw.reachable.origin.x()) / 0.05));
  const int sy = static_cast<int>(std::floor((1.0 - rw.reachable.origin.y()) / 0.05));
  EXPECT_TRUE(rw.reachableAt(sx, sy, rw.yaw_bins / 2));
}

/// A box room 4.5 cm wider than the omniRob on every side, centred on the
/// cell centre (1.025, 1.025): it fits at yaws within one bin of 0 only, and
/// only at that cell. With `pole`, a 4 mm post stands where its front left
/// corner passes half-way through the turn to the next bin (yaw 1.25 deg):
/// outside the rectangle at yaw 0 and at yaw 2.5 deg, but on the corner's arc.
World tightBox(bool pole)
{
  World w;
  w.name = "tight_box";
  floorQuad(w, -1, -1, 3, 3);
  const float c = 1.025f, hx = 0.645f, hy = 0.401f;
  wall(w, c - hx - kWall, c - hy - kWall, c + hx + kWall, c - hy);
  wall(w, c - hx - kWall, c + hy, c + hx + kWall, c + hy + kWall);
  wall(w, c - hx - kWall, c - hy, c - hx, c + hy);
  wall(w, c + hx, c - hy, c + hx + kWall, c + hy);
  if (pole)
  {
    const double half = 0.5 * M_PI / 72;  // half a bin of 2.5 deg
    const Eigen::Vector2d corner(0.6, 0.356);
    const Eigen::Vector2d p = Eigen::Rotation2Dd(half) * corner;
    w.mesh.addBox({c + static_cast<float>(p.x()), c + static_cast<float>(p.y()), 0.5f},
                  {0.004f, 0.004f, 1.0f});
  }
  w.start = mrpt::poses::CPose2D(c, c, 0);
  return w;
}

TEST(FootprintReach, TurningInPlaceClearsTheCornersArc)
{
  for (const bool pole : {false, true})
  {
    const World w = tightBox(pole);
    const CollisionChecker checker = checkerOf(w);
    const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
    ASSERT_TRUE(r.start_free);
    const int s = static_cast<int>(std::floor((1.025 - r.reachable.origin.x()) / 0.05));
    ASSERT_NEAR(r.reachable.center(s, s).x(), 1.025, 1e-9);
    EXPECT_EQ(std::count(r.reachable.cells.begin(), r.reachable.cells.end(), 1), 1);
    const Eigen::Vector2d c = r.reachable.center(s, s);
    // Both ends of the turn fit; with the pole the turn between them does not.
    EXPECT_FALSE(checker.collides(mrpt::poses::CPose2D(c.x(), c.y(), 0), kOmniRob));
    EXPECT_FALSE(checker.collides(mrpt::poses::CPose2D(c.x(), c.y(), r.binYaw(1)), kOmniRob));
    EXPECT_EQ(checker.collides(mrpt::poses::CPose2D(c.x(), c.y(), 0.5 * r.binYaw(1)), kOmniRob),
              pole);
    EXPECT_TRUE(r.reachableAt(s, s, 0));
    EXPECT_EQ(r.reachableAt(s, s, 1), !pole) << (pole ? "with" : "without") << " the pole";
  }
}

TEST(FootprintReach, FloorSeenThroughAGapCountsFloorBehindAWallDoesNot)
{
  const World w = roomsBehindGapAndWall();
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  // Behind the 0.5 m gap: no body gets there, the cameras see it.
  EXPECT_FALSE(cellAt(r.reachable, 4.6, 2.0));
  EXPECT_FALSE(cellAt(r.swept, 4.6, 2.0));
  EXPECT_TRUE(cellAt(r.visible, 4.6, 2.0));
  EXPECT_TRUE(cellAt(r.free_floor, 4.6, 2.0));
  EXPECT_TRUE(cellAt(r.free_floor, 5.5, 2.0));
  // Behind the solid wall, within 3 m of reachable centres: not counted.
  EXPECT_FALSE(cellAt(r.free_floor, 2.0, 4.6));
  EXPECT_FALSE(cellAt(r.free_floor, 3.0, 5.0));
  // Without the cameras only the body counts.
  FootprintReachParams blind;
  blind.view_range_m = 0;
  const FootprintReach rb = footprintReachableFloor(w, checker, w.start, kOmniRob, blind);
  EXPECT_FALSE(cellAt(rb.free_floor, 4.6, 2.0));
  EXPECT_LT(rb.free_floor_area_m2, r.free_floor_area_m2 - 1.0);
  // The body sweeps the room's corners the inscribed circle does not reach.
  EXPECT_TRUE(cellAt(rb.free_floor, 0.07, 0.07));
}

TEST(FootprintReach, ReachableStatesAgreeWithTheExactChecker)
{
  const World w = twoRoomsWithDoor(0.9f);
  const CollisionChecker checker = checkerOf(w);
  const FootprintReach r = footprintReachableFloor(w, checker, w.start, kOmniRob);
  ASSERT_TRUE(r.start_free);
  const FloorGrid& g = r.reachable;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> cx(0, g.nx - 1), cy(0, g.ny - 1), bin(0, r.yaw_bins - 1);
  int reachable = 0, free_in_room = 0, agree_in_room = 0, free_neighbours = 0;
  for (int i = 0; i < 200000; ++i)
  {
    const int ix = cx(rng), iy = cy(rng), k = bin(rng);
    const Eigen::Vector2d c = g.center(ix, iy);
    const mrpt::poses::CPose2D pose(c.x(), c.y(), r.binYaw(k));
    const bool collides = checker.collides(pose, kOmniRob);
    if (r.reachableAt(ix, iy, k))
    {
      reachable++;
      EXPECT_FALSE(collides) << "reachable state (" << c.x() << ", " << c.y() << ", bin " << k
                             << ") collides";
      // Translation is exact too: a neighbour cell where the checker says
      // the rectangle fits at the same yaw is reachable.
      const int nx = ix + static_cast<int>(rng() % 3) - 1,
                ny = iy + static_cast<int>(rng() % 3) - 1;
      const Eigen::Vector2d n = g.center(nx, ny);
      if (!checker.collides(mrpt::poses::CPose2D(n.x(), n.y(), r.binYaw(k)), kOmniRob))
      {
        free_neighbours++;
        EXPECT_TRUE(r.reachableAt(nx, ny, k))
            << "(" << n.x() << ", " << n.y() << ", bin " << k << ") fits beside a reachable state";
      }
    }
    // In the convex west room away from the door, every free state is
    // connected to the start: reachable exactly when the checker says free.
    if (c.x() < 3.2)
    {
      free_in_room += !collides;
      agree_in_room += r.reachableAt(ix, iy, k) == !collides;
      if (r.reachableAt(ix, iy, k) != !collides)
        ADD_FAILURE() << "(" << c.x() << ", " << c.y() << ", bin " << k << "): checker "
                      << (collides ? "collides" : "free");
    }
  }
  EXPECT_GT(reachable, 1000);
  EXPECT_GT(free_neighbours, 900);
  EXPECT_GT(free_in_room, 1000);
  EXPECT_GT(agree_in_room, 5000);
}
