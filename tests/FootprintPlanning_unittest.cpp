/* voxplore tests — planning the omniRob's rectangle in (x, y, yaw) (issue 13):
 * doors passed turned lengthwise or refused, corridor corners never clipped. */
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/footprint.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <limits>
#include <random>
#include <vector>

#include "exploration_test_maps.h"
#include "test_worlds.h"

using namespace voxplore::exploration;
using mrpt::poses::CPose2D;
using voxplore::test::makeGround;
using voxplore::test::paint;

namespace
{
constexpr double kRes = 0.05;
constexpr double kLength = 1.2, kWidth = 0.712;  // the omniRob

CollisionParams omniRob()
{
  CollisionParams p;
  p.model = CollisionParams::Model::Footprint;
  p.r_coll_m = std::hypot(kLength / 2, kWidth / 2);
  p.footprint_length_m = kLength;
  p.footprint_width_m = kWidth;
  return p;
}

/// The omniRob at the defaults but on whole squares (footprint_square_share
/// 1, the default up to the twenty-second session): the door widths of the
/// cases below are set against whole squares.
CollisionParams omniRobWholeSquares()
{
  CollisionParams p = omniRob();
  p.footprint_square_share = 1.0;
  return p;
}

/// The omniRob as the cases below were found: every yaw of a bin at the cell
/// centres on whole squares (footprint_bin_span 1, footprint_lateral_m 0,
/// footprint_square_share 1; the defaults since the sixteenth session are
/// 0.35 and 2.5 cm, since the twenty-third half squares, and they open some
/// of their doors without the mechanism each case tests).
CollisionParams omniRobWholeBin()
{
  CollisionParams p = omniRobWholeSquares();
  p.footprint_bin_span = 1.0;
  p.footprint_lateral_m = 0.0;
  return p;
}

/// Two known rooms, x in [-3, 0) and [0.1, 3.1), y in [-1.5, 1.5), split by
/// a 10 cm wall with a door of `door_m` centred on y = 0; walls round both.
GroundGrid twoRoomsWithADoor(double door_m)
{
  GroundGrid g = makeGround(-3.2, 3.3, -1.7, 1.7, kRes, GroundState::Occupied);
  paint(g, -3.0, 3.1, -1.5, 1.5, GroundState::Free);
  paint(g, 0.0, 0.1, -1.5, -0.5 * door_m, GroundState::Occupied);
  paint(g, 0.0, 0.1, 0.5 * door_m, 1.5, GroundState::Occupied);
  return g;
}

/// Does the rectangle (half sides hl, hw) at `pose` overlap the square cell
/// (cx, cy) of g? Separating axes: the two of the rectangle and the two of
/// the square.
bool overlapsCell(const GroundGrid& g, int cx, int cy, const CPose2D& pose, double hl, double hw)
{
  const double h = 0.5 * g.state.getResolution();
  const double sx = g.state.idx2x(cx), sy = g.state.idx2y(cy);
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  // the square's centre in the rectangle's frame
  const double dx = sx - pose.x(), dy = sy - pose.y();
  const double u = c * dx + s * dy, v = -s * dx + c * dy;
  const double support = h * (std::abs(c) + std::abs(s));
  if (std::abs(u) > hl + support || std::abs(v) > hw + support) return false;
  // the rectangle's extent along the world axes
  const double ex = hl * std::abs(c) + hw * std::abs(s), ey = hl * std::abs(s) + hw * std::abs(c);
  return std::abs(dx) <= ex + h && std::abs(dy) <= ey + h;
}

/// The rectangle at `pose` overlaps an Occupied cell of g.
bool clipsAWall(const GroundGrid& g, const CPose2D& pose, double hl = kLength / 2,
                double hw = kWidth / 2)
{
  for (int cy = 0; cy < static_cast<int>(g.state.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(g.state.getSizeX()); ++cx)
      if (*g.state.cellByIndex(cx, cy) == GroundState::Occupied &&
          overlapsCell(g, cx, cy, pose, hl, hw))
        return true;
  return false;
}

/// Every pose along the path (1 cm and 1 deg apart, turns in place included)
/// keeps the bare rectangle off every wall square.
void expectNeverClips(const GroundGrid& g, const Path& path)
{
  ASSERT_EQ(path.waypoints.size(), path.yaws.size());
  for (std::size_t k = 0; k + 1 < path.waypoints.size(); ++k)
  {
    const Eigen::Vector2d a = path.waypoints[k], b = path.waypoints[k + 1];
    const double ya = path.yaws[k], yb = path.yaws[k + 1];
    // The drive to waypoint k+1 turns to its yaw first, then translates; or
    // (turn_on_way) turns in proportion to the way made.
    const uint8_t kind = k + 1 < path.turn_on_way.size() ? path.turn_on_way[k + 1] : uint8_t(0);
    const bool on_way = kind != 0;
    if (kind == Path::kTurnFromAnyYaw)
    {
      // A lead-in starts in whatever yaw the robot has: every yaw (10 deg
      // apart) every 2 cm along it.
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.02)));
      for (int i = 0; i <= n; ++i)
        for (int deg = 0; deg < 360; deg += 10)
        {
          const Eigen::Vector2d q = a + (b - a) * (static_cast<double>(i) / n);
          ASSERT_FALSE(clipsAWall(g, CPose2D(q.x(), q.y(), mrpt::DEG2RAD(deg))))
              << "lead-in to waypoint " << k + 1 << " at (" << q.x() << ", " << q.y() << ") yaw "
              << deg;
        }
      continue;
    }
    const int turns = std::max(1, static_cast<int>(std::ceil(std::abs(yb - ya) / 0.0175)));
    for (int i = 0; i <= turns && !on_way; ++i)
    {
      const CPose2D p(a.x(), a.y(), ya + (yb - ya) * i / turns);
      ASSERT_FALSE(clipsAWall(g, p)) << "turning at waypoint " << k << " to yaw " << p.phi();
    }
    const int steps = std::max({1, static_cast<int>(std::ceil((b - a).norm() / 0.01)), on_way ? turns : 1});
    for (int i = 0; i <= steps; ++i)
    {
      const double f = static_cast<double>(i) / steps;
      const Eigen::Vector2d q = a + (b - a) * f;
      ASSERT_FALSE(clipsAWall(g, CPose2D(q.x(), q.y(), on_way ? ya + (yb - ya) * f : yb)))
          << "on the way to waypoint " << k + 1 << " at (" << q.x() << ", " << q.y() << ")";
    }
  }
}

struct Planned
{
  CollisionSpace cs;
  FootprintSpace fs;
};

Planned footprintSpaceOf(GroundGrid& g, const CPose2D& robot, const CollisionParams& p = omniRob(),
                         const SweptPath& swept = {})
{
  cellOf(g.state, Eigen::Vector2d(robot.x(), robot.y()), g.robot);
  Planned out;
  out.cs = computeCollisionSpace(g, p);
  out.fs = computeFootprintSpace(g, out.cs, p, robot, swept);
  applyFootprint(out.cs, out.fs);
  return out;
}

bool reachedAt(const Planned& pl, double x, double y)
{
  Cell c;
  if (!cellOf(pl.fs.reach, Eigen::Vector2d(x, y), c)) return false;
  return *pl.fs.reach.cellByIndex(c.cx, c.cy) != 0;
}
}  // namespace

TEST(FootprintSpace, ANinetyCentimetreDoorIsPassedTurnedLengthwise)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  // Start across the door's axis: the robot must turn to pass.
  const CPose2D start(-1.5, 0.3, M_PI / 2);
  const Planned pl = footprintSpaceOf(g, start);
  EXPECT_TRUE(reachedAt(pl, 1.6, 0.0));
  // The circle of the thesis does not pass.
  CollisionParams circle = omniRob();
  circle.model = CollisionParams::Model::Circle;
  const CollisionSpace cs_circle = computeCollisionSpace(g, circle);
  EXPECT_FALSE(planPath(cs_circle, {start.x(), start.y()}, {1.6, 0.0}, PathParams{}));

  const auto path = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.0}, M_PI / 2, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
  // In the doorway (x in [0, 0.1]) the robot is lengthwise: yaw 0 or pi, within two bins.
  bool crossed = false;
  for (std::size_t k = 1; k < path->waypoints.size(); ++k)
  {
    const Eigen::Vector2d a = path->waypoints[k - 1], b = path->waypoints[k];
    if ((a.x() - 0.05) * (b.x() - 0.05) > 0) continue;
    crossed = true;
    const double off = std::abs(mrpt::math::wrapToPi(2.0 * path->yaws[k])) / 2.0;
    EXPECT_LE(off, mrpt::DEG2RAD(12.0)) << "yaw through the door " << path->yaws[k];
    EXPECT_TRUE(path->narrow[k]);
  }
  EXPECT_TRUE(crossed);
  ASSERT_TRUE(path->final_yaw);
  EXPECT_NEAR((path->waypoints.back() - Eigen::Vector2d(1.6, 0.0)).norm(), 0.0, 1e-9);
}

// [path] turn_on_the_way_deg (issue 15): the turns in place of the door
// case above are made along the translations after them where the turn
// layer holds every yaw between; the robot then never stops to turn there.
TEST(FootprintSpace, TurnsOnTheWayReplaceTurnsInPlaceAndNeverClip)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  const CPose2D start(-1.5, 0.3, M_PI / 2);
  const Planned pl = footprintSpaceOf(g, start);
  PathParams in_place;
  in_place.turn_on_the_way_deg = 0;
  PathParams on_way;
  on_way.turn_on_the_way_deg = 150;
  const auto a = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.0}, M_PI / 2, in_place);
  const auto b = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.0}, M_PI / 2, on_way);
  ASSERT_TRUE(a && b);
  const auto turnsInPlace = [](const Path& p)
  {
    std::size_t n = 0;
    for (std::size_t k = 1; k < p.waypoints.size(); ++k)
      n += (p.waypoints[k] - p.waypoints[k - 1]).norm() < 1e-9 && p.yaws[k] != p.yaws[k - 1];
    return n;
  };
  ASSERT_EQ(b->turn_on_way.size(), b->waypoints.size());
  const auto merged = b->turn_on_way.size() -
                      std::count(b->turn_on_way.begin(), b->turn_on_way.end(), uint8_t(0));
  std::cout << "[ turns ] in place " << turnsInPlace(*a) << " of " << a->waypoints.size()
            << " waypoints; on the way: in place " << turnsInPlace(*b) << ", on the way " << merged
            << " of " << b->waypoints.size() << std::endl;
  EXPECT_GE(turnsInPlace(*a), 1u);
  EXPECT_GE(merged, 1u);
  EXPECT_LT(turnsInPlace(*b), turnsInPlace(*a));
  EXPECT_EQ(std::count(a->turn_on_way.begin(), a->turn_on_way.end(), 1), 0);
  // The same way: the translations are the same (the turns left out).
  EXPECT_NEAR(a->length_m, b->length_m, 1e-9);
  expectNeverClips(g, *b);
  for (std::size_t k = 1; k < b->waypoints.size(); ++k)
    if (b->turn_on_way[k])
    {
      EXPECT_TRUE(b->narrow[k]) << k;
      EXPECT_GT((b->waypoints[k] - b->waypoints[k - 1]).norm(), 1e-9) << k;
    }
}

// Lead-ins (issue 15): the wide way before the door, which MRPT's reactive
// drive would end facing its own direction of travel, turns to the door's
// yaw on the way, from any yaw; the last wide way turns to the goal's yaw
// (no turn in place at the goal). No yaw clips a wall on a lead-in.
TEST(FootprintSpace, LeadInsTurnOnTheWideWayToThePassageAndToTheGoalYaw)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  const CPose2D start(-1.5, 0.3, M_PI / 2);
  const Planned pl = footprintSpaceOf(g, start);
  PathParams on_way;
  on_way.turn_on_the_way_deg = 150;
  const auto door = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.0}, M_PI / 2, on_way);
  ASSERT_TRUE(door);
  expectNeverClips(g, *door);
  std::size_t into_door = 0;
  for (std::size_t k = 1; k + 1 < door->waypoints.size(); ++k)
    if (door->turn_on_way[k] == Path::kTurnFromAnyYaw && door->narrow[k + 1])
    {
      ++into_door;
      EXPECT_TRUE(door->narrow[k]);
      EXPECT_NE(door->turn_on_way[k + 1], Path::kTurnFromPrevious) << "turned before, on the lead-in";
      EXPECT_NEAR(mrpt::math::wrapToPi(door->yaws[k] - door->yaws[k + 1]), 0.0, 1e-9);
      EXPECT_LT(door->waypoints[k].x(), 0.0);  // before the door
    }
  EXPECT_GE(into_door, 1u);

  const CPose2D in_room(-2.0, 0.0, 0.0);
  const Planned room = footprintSpaceOf(g, in_room);
  const auto goal = planFootprintPath(room.cs, room.fs, in_room, {-1.0, 0.5}, M_PI / 2, on_way);
  ASSERT_TRUE(goal && goal->final_yaw);
  expectNeverClips(g, *goal);
  const std::size_t n = goal->waypoints.size();
  ASSERT_GE(n, 2u);
  EXPECT_EQ(goal->turn_on_way[n - 1], Path::kTurnFromAnyYaw);
  EXPECT_GT((goal->waypoints[n - 1] - goal->waypoints[n - 2]).norm(), 1e-9) << "a turn in place at the goal";
  EXPECT_NEAR(mrpt::math::wrapToPi(goal->yaws[n - 1] - *goal->final_yaw), 0.0, 1e-9);
  EXPECT_NEAR(mrpt::math::wrapToPi(2.0 * (*goal->final_yaw - M_PI / 2)), 0.0, 0.2);
  // Off (stop-and-scan): no lead-in.
  const auto off = planFootprintPath(room.cs, room.fs, in_room, {-1.0, 0.5}, M_PI / 2, PathParams{});
  ASSERT_TRUE(off);
  EXPECT_EQ(std::count(off->turn_on_way.begin(), off->turn_on_way.end(), Path::kTurnFromAnyYaw), 0);
}

// Every turn made on the way (onto the translation after it or before it,
// or a lead-in from any yaw) keeps the rectangle off the walls, from starts
// all over the first room in four yaws to goals in both rooms.
TEST(FootprintSpace, TurnsOnTheWayNeverClipFromAnyStart)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  PathParams on_way;
  on_way.turn_on_the_way_deg = 150;
  std::size_t paths = 0, on_the_way = 0;
  for (const double x : {-2.2, -1.2})
    for (const double y : {-0.6, 0.6})
      for (const double yaw : {0.0, M_PI / 2, M_PI, -M_PI / 4})
      {
        const CPose2D start(x, y, yaw);
        const Planned pl = footprintSpaceOf(g, start);
        for (const Eigen::Vector2d& goal : {Eigen::Vector2d(1.6, 0.8), Eigen::Vector2d(-2.3, -0.8)})
        {
          const auto path = planFootprintPath(pl.cs, pl.fs, start, goal, yaw + 1.0, on_way);
          if (!path) continue;
          ++paths;
          on_the_way += path->turn_on_way.size() -
                        std::count(path->turn_on_way.begin(), path->turn_on_way.end(), uint8_t(0));
          expectNeverClips(g, *path);
        }
      }
  std::cout << "[ turns on the way ] " << on_the_way << " on " << paths << " paths" << std::endl;
  EXPECT_GE(paths, 24u);
  EXPECT_GE(on_the_way, paths);
}

// A turn of a bin or two at a passage's mouth, which the turn layer holds
// neither all along the way into the door nor along the way before it, is
// made on the part of the way in where it does (partial turns): the robot
// no longer stops at the mouth to turn in place. No yaw on the way clips.
TEST(FootprintSpace, ATurnAtAPassagesMouthIsMadeOnPartOfTheWayIn)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  PathParams on_way;
  on_way.turn_on_the_way_deg = 150;
  PathParams in_place;
  in_place.turn_on_the_way_deg = 0;
  // Turns in place with the rectangle's centre at the door's mouth, in the
  // first room (within 0.6 m of the wall).
  const auto turnsAtTheDoor = [](const Path& p)
  {
    std::size_t n = 0;
    for (std::size_t k = 1; k < p.waypoints.size(); ++k)
      n += (p.waypoints[k] - p.waypoints[k - 1]).norm() < 1e-9 && p.yaws[k] != p.yaws[k - 1] &&
           p.waypoints[k].x() > -0.6 && p.waypoints[k].x() < 0.0;
    return n;
  };
  std::size_t split = 0;
  for (const double y : {-0.6, 0.6})
    for (const double yaw : {0.0, M_PI / 2, M_PI})
    {
      const CPose2D start(-1.2, y, yaw);
      const Planned pl = footprintSpaceOf(g, start);
      const auto before = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.8}, yaw + 1.0, in_place);
      const auto path = planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.8}, yaw + 1.0, on_way);
      ASSERT_TRUE(before && path);
      EXPECT_GE(turnsAtTheDoor(*before), 1u) << "start " << y << ", " << yaw;
      EXPECT_EQ(turnsAtTheDoor(*path), 0u) << "start " << y << ", " << yaw;
      expectNeverClips(g, *path);
      // The way into the door: held first, turned on the rest of it.
      for (std::size_t k = 2; k < path->waypoints.size(); ++k)
      {
        const Eigen::Vector2d a = path->waypoints[k - 1] - path->waypoints[k - 2],
                              b = path->waypoints[k] - path->waypoints[k - 1];
        if (path->turn_on_way[k] == Path::kTurnFromPrevious && path->turn_on_way[k - 1] == 0 &&
            a.norm() > 1e-9 && b.norm() > 1e-9 && std::abs(a.x() * b.y() - a.y() * b.x()) < 1e-9 &&
            path->narrow[k - 1] && path->narrow[k] && path->yaws[k - 1] == path->yaws[k - 2] &&
            path->waypoints[k].x() < 0.1)
          ++split;
      }
    }
  EXPECT_GE(split, 6u);
}

// A robot standing before a door in a yaw off the door's (after a circle
// drive, or where a plan starts) turns on the first part of its way through
// it (turnFirstSplit, issue 15) where the turn layer holds the turn there
// and the translation layer the door's yaw on: no turn in place, and no yaw
// on the way clips. Next to the jamb no piece holds it: none is offered.
TEST(FootprintSpace, ARobotBeforeADoorInAnotherYawTurnsOnTheFirstPartOfItsWay)
{
  GroundGrid g = twoRoomsWithADoor(0.90);
  const Eigen::Vector2d through(1.2, 0.0);
  std::size_t turned = 0;
  for (const double x : {-1.3, -1.1, -0.95})
    for (const double deg : {-40.0, -20.0, -8.0, 8.0, 20.0, 40.0})
    {
      const CPose2D start(x, 0.0, mrpt::DEG2RAD(deg));
      const Planned pl = footprintSpaceOf(g, start);
      const Eigen::Vector2d from(x, 0.0);
      const auto s = turnFirstSplit(pl.cs, pl.fs, from, through, start.phi(), 0.0);
      if (!s) continue;
      ++turned;
      // On the way from `from`, at most half of it, the longest piece first.
      const double d = (*s - from).norm();
      EXPECT_LE(d, 0.5 * (through - from).norm() + 1e-9);
      EXPECT_NEAR((*s - from).normalized().dot((through - from).normalized()), 1.0, 1e-9);
      Path p;
      p.waypoints = {from, *s, through};
      p.yaws = {start.phi(), 0.0, 0.0};
      p.narrow = {1, 1, 1};
      p.turn_on_way = {0, Path::kTurnFromPrevious, 0};
      expectNeverClips(g, p);
    }
  std::cout << "[ turn first ] " << turned << " of 18 starts turn on their way" << std::endl;
  EXPECT_GE(turned, 12u);
  // The rectangle's nose a few centimetres off the wall, 20 deg off the
  // door's yaw: no piece of the way in holds the turn.
  const CPose2D jammed(-0.75, 0.0, mrpt::DEG2RAD(20.0));
  ASSERT_FALSE(clipsAWall(g, jammed));
  const Planned pl = footprintSpaceOf(g, jammed);
  EXPECT_FALSE(turnFirstSplit(pl.cs, pl.fs, {-0.75, 0.0}, through, jammed.phi(), 0.0));
}

TEST(FootprintSpace, ASeventyCentimetreDoorIsRefused)
{
  GroundGrid g = twoRoomsWithADoor(0.70);
  const CPose2D start(-1.5, 0.0, 0.0);
  const Planned pl = footprintSpaceOf(g, start);
  EXPECT_TRUE(reachedAt(pl, -1.0, 0.0));
  for (double x = 0.15; x < 3.0; x += 0.05)
    for (double y = -1.4; y < 1.4; y += 0.05) ASSERT_FALSE(reachedAt(pl, x, y)) << x << ", " << y;
  EXPECT_FALSE(planFootprintPath(pl.cs, pl.fs, start, {1.6, 0.0}, 0.0, PathParams{}));
  // The far room's cells are not Free for the planner either.
  Cell c;
  ASSERT_TRUE(cellOf(pl.cs.state, Eigen::Vector2d(1.6, 0.0), c));
  EXPECT_NE(*pl.cs.state.cellByIndex(c.cx, c.cy), SpaceState::Free);
}

TEST(FootprintSpace, AClearBinKeepsTheMarginFromEveryWallSquareAtEveryYawOfTheBin)
{
  // Walls and pillars at random; every (cell, bin) said clear is checked at
  // 9 yaws of the bin with the rectangle grown by the margin.
  GroundGrid g = makeGround(-2.0, 2.0, -2.0, 2.0, kRes, GroundState::Free);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.9, 1.9);
  for (int k = 0; k < 12; ++k)
  {
    const double x = u(rng), y = u(rng);
    paint(g, x, x + 0.1, y, y + 0.15, GroundState::Occupied);
  }
  const CPose2D robot(0, 0, 0);
  paint(g, -0.05, 0.05, -0.05, 0.05, GroundState::Free);
  const Planned pl = footprintSpaceOf(g, robot, omniRobWholeBin());
  const CollisionParams p = omniRobWholeBin();
  int checked = 0, clear_states = 0;
  for (int cy = 0; cy < static_cast<int>(g.state.getSizeY()); cy += 3)
    for (int cx = 0; cx < static_cast<int>(g.state.getSizeX()); cx += 3)
    {
      const YawMask m = *pl.fs.clear_occ.cellByIndex(cx, cy);
      for (int b = 0; b < pl.fs.bins; b += 3)
      {
        if (!((m >> b) & 1u)) continue;
        ++clear_states;
        for (int i = -4; i <= 4; ++i)
        {
          const double yaw = pl.fs.binYaw(b) + i / 8.0 * pl.fs.binWidth();
          const CPose2D pose(g.state.idx2x(cx), g.state.idx2y(cy), yaw);
          ASSERT_FALSE(clipsAWall(g, pose, 0.5 * kLength + p.marginInForce(kRes),
                                  0.5 * kWidth + p.marginInForce(kRes)))
              << "cell (" << cx << ", " << cy << ") bin " << b << " yaw " << yaw;
          ++checked;
        }
      }
    }
  EXPECT_GT(clear_states, 100);
  EXPECT_GT(checked, 900);
}

TEST(FootprintSpace, ABinIsBlockedExactlyWhenTheRectangleAtAYawOfTheBinComesNearAWall)
{
  // A wall of squares along y = 1 (cells y in [1, 1.1)); the robot centre at
  // x = 0.025 and y below it, bin 0 (yaws within +-delta/2 of 0). The squares
  // are tested as the rectangle grown by the margin plus their support
  // h (|cos| + |sin|) at the bin's worst yaw: the bin is blocked exactly when
  // that rectangle's top corner, tilted by delta/2, reaches the squares' centres.
  GroundGrid g = makeGround(-2.0, 2.0, -1.0, 1.5, kRes, GroundState::Free);
  paint(g, -2.0, 2.0, 1.0, 1.1, GroundState::Occupied);
  const CPose2D robot(0.025, 0.025, 0);
  const Planned pl = footprintSpaceOf(g, robot, omniRobWholeBin());
  const CollisionParams p = omniRobWholeBin();
  const double half = 0.5 * pl.fs.binWidth();
  const double support = 0.5 * kRes * (std::cos(half) + std::sin(half));
  const double a = 0.5 * kLength + p.marginInForce(kRes) + support;
  const double b = 0.5 * kWidth + p.marginInForce(kRes) + support;
  const double reach_up = a * std::sin(half) + b * std::cos(half);
  int clear = 0, blocked = 0;
  const int cx = g.state.x2idx(0.025);
  for (int cy = 0; cy < static_cast<int>(g.state.getSizeY()); ++cy)
  {
    const double y = g.state.idx2y(cy);
    if (y >= 1.0) break;
    const bool clear0 = *pl.fs.clear_occ.cellByIndex(cx, cy) & 1u;
    const double d = 1.025 - y;  // to the squares' centres
    // The squares' centres are 5 cm apart along the wall: the corner may fall
    // between two of them (lower by at most 2.5 cm * sin(delta/2)).
    if (d > reach_up + 1e-6)
    {
      EXPECT_TRUE(clear0) << "y " << y;
    }
    if (d < reach_up - 0.025 * std::sin(half) - 1e-6)
    {
      EXPECT_FALSE(clear0) << "y " << y;
    }
    (clear0 ? clear : blocked)++;
  }
  EXPECT_GT(clear, 5);
  EXPECT_GT(blocked, 5);
}

TEST(FootprintSpace, ACorridorCornerNarrowerThanTheDiagonalIsRefusedOrTurnedWithoutClipping)
{
  // An L of corridors: along x at y in [-w/2, w/2), then along y at x in [-w/2, w/2).
  for (const double w : {0.80, 0.95, 1.10, 1.25})
  {
    SCOPED_TRACE("corridor width " + std::to_string(w));
    GroundGrid g = makeGround(-4.2, 1.0, -1.0, 4.2, kRes, GroundState::Occupied);
    paint(g, -4.0, 0.5 * w, -0.5 * w, 0.5 * w, GroundState::Free);
    paint(g, -0.5 * w, 0.5 * w, -0.5 * w, 4.0, GroundState::Free);
    const CPose2D start(-3.0, 0.0, 0.0);
    const Planned pl = footprintSpaceOf(g, start);
    const auto path = planFootprintPath(pl.cs, pl.fs, start, {0.0, 3.0}, M_PI / 2, PathParams{});
    if (w < 0.85)  // the 1.2 x 0.712 rectangle cannot round a 0.80 m corner
    {
      EXPECT_FALSE(path);
    }
    if (w > 1.2)  // turned within the corner, in place (5 cm turn margin) and lengthwise moves
    {
      EXPECT_TRUE(path);
    }
    if (path) expectNeverClips(g, *path);
  }
}

TEST(FootprintSpace, TheRobotStartingWithUnknownRoundItEscapesToTheKnownFloor)
{
  // The cameras leave unknown round the body at first: the start is not
  // clear of open unknown, the rest of the room is.
  GroundGrid g = makeGround(-3.0, 3.0, -2.0, 2.0, kRes, GroundState::Occupied);
  paint(g, -2.8, 2.8, -1.8, 1.8, GroundState::Free);
  paint(g, -0.9, 0.9, -0.6, 0.6, GroundState::Unknown);
  paint(g, -0.6, 0.6, -0.36, 0.36, GroundState::Free);  // under the body
  paint(g, 2.0, 2.8, 1.0, 1.8, GroundState::Unknown);  // unexplored beyond
  const CPose2D start(0, 0, 0);
  const Planned pl = footprintSpaceOf(g, start);
  EXPECT_TRUE(reachedAt(pl, -2.0, -1.0));
  const auto path = planFootprintPath(pl.cs, pl.fs, start, {-2.0, -1.0}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
}

TEST(FootprintSpace, ARobotWithinTheMarginOfAWallEscapesWithoutClipping)
{
  // A turn at the last target left the long side 1 cm from the wall squares
  // (the guard allows 3 cm from a sensed point; a square reaches up to a
  // cell beyond the wall's surface): the start is blocked at the margin. It
  // used to reach no state at all and end the run (b1, nbv).
  GroundGrid g = makeGround(-3.0, 3.0, -2.0, 2.0, kRes, GroundState::Occupied);
  paint(g, -2.8, 2.8, -1.5, 1.5, GroundState::Free);
  const CPose2D start(0.0, 1.5 - 0.5 * kWidth - 0.01, 0.0);
  ASSERT_FALSE(clipsAWall(g, start));
  // On whole squares without the sideways shift, as the case was found:
  // the defaults since (half squares, footprint_lateral_m) clear this start
  // outright. (The check below held vacuously until the forty-eighth
  // session: escape_margin_m was left 0 when no escape ran.)
  const Planned pl = footprintSpaceOf(g, start, omniRobWholeBin());
  const std::size_t ri = static_cast<std::size_t>(pl.fs.robot.cy) * g.state.getSizeX() + pl.fs.robot.cx;
  ASSERT_FALSE(pl.fs.clear.data()[ri] & (YawMask(1) << pl.fs.robot_bin)) << "blocked where it stands";
  EXPECT_LT(pl.fs.escape_margin_m, pl.fs.margin_m);
  EXPECT_TRUE(reachedAt(pl, 0.0, -0.5));
  const auto path = planFootprintPath(pl.cs, pl.fs, start, {0.0, -0.5}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
}

TEST(FootprintSpace, OccupiedCellsUnderTheBodyDoNotTrapTheRobot)
{
  // A registration off by decimetres put a wall end under the body: the
  // robot, standing there, contradicts those cells. Its escape ignores them
  // and keeps the margin from every other wall.
  GroundGrid real = makeGround(-3.0, 3.0, -2.0, 2.0, kRes, GroundState::Occupied);
  paint(real, -2.8, 2.8, -1.5, 1.5, GroundState::Free);
  GroundGrid g = real;
  paint(g, 0.25, 0.35, -0.4, 0.1, GroundState::Occupied);  // under the body's front half
  const CPose2D start(0.0, 0.0, 0.0);
  const Planned pl = footprintSpaceOf(g, start);
  EXPECT_TRUE(pl.fs.escape_ignored_occupied);
  EXPECT_TRUE(reachedAt(pl, -2.0, 0.5));
  const auto path = planFootprintPath(pl.cs, pl.fs, start, {-2.0, 0.5}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(real, *path);
  // A robot clear of every wall never ignores one.
  EXPECT_FALSE(footprintSpaceOf(g, CPose2D(-1.5, 0.0, 0.0)).fs.escape_ignored_occupied);
}

TEST(FootprintSpace, TheWayTheRobotCameInStaysOpen)
{
  // A 0.78 m door: the bare rectangle passes lengthwise with 3.4 cm a side,
  // but not with the margin at every yaw of a bin, so the far room is not
  // reached ...
  GroundGrid g = twoRoomsWithADoor(0.78);
  const CPose2D start(1.6, 0.0, 0.0);
  const Planned closed = footprintSpaceOf(g, start, omniRobWholeBin());
  ASSERT_FALSE(reachedAt(closed, -1.5, 0.0));
  // ... unless the robot came in through it: where the body has been it can
  // be again.
  SweptPath swept;
  for (double x = -1.5; x <= 1.6 + 1e-9; x += 0.05) swept.emplace_back(x, 0.0, 0.0);
  const Planned open = footprintSpaceOf(g, start, omniRobWholeBin(), swept);
  EXPECT_TRUE(reachedAt(open, -1.5, 0.0));
  const auto path = planFootprintPath(open.cs, open.fs, start, {-1.5, 0.0}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
  // A swept pose the map says would clip a wall by more than a cell (a pose
  // estimate off by that much) is not trusted: a 0.60 m door stays closed
  // (the body shrunk by a cell a side is 0.612 m wide; 0.70 m between the
  // squares is trusted: the squares are up to a cell wider than the wall,
  // so the door may be 0.80 m).
  GroundGrid g60 = twoRoomsWithADoor(0.60);
  const Planned refused = footprintSpaceOf(g60, start, omniRobWholeBin(), swept);
  EXPECT_FALSE(reachedAt(refused, -1.5, 0.0));
}

TEST(FootprintSpace, UnknownBesideTheSweptPathDoesNotCloseIt)
{
  // The cameras see no floor within about 1 m of the body: the corridor the
  // robot drove down is lined with open unknown within the margin.
  GroundGrid g = makeGround(-3.0, 3.0, -2.0, 2.0, kRes, GroundState::Occupied);
  paint(g, -2.8, 2.8, -1.8, 1.8, GroundState::Free);
  paint(g, -1.0, 1.0, -1.8, -0.38, GroundState::Unknown);
  paint(g, -1.0, 1.0, 0.38, 1.8, GroundState::Unknown);
  const CPose2D start(2.0, 0.0, 0.0);
  ASSERT_FALSE(reachedAt(footprintSpaceOf(g, start, omniRobWholeBin()), -2.0, 0.0));
  SweptPath swept;
  for (double x = -2.0; x <= 2.0 + 1e-9; x += 0.05) swept.emplace_back(x, 0.0, M_PI);
  const Planned pl = footprintSpaceOf(g, start, omniRobWholeBin(), swept);
  EXPECT_TRUE(reachedAt(pl, -2.0, 0.0));
}

namespace
{
/// A known room (x in [-3, 0)), a 0.9 m door at x = 0 seen a little beyond,
/// and unknown past it: the door is the frontier.
void addRoomWithADoorToUnknown(octomap::OcTree& t)
{
  voxplore::test::addRoom(t, -3.0, 0.0, -1.5, 1.5);
  voxplore::test::setColumns(t, 0.0, 0.6, -0.45, 0.45, false);  // the door, seen a little beyond
  voxplore::test::setColumns(t, 0.0, 0.6, -0.50, -0.45, true);    // its jambs
  voxplore::test::setColumns(t, 0.0, 0.6, 0.45, 0.50, true);
}

/// The omniRob's footprint model, nearest strategy, at the default stand-off.
PlannerParams omniRobNearest()
{
  PlannerParams p;
  p.collision = omniRob();
  p.projection.footprint_length_m = kLength;
  p.projection.footprint_width_m = kWidth;
  p.strategy = Strategy::NearestFrontier;
  return p;
}

/// How far the plan's target stands from the nearest of the frontier's cells [m].
double targetToFrontier(const PlanResult& r, const Frontier& f)
{
  double d = std::numeric_limits<double>::infinity();
  for (const Cell& c : f.cells)
    d = std::min(d, (cellCenter(r.space->state, c) - Eigen::Vector2d(r.target.x(), r.target.y())).norm());
  return d;
}
}  // namespace

TEST(FootprintPlanner, TheFootprintModelExploresTheRoomBehindTheDoorTheCircleCannot)
{
  // plan() with model = footprint on an OcTree: a known room, a 0.9 m door,
  // and unknown beyond it: the frontier is the door, the plan goes through it.
  octomap::OcTree t(kRes);
  addRoomWithADoorToUnknown(t);
  PlannerParams p = omniRobNearest();
  p.sampling.view_standoff_m = 0;  // the thesis' nearest target: at the frontier
  const CPose2D robot(-1.5, 0.0, M_PI / 2);
  const PlanResult r = plan(t, robot, p);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_TRUE(r.footprint);
  ASSERT_EQ(r.waypoint_yaws.size(), r.waypoints.size());
  ASSERT_EQ(r.waypoint_narrow.size(), r.waypoints.size());
  EXPECT_GT(r.target.x(), -0.7);  // at the door (its frontier), not short of it

  // With the viewing stand-off the target sees the door's frontier from
  // 1.5-2.5 m (the cameras see no floor nearer than ~0.9 m from their rim).
  PlannerParams standoff = p;
  standoff.sampling.view_standoff_m = 1.5;
  const PlanResult rs = plan(t, robot, standoff);
  ASSERT_TRUE(rs.ok()) << rs.message;
  ASSERT_TRUE(rs.frontier);
  const double nearest = targetToFrontier(rs, *rs.frontier);
  EXPECT_GE(nearest, 1.5 - kRes);
  EXPECT_LE(nearest, 2.5 + kRes);
  // Lengthwise to the door, either end first (the rectangle is planned
  // modulo a half turn; the omniRob's cameras look both ways).
  EXPECT_GT(std::abs(std::cos(rs.target.phi())), 0.5) << "lengthwise to the door";

  PlannerParams circle = p;
  circle.collision.model = CollisionParams::Model::Circle;
  const PlanResult rc = plan(t, robot, circle);
  EXPECT_FALSE(rc.ok() && rc.target.x() > -0.7) << rc.message;
}

TEST(FootprintPlanner, ANearestStandOffThatDidNotClearItsFrontierIsApproached)
{
  // b12 omniRob nearest: the view stand-off stood in the corridor and saw a
  // 0.99 m door's room at a slant, twice; the frontier was blacklisted and
  // the room never entered (coverage 0.920). A frontier planned before
  // (in `approach`) is approached as next-best-view's are: the target is its
  // nearest reachable cell, at the door.
  octomap::OcTree t(kRes);
  addRoomWithADoorToUnknown(t);
  const PlannerParams p = omniRobNearest();
  ASSERT_GT(p.sampling.view_standoff_m, 0);
  const CPose2D robot(-1.5, 0.0, M_PI / 2);
  const PlanResult viewed = plan(t, robot, p);
  ASSERT_TRUE(viewed.ok()) << viewed.message;
  ASSERT_TRUE(viewed.frontier);
  EXPECT_FALSE(viewed.approached);
  EXPECT_GE(targetToFrontier(viewed, *viewed.frontier), 1.5 - kRes) << "the stand-off";
  const PlanResult approached = plan(t, robot, p, {}, 0, {}, {}, {viewed.frontier->center});
  ASSERT_TRUE(approached.ok()) << approached.message;
  EXPECT_TRUE(approached.approached);
  EXPECT_LT(targetToFrontier(approached, *viewed.frontier), 0.6) << "at the door";
  EXPECT_GT(approached.target.x(), -0.7) << "at the door";
  // A frontier elsewhere in the approach list changes nothing.
  const PlanResult other = plan(t, robot, p, {}, 0, {}, {}, {Eigen::Vector2d(-2.5, 1.2)});
  EXPECT_FALSE(other.approached);
  EXPECT_NEAR(other.target.x(), viewed.target.x(), 1e-9);
}

TEST(FootprintSpace, ARobotBoxedInADoorOneBinOffItsWayInTurnsBackOntoIt)
{
  // b14, nbv: the robot stood in a door one bin (5.6 deg) off the last pose
  // of the way it came in, unknown a cell beyond its rectangle on both sides
  // (the cameras see no floor near the body). Its own state was clear but
  // not turnable (no turn margin), its bin ran into the unknown: 4 cells
  // reached, "no frontier". It escapes by turning back onto its way in.
  GroundGrid g = twoRoomsWithADoor(0.90);
  paint(g, -1.3, -0.65, -1.5, 1.5, GroundState::Unknown);
  paint(g, 0.75, 1.4, -1.5, 1.5, GroundState::Unknown);
  const CollisionParams p = omniRob();
  const CPose2D start(0.05, 0.0, M_PI / p.yaw_bins);
  ASSERT_FALSE(clipsAWall(g, start));
  SweptPath swept;
  for (double x = -2.0; x <= 0.05 + 1e-9; x += 0.05) swept.emplace_back(x, 0.0, 0.0);
  const Planned pl = footprintSpaceOf(g, start, p, swept);
  const std::size_t ri = pl.fs.robot.cx + pl.fs.robot.cy * pl.fs.clear.getSizeX();
  const YawMask own = YawMask(1) << pl.fs.robot_bin;
  ASSERT_TRUE(pl.fs.clear.data()[ri] & own);        // clear where it stands ...
  ASSERT_FALSE(pl.fs.clear_turn.data()[ri] & own);  // ... but not turnable
  EXPECT_TRUE(pl.fs.escape_boxed_in);
  EXPECT_TRUE(reachedAt(pl, -2.0, 0.0));
  const auto path = planFootprintPath(pl.cs, pl.fs, start, {-2.0, 0.0}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
  // A robot that can turn where it stands is not boxed in.
  EXPECT_FALSE(footprintSpaceOf(g, CPose2D(-2.0, 0.0, M_PI / p.yaw_bins), p, swept).fs.escape_boxed_in);
}

TEST(FootprintSpace, TheWayInStaysOpenWhereTheBodysEndWasInTheDoor)
{
  // b18, nearest: the robot drove through a 0.80 m door (between the wall
  // squares; a 0.15 m wall) squarely at a bin's centre yaw, its estimate
  // 7.5 cm off the door's middle (the bare body 3.1 cm into a post's
  // squares: they are up to a cell wider than the wall). Tested at every
  // yaw of the bin, the corners of the body shrunk by a cell swung 3 cm
  // into the post where the body's end was in the door, the way back was
  // closed, and the run ended at 0.088.
  GroundGrid g = makeGround(-3.2, 3.4, -1.7, 1.7, kRes, GroundState::Occupied);
  paint(g, -3.0, 3.2, -1.5, 1.5, GroundState::Free);
  paint(g, 0.0, 0.15, -1.5, -0.40, GroundState::Occupied);
  paint(g, 0.0, 0.15, 0.40, 1.5, GroundState::Occupied);
  // Unknown beyond a metre of the wall on the far side: the body's own bin
  // is all that leads back.
  paint(g, -3.0, -0.9, -1.5, 1.5, GroundState::Unknown);
  const CPose2D start(1.8, 0.0, 0.0);
  SweptPath swept;
  for (double x = -0.8; x <= 1.8 + 1e-9; x += 0.05) swept.emplace_back(x, 0.075, 0.0);
  const Planned pl = footprintSpaceOf(g, start, omniRob(), swept);
  EXPECT_TRUE(reachedAt(pl, -0.6, 0.075));
  const auto path = planFootprintPath(pl.cs, pl.fs, start, {-0.6, 0.075}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  // The body shrunk by a cell never clips a wall square on the way.
  GroundGrid walls = g;
  for (auto it = walls.state.begin(); it != walls.state.end(); ++it)
    if (*it == GroundState::Unknown) *it = GroundState::Free;
  for (std::size_t k = 0; k + 1 < path->waypoints.size(); ++k)
    for (int i = 0; i <= 20; ++i)
    {
      const Eigen::Vector2d q = path->waypoints[k] + (path->waypoints[k + 1] - path->waypoints[k]) * (i / 20.0);
      ASSERT_FALSE(clipsAWall(walls, CPose2D(q.x(), q.y(), path->yaws[k + 1]), kLength / 2 - kRes,
                              kWidth / 2 - kRes));
    }
}

TEST(FootprintSpace, TheWayInStaysOpenWhereTheRobotDroveAtAYawOffItsBinsCentre)
{
  // b18, nbv: the robot drove through a door at 99.8 deg, in the bin whose
  // centre is 101.25 deg. Tested only at the bin's centre, the body shrunk
  // by a cell overlapped a post's squares where the robot had really
  // passed, the chain of swept states broke in the door, and the run ended
  // in the first room at 0.076. Here: 16 bins (11.25 deg), a 0.80 m door
  // between the squares, the robot driving along its own axis at 5 deg (bin
  // 0, centre 0 deg), its lower side 3.5 cm above the lower post.
  GroundGrid g = makeGround(-3.2, 3.4, -1.7, 1.7, kRes, GroundState::Occupied);
  paint(g, -3.0, 3.2, -1.5, 1.5, GroundState::Free);
  paint(g, 0.0, 0.15, -1.5, -0.40, GroundState::Occupied);
  paint(g, 0.0, 0.15, 0.40, 1.5, GroundState::Occupied);
  paint(g, -3.0, -0.9, -1.5, 1.5, GroundState::Unknown);  // only the swept bins lead back
  CollisionParams p = omniRob();
  p.yaw_bins = 16;
  const double yaw = 5.0 * M_PI / 180, y0 = -0.065;
  SweptPath swept;
  for (double x = -0.8; x <= 1.8 + 1e-9; x += 0.05) swept.emplace_back(x, y0 + x * std::tan(yaw), yaw);
  // The precondition: at some swept cell the shrunk body at the bin's
  // centre yaw (0) clips a post's square, at the yaw driven it clips none.
  GroundGrid walls = g;
  for (auto it = walls.state.begin(); it != walls.state.end(); ++it)
    if (*it == GroundState::Unknown) *it = GroundState::Free;
  bool centre_clips = false;
  for (const auto& q : swept)
  {
    Cell c;
    ASSERT_TRUE(cellOf(g.state, Eigen::Vector2d(q.x(), q.y()), c));
    const double cx = g.state.idx2x(c.cx), cy = g.state.idx2y(c.cy);
    ASSERT_FALSE(clipsAWall(walls, CPose2D(cx, cy, yaw), kLength / 2 - kRes, kWidth / 2 - kRes));
    centre_clips = centre_clips ||
                   clipsAWall(walls, CPose2D(cx, cy, 0.0), kLength / 2 - kRes, kWidth / 2 - kRes);
  }
  ASSERT_TRUE(centre_clips);
  const CPose2D start(1.8, y0 + 1.8 * std::tan(yaw), yaw);
  const Planned pl = footprintSpaceOf(g, start, p, swept);
  EXPECT_TRUE(reachedAt(pl, -0.6, y0 - 0.6 * std::tan(yaw)));
}

namespace
{
/// A ground grid crop written from a real run (tests/data/*.txt: a comment
/// line, "grid NX NY RES X0 Y0", "robot X Y YAW", NY rows of NX chars from
/// the top, '.' free, 'O' occupied, 'U' unknown, then "sw X Y YAW" lines).
struct GroundFixture
{
  GroundGrid g;
  CPose2D robot;
  SweptPath swept;
};

GroundFixture loadGroundFixture(const std::string& path)
{
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open fixture '" + path + "'");
  std::string line, tag;
  std::getline(in, line);  // comment
  int nx = 0, ny = 0;
  double res = 0, x0 = 0, y0 = 0, x = 0, y = 0, yaw = 0;
  in >> tag >> nx >> ny >> res >> x0 >> y0;
  if (tag != "grid") throw std::runtime_error("fixture '" + path + "': 'grid' expected");
  GroundFixture f;
  f.g = makeGround(x0, x0 + nx * res, y0, y0 + ny * res, res, GroundState::Unknown);
  in >> tag >> x >> y >> yaw;
  f.robot = CPose2D(x, y, yaw);
  for (int row = 0; row < ny; ++row)
  {
    in >> line;
    if (static_cast<int>(line.size()) != nx) throw std::runtime_error("fixture '" + path + "': short row");
    for (int cx = 0; cx < nx; ++cx)
      *f.g.state.cellByIndex(cx, ny - 1 - row) = line[cx] == '.'   ? GroundState::Free
                                                 : line[cx] == 'O' ? GroundState::Occupied
                                                                   : GroundState::Unknown;
  }
  while (in >> tag >> x >> y >> yaw) f.swept.emplace_back(x, y, yaw);
  return f;
}
}  // namespace

TEST(FootprintSpace, ARobotThatReversedIntoADoorEscapesBothWays)
{
  // b11, omniRob, nearest (a real map): the robot reversed into a door
  // (yaw -91 deg) and its last stop lay 3.5 cm past the swept path's last
  // state, in open unknown's margin. Its own bin was not clear; the escape
  // stopped at the first clear state, a bin that led a few cells into the
  // room ahead and no further (not turnable), and the way back down the
  // swept path was never tried: 3 cells reached, 'all frontiers skipped'
  // at 0.71. The escape now goes on to turnable states.
  GroundFixture f = loadGroundFixture(voxplore::test::sourceDir() +
                                      "/tests/data/footprint_b11_reversed_into_door.txt");
  ASSERT_GT(f.swept.size(), 50u);
  const Planned pl = footprintSpaceOf(f.g, f.robot, omniRobWholeBin(), f.swept);
  // The precondition: the start was not clear in its own bin.
  const std::size_t ri = static_cast<std::size_t>(pl.fs.robot.cy) * f.g.state.getSizeX() + pl.fs.robot.cx;
  ASSERT_FALSE(pl.fs.clear.data()[ri] & (YawMask(1) << pl.fs.robot_bin));
  // The corridor it came from (its middle, 1 m behind it; 2 m along it
  // either way) and the room ahead.
  EXPECT_TRUE(reachedAt(pl, f.robot.x(), f.robot.y() - 1.0));
  EXPECT_TRUE(reachedAt(pl, f.robot.x() - 2.0, f.robot.y() - 1.0));
  EXPECT_TRUE(reachedAt(pl, f.robot.x() + 2.0, f.robot.y() - 1.0));
  EXPECT_TRUE(reachedAt(pl, f.robot.x(), f.robot.y() + 1.0));
}

TEST(FootprintSpace, ABinSpanOfZeroKeepsTheMarginAtTheBinsCentreYawOnly)
{
  // 16 bins of 11.25 deg and a 0.85 m door between the wall squares (17
  // cells, a cell centre in its middle): lengthwise at the bin's centre yaw
  // (0 deg) the rectangle (0.712 m) has 6.9 cm a side, 4.9 cm past its 2 cm
  // margin; over the whole bin the 1.2 m body's corners swing 5.9 cm.
  // footprint_bin_span = 1 closes the door, 0 opens it.
  // Turning in place keeps the turn margin over the whole bin either way.
  GroundGrid g = makeGround(-3.2, 3.3, -1.7, 1.7, kRes, GroundState::Occupied);
  paint(g, -3.0, 3.1, -1.5, 1.5, GroundState::Free);
  paint(g, 0.0, 0.1, -1.5, -0.45, GroundState::Occupied);  // squares up to y = -0.45
  paint(g, 0.0, 0.1, 0.40, 1.5, GroundState::Occupied);    // ... from y = 0.40
  const CPose2D start(1.6, -0.025, 0.0);
  CollisionParams p = omniRobWholeSquares();
  p.yaw_bins = 16;
  p.footprint_bin_span = 1.0;
  p.footprint_lateral_m = 0.0;
  EXPECT_FALSE(reachedAt(footprintSpaceOf(g, start, p), -1.5, -0.025));
  p.footprint_bin_span = 0.0;
  const Planned open = footprintSpaceOf(g, start, p);
  EXPECT_TRUE(reachedAt(open, -1.5, -0.025));
  Cell door;
  // The body's rear end in the door (where the swing counts).
  ASSERT_TRUE(cellOf(open.fs.clear, Eigen::Vector2d(0.05 + 0.55, -0.025), door));
  EXPECT_TRUE(*open.fs.clear.cellByIndex(door.cx, door.cy) & YawMask(1));
  EXPECT_FALSE(*open.fs.clear_turn.cellByIndex(door.cx, door.cy) & YawMask(1));
  const auto path = planFootprintPath(open.cs, open.fs, start, {-1.5, -0.025}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
}

TEST(FootprintSpace, ADoorWhoseMiddleFallsBetweenTwoCellCentresIsPassedMovedSideways)
{
  // b1, omniRob, nbv (a real map): a 0.90 m door mapped 0.80 m wide (a jamb
  // face 4 mm from a cell border, its noisy points in the next cell), its
  // middle on a cell border. At both cell centres beside the middle the
  // rectangle (0.712 m, 2 cm margin) has 37.5 cm on one side, 1 mm short:
  // the room behind stayed shut. Moved 2.5 cm sideways it has 4 cm a side
  // to spare over the margin: footprint_lateral_m opens it; turning stays
  // at the cell centre.
  GroundGrid g = makeGround(-3.2, 3.3, -1.7, 1.7, kRes, GroundState::Occupied);
  paint(g, -3.0, 3.1, -1.5, 1.5, GroundState::Free);
  paint(g, 0.0, 0.1, -1.5, -0.40, GroundState::Occupied);  // squares up to y = -0.40
  paint(g, 0.0, 0.1, 0.40, 1.5, GroundState::Occupied);    // ... from y = 0.40
  const CPose2D start(1.6, 0.025, 0.0);
  CollisionParams p = omniRobWholeSquares();
  p.yaw_bins = 16;
  p.footprint_bin_span = 0.0;
  p.footprint_lateral_m = 0.0;
  EXPECT_FALSE(reachedAt(footprintSpaceOf(g, start, p), -1.5, 0.025));
  p.footprint_lateral_m = 0.025;
  const Planned open = footprintSpaceOf(g, start, p);
  EXPECT_TRUE(reachedAt(open, -1.5, 0.025));
  EXPECT_TRUE(reachedAt(open, -1.5, -0.025));
  // In the door: the bin along the wall's normal (and, through a wall this
  // thin, its neighbours), never turnable.
  Cell door;
  ASSERT_TRUE(cellOf(open.fs.clear, Eigen::Vector2d(0.05, 0.025), door));
  EXPECT_TRUE(*open.fs.clear.cellByIndex(door.cx, door.cy) & YawMask(1));
  EXPECT_EQ(*open.fs.clear_turn.cellByIndex(door.cx, door.cy), YawMask(0));
  // A cell more off the middle is not clear: the shift is at most 2.5 cm.
  ASSERT_TRUE(cellOf(open.fs.clear, Eigen::Vector2d(0.05, 0.075), door));
  EXPECT_FALSE(*open.fs.clear.cellByIndex(door.cx, door.cy) & YawMask(1));
  // Moved sideways by the shift, the body keeps the margin at every state
  // of the door (the drive's centring puts it there).
  const auto path = planFootprintPath(open.cs, open.fs, start, {-1.5, 0.025}, 0.0, PathParams{});
  ASSERT_TRUE(path);
  expectNeverClips(g, *path);
  // A door 5 cm narrower stays shut: the shift does not eat the margin.
  paint(g, 0.0, 0.1, 0.35, 0.40, GroundState::Occupied);
  EXPECT_FALSE(reachedAt(footprintSpaceOf(g, start, p), -1.5, 0.025));
}

TEST(FootprintSpace, MoreThan32BinsGiveTheClearStatesOfTheir32BinHalves)
{
  // Up to 32 bins both stamps of a pass share one 64-bit mask per cell;
  // above, they go into two layers. At their centre yaws alone
  // (footprint_bin_span 0), bin 2k of 64 is bin k of 32: both layouts must
  // give the same clear states there (occupied, open unknown, the sideways
  // move). The turn margin holds over the whole bin: a bin half as wide
  // is turnable wherever the wider one is.
  GroundGrid g = twoRoomsWithADoor(0.90);
  paint(g, 2.0, 3.1, -1.5, 1.5, GroundState::Unknown);  // unexplored floor in the right room
  const CPose2D start(1.2, 0.0, 0.0);
  CollisionParams p = omniRob();
  p.footprint_bin_span = 0.0;
  p.footprint_lateral_m = 0.025;
  p.yaw_bins = 32;
  const Planned packed = footprintSpaceOf(g, start, p);
  p.yaw_bins = 64;
  const Planned split = footprintSpaceOf(g, start, p);
  std::size_t differ_unknown = 0, differ_turn = 0;
  const auto& a = packed.fs;
  const auto& b = split.fs;
  for (std::size_t i = 0; i < a.clear.data().size(); ++i)
  {
    differ_unknown += a.clear_occ.data()[i] != a.clear.data()[i];
    differ_turn += a.clear.data()[i] != a.clear_turn.data()[i];
    for (int k = 0; k < 32; ++k)
    {
      const YawMask bit32 = YawMask(1) << k, bit64 = YawMask(1) << (2 * k);
      ASSERT_EQ((a.clear_occ.data()[i] & bit32) != 0, (b.clear_occ.data()[i] & bit64) != 0)
          << "clear_occ, cell " << i << " bin " << k;
      ASSERT_EQ((a.clear.data()[i] & bit32) != 0, (b.clear.data()[i] & bit64) != 0)
          << "clear, cell " << i << " bin " << k;
      if (a.clear_turn.data()[i] & bit32)
      {
        ASSERT_TRUE(b.clear_turn.data()[i] & bit64) << "clear_turn, cell " << i << " bin " << k;
      }
    }
  }
  // Each margin and the unknown leave their mark (else the check is empty).
  EXPECT_GT(differ_unknown, 100u);
  EXPECT_GT(differ_turn, 100u);
  EXPECT_TRUE(reachedAt(packed, -1.5, 0.0));
  EXPECT_TRUE(reachedAt(split, -1.5, 0.0));
}

TEST(FootprintSpace, HalfSquaresNarrowTranslationNotTurning)
{
  // footprint_square_share 0.5 gives translation half a cell of a door's
  // width back; turning in place keeps whole squares
  // (footprint_turn_square_share 1): with half squares for both, the plans
  // turned where the guard held the body (b3 omniRob nearest: 0.614).
  GroundGrid g = twoRoomsWithADoor(0.85);
  const CPose2D start(1.6, 0.0, 0.0);
  CollisionParams p = omniRobWholeSquares();
  const Planned whole = footprintSpaceOf(g, start, p);
  p.footprint_square_share = 0.5;
  const Planned half = footprintSpaceOf(g, start, p);
  std::size_t more_clear = 0;
  for (std::size_t i = 0; i < half.fs.clear.data().size(); ++i)
  {
    more_clear += (half.fs.clear.data()[i] & ~whole.fs.clear.data()[i]) != 0;
    ASSERT_EQ(half.fs.clear_turn.data()[i] & ~whole.fs.clear_turn.data()[i], YawMask(0))
        << "cell " << i << ": turnable with half squares only";
  }
  EXPECT_GT(more_clear, 0u);
  // Half squares for turning too, when asked for.
  p.footprint_turn_square_share = 0.5;
  const Planned both = footprintSpaceOf(g, start, p);
  std::size_t more_turnable = 0;
  for (std::size_t i = 0; i < both.fs.clear_turn.data().size(); ++i)
    more_turnable += (both.fs.clear_turn.data()[i] & ~whole.fs.clear_turn.data()[i]) != 0;
  EXPECT_GT(more_turnable, 0u);
}

namespace
{
/// The compact robot (0.50 x 0.36 m) with the footprint model at the defaults.
CollisionParams compactFootprint()
{
  CollisionParams p;
  p.model = CollisionParams::Model::Footprint;
  p.footprint_length_m = 0.50;
  p.footprint_width_m = 0.36;
  p.r_coll_m = 0.308;
  // The margin the fixtures were planned with (the twenty-sixth session's
  // "auto" gives this robot 0.05).
  p.footprint_margin_m = 0.02;
  return p;
}

/// Every `stride`-th cell (in x and y) that the reach holds in a clear bin
/// (what the planner offers as a goal) gets a path from the robot; the cells
/// that do not, at most `report` of them, as "(x, y)" in `missing`.
std::size_t goalsWithoutPath(const Planned& pl, const CPose2D& robot, int stride,
                             std::size_t& goals, std::string& missing, std::size_t report = 5)
{
  const std::vector<float> from_start = footprintCostFromStart(pl.cs, pl.fs, PathParams{});
  const int nx = static_cast<int>(pl.fs.reach.getSizeX()), ny = static_cast<int>(pl.fs.reach.getSizeY());
  std::size_t failed = 0;
  goals = 0;
  for (int cy = 0; cy < ny; cy += stride)
    for (int cx = 0; cx < nx; cx += stride)
    {
      const std::size_t i = static_cast<std::size_t>(cy) * nx + cx;
      if (!(pl.fs.reach.data()[i] & pl.fs.clear.data()[i])) continue;
      ++goals;
      const Eigen::Vector2d goal = cellCenter(pl.fs.reach, Cell{cx, cy});
      if (planFootprintPath(pl.cs, pl.fs, robot, goal, 0.0, PathParams{}, &from_start)) continue;
      if (++failed <= report)
        missing += " (" + std::to_string(goal.x()) + ", " + std::to_string(goal.y()) + ")";
    }
  return failed;
}
}  // namespace

TEST(FootprintSpace, ThePathSearchFollowsEveryStateTheReachHolds)
{
  // b3, compact robot, footprint model, nearest (a real map): the robot
  // stood pinched between furniture at yaw -41 deg, its own bin blocked.
  // The escape turned in place through two bins clear of occupied cells only
  // into clear bins that were not turnable, and went on from there; the
  // reach held most of the building. The search turns at a cell only between
  // clear_turn or escape bins, and the escape had dropped its clear ones:
  // each of 58 goals the reach held was searched for in vain (1.9 s each),
  // 'all frontiers skipped' at coverage 0.45. Whatever the reach holds in a
  // clear bin, the search must find.
  GroundFixture f = loadGroundFixture(voxplore::test::sourceDir() +
                                      "/tests/data/footprint_b3_pinched_turn.txt");
  const Planned pl = footprintSpaceOf(f.g, f.robot, compactFootprint(), f.swept);
  // The precondition: the start was not clear in its own bin.
  const std::size_t ri = static_cast<std::size_t>(pl.fs.robot.cy) * f.g.state.getSizeX() + pl.fs.robot.cx;
  ASSERT_FALSE(pl.fs.clear.data()[ri] & (YawMask(1) << pl.fs.robot_bin));
  std::size_t goals = 0;
  std::string missing;
  EXPECT_EQ(goalsWithoutPath(pl, f.robot, 15, goals, missing), 0u) << "of " << goals << ":" << missing;
  EXPECT_GT(goals, 20u) << "the crop's reach";

  // The same on the other real map (the omniRob reversed into a door, its
  // start in open unknown's margin) and on the door tests' rooms, from
  // starts that need an escape (within the margin of a wall, across the
  // door) and from one that does not.
  GroundFixture b11 = loadGroundFixture(voxplore::test::sourceDir() +
                                        "/tests/data/footprint_b11_reversed_into_door.txt");
  const Planned pl11 = footprintSpaceOf(b11.g, b11.robot, omniRobWholeBin(), b11.swept);
  EXPECT_EQ(goalsWithoutPath(pl11, b11.robot, 5, goals, missing), 0u) << "b11, of " << goals << ":" << missing;
  EXPECT_GT(goals, 40u) << "b11's reach";
  for (const CPose2D& start : {CPose2D(-1.5, 0.3, M_PI / 2), CPose2D(-0.45, 0.0, 0.3),
                               CPose2D(-2.6, 1.1, 0.0), CPose2D(1.0, -1.05, M_PI / 2)})
  {
    GroundGrid g = twoRoomsWithADoor(0.90);
    const Planned rooms = footprintSpaceOf(g, start, omniRob());
    EXPECT_EQ(goalsWithoutPath(rooms, start, 6, goals, missing), 0u)
        << "rooms from (" << start.x() << ", " << start.y() << ", " << start.phi() << "), of "
        << goals << ":" << missing;
  }
}

TEST(FootprintSpace, ARobotWedgedAtASkewInADoorStraightensAndBacksOut)
{
  // b6, omniRob, nbv (a real map, 32 bins at the defaults): the guard held
  // a drive through a 0.80 m door at a skew and the robot stood half
  // through it, 11 deg off the door's axis. Its own bin was clear and
  // turnable, so the boxed-in escape (then: "the start is not turnable and
  // no reached state is") did not run; but neither neighbour bin was
  // turnable and translation in its bin went one cell: 2 cells reached,
  // 962 m^2 of known floor cut off, "no frontier". Boxed in means no reached
  // state can turn (a turnable bin with a turnable neighbour).
  GroundFixture f = loadGroundFixture(voxplore::test::sourceDir() +
                                      "/tests/data/footprint_b6_wedged_door.txt");
  const Planned pl = footprintSpaceOf(f.g, f.robot, omniRobWholeSquares(), f.swept);
  const std::size_t nx = f.g.state.getSizeX();
  const std::size_t ri = static_cast<std::size_t>(pl.fs.robot.cy) * nx + pl.fs.robot.cx;
  const YawMask own = YawMask(1) << pl.fs.robot_bin;
  // The precondition: clear and turnable in its own bin, not in either neighbour.
  ASSERT_TRUE(pl.fs.clear.data()[ri] & own);
  ASSERT_TRUE(pl.fs.clear_turn.data()[ri] & own);
  ASSERT_FALSE(pl.fs.clear_turn.data()[ri] & pl.fs.neighbourBins(own));
  EXPECT_TRUE(pl.fs.escape_boxed_in);
  std::size_t reached = 0;
  for (const YawMask m : pl.fs.reach.data()) reached += m != 0;
  EXPECT_GT(reached, 1000u) << "cells reached (2 before the rule asked whether a state can turn)";
  // Both rooms the door joins (1.5 m either side of it, across its axis).
  EXPECT_TRUE(reachedAt(pl, f.robot.x() - 1.5, f.robot.y()));
  EXPECT_TRUE(reachedAt(pl, f.robot.x() + 1.5, f.robot.y()));
  // The start itself overlaps a jamb's square (the squares reach up to a
  // cell past the wall); every pose after it keeps off them all.
  ASSERT_TRUE(clipsAWall(f.g, f.robot));
  for (const double dx : {-1.5, 1.5})
  {
    auto path = planFootprintPath(pl.cs, pl.fs, f.robot, {f.robot.x() + dx, f.robot.y()}, 0.0,
                                  PathParams{});
    ASSERT_TRUE(path) << "to dx = " << dx;
    ASSERT_GT(path->waypoints.size(), 2u);
    path->waypoints.erase(path->waypoints.begin());
    path->yaws.erase(path->yaws.begin());
    expectNeverClips(f.g, *path);
  }
  std::size_t goals = 0;
  std::string missing;
  EXPECT_EQ(goalsWithoutPath(pl, f.robot, 7, goals, missing), 0u) << "of " << goals << ":" << missing;
}

TEST(FootprintSpace, LayersRecycledFromAnotherSpaceGiveTheSameSpaceAsFreshOnes)
{
  // The planner hands a step's layers back (recycleFootprintSpace) and the
  // next space is written into them: nothing of the old space may remain.
  GroundGrid g = twoRoomsWithADoor(0.90);
  const CPose2D start(-1.5, 0.3, M_PI / 2);
  const Planned fresh = footprintSpaceOf(g, start);
  {
    // Spares from another map of the same extent (the far room shut off,
    // another pose) and from a smaller one.
    GroundGrid other = twoRoomsWithADoor(0.70);
    Planned a = footprintSpaceOf(other, CPose2D(-1.0, -0.5, 0.3));
    GroundGrid small = makeGround(-1.0, 1.0, -1.0, 1.0, kRes, GroundState::Free);
    Planned b = footprintSpaceOf(small, CPose2D(0.0, 0.0, 0.0));
    recycleFootprintSpace(std::move(a.fs));
    recycleFootprintSpace(std::move(b.fs));
    EXPECT_EQ(a.fs.clear.getSizeX(), 0u);
    EXPECT_TRUE(a.fs.reach.data().empty());
  }
  const Planned again = footprintSpaceOf(g, start);
  const auto same = [](const Grid<YawMask>& x, const Grid<YawMask>& y)
  {
    return x.getSizeX() == y.getSizeX() && x.getSizeY() == y.getSizeY() &&
           x.getXMin() == y.getXMin() && x.getYMin() == y.getYMin() && x.data() == y.data();
  };
  EXPECT_TRUE(same(again.fs.clear_occ, fresh.fs.clear_occ));
  EXPECT_TRUE(same(again.fs.clear, fresh.fs.clear));
  EXPECT_TRUE(same(again.fs.clear_turn, fresh.fs.clear_turn));
  EXPECT_TRUE(same(again.fs.reach, fresh.fs.reach));
  EXPECT_TRUE(same(again.fs.escape, fresh.fs.escape));
}

TEST(FootprintSpace, AStartOnACellBorderStartsAtTheSpacesRobotCell)
{
  // projectToGround takes the robot's cell from its OctoMap key, and a
  // coordinate on a cell border may round the other way there than in
  // cellOf. The path from that pose starts at the space's robot cell (and so
  // shares the step's heuristic, computed from it).
  GroundGrid g = twoRoomsWithADoor(0.90);
  Cell c;
  ASSERT_TRUE(cellOf(g.state, Eigen::Vector2d(-1.5, 0.0), c));
  const Eigen::Vector2d centre = cellCenter(g.state, c);
  const CPose2D start(centre.x() + 0.5 * kRes, centre.y(), 0.0);  // on c's east border
  Cell by_cellof;
  ASSERT_TRUE(cellOf(g.state, Eigen::Vector2d(start.x(), start.y()), by_cellof));
  // The key's cell: the other side of the border.
  g.robot = by_cellof.cx == c.cx ? Cell{c.cx + 1, c.cy} : c;
  Planned pl;
  pl.cs = computeCollisionSpace(g, omniRob());
  pl.fs = computeFootprintSpace(g, pl.cs, omniRob(), start);
  applyFootprint(pl.cs, pl.fs);
  ASSERT_NE(pl.fs.robot, by_cellof);
  const Eigen::Vector2d goal(1.6, 0.0);
  const auto h = footprintCostFromStart(pl.cs, pl.fs, PathParams{});
  const auto shared = planFootprintPath(pl.cs, pl.fs, start, goal, 0.0, PathParams{}, &h);
  const auto own = planFootprintPath(pl.cs, pl.fs, start, goal, 0.0, PathParams{});
  ASSERT_TRUE(shared);
  ASSERT_TRUE(own);
  EXPECT_NEAR((shared->cells_path.front() - cellCenter(g.state, pl.fs.robot)).norm(), 0.0, 1e-9);
  EXPECT_EQ(shared->cells_path, own->cells_path);
  expectNeverClips(g, *shared);
}

TEST(FootprintSpace, ARobotBetweenTableLegsWhoseReachIsShorterThanItsBodyEscapes)
{
  // b7, compact robot, nbv, seed 2 (a real map, the defaults: "auto"
  // margin 5 cm): a drive ended with the robot between two tables' leg
  // groups. Its own state was clear, and two of the 3 cells its bin reached
  // were turnable into the next bin, so it was not "boxed in"; but nothing
  // else was reached: all 146 m^2 of known floor cut off, 'the map shut the
  // robot in' at coverage 0.40. The body passes there (the simulator's
  // clearance 2.8 cm). A reach shorter than the body is boxed in: it
  // escapes, at the margin, to turnable states it did not hold.
  GroundFixture f = loadGroundFixture(voxplore::test::sourceDir() +
                                      "/tests/data/footprint_b7_between_table_legs.txt");
  CollisionParams p = compactFootprint();
  p.footprint_margin_m = CollisionParams{}.footprint_margin_m;  // "auto", as the run had
  const Planned pl = footprintSpaceOf(f.g, f.robot, p, f.swept);
  const std::size_t nx = f.g.state.getSizeX();
  const std::size_t ri = static_cast<std::size_t>(pl.fs.robot.cy) * nx + pl.fs.robot.cx;
  ASSERT_TRUE(pl.fs.clear.data()[ri] & (YawMask(1) << pl.fs.robot_bin));  // clear where it stands
  EXPECT_TRUE(pl.fs.escape_boxed_in);
  EXPECT_EQ(pl.fs.escape_margin_m, pl.fs.margin_m);
  std::size_t reached = 0;
  for (const YawMask m : pl.fs.reach.data()) reached += m != 0;
  EXPECT_GT(reached, 2000u) << "cells reached (3 before)";
  // The open floor past the tables' ends, on either side of them.
  EXPECT_TRUE(reachedAt(pl, f.robot.x() - 1.0, f.robot.y() + 1.4));
  EXPECT_TRUE(reachedAt(pl, f.robot.x() - 1.0, f.robot.y() - 1.5));
  EXPECT_TRUE(reachedAt(pl, f.robot.x() - 1.5, f.robot.y()));
  std::size_t goals = 0;
  std::string missing;
  EXPECT_EQ(goalsWithoutPath(pl, f.robot, 7, goals, missing), 0u) << "of " << goals << ":" << missing;
  EXPECT_GT(goals, 40u);
  // A path out; the body (0.50 x 0.36 m) at its end clips no wall square.
  const auto path = planFootprintPath(pl.cs, pl.fs, f.robot, {f.robot.x() - 1.5, f.robot.y()}, 0.0,
                                      PathParams{});
  ASSERT_TRUE(path);
  const Eigen::Vector2d last = path->waypoints.back();
  EXPECT_FALSE(clipsAWall(f.g, CPose2D(last.x(), last.y(), path->yaws.back()), 0.25, 0.18));
}

// FootprintSpace::nearestReachedYaw ([sampling] rate_reached_yaw): in a
// corridor narrower than the body is long, a yaw along it is kept, a yaw
// across it becomes the nearest yaw the robot can stand at there, and a cell
// in the wall has none.
TEST(FootprintSpace, TheNearestReachedYawIsTheWantedOneWhereReachedElseTheNearestReachedBin)
{
  GroundGrid g = makeGround(-4.2, 4.2, -0.7, 0.7, kRes, GroundState::Occupied);
  paint(g, -4.0, 4.0, -0.5, 0.5, GroundState::Free);  // 1.0 m wide: the 1.2 m body stays lengthwise
  const CPose2D robot(0.0, 0.0, 0.0);
  const Planned pl = footprintSpaceOf(g, robot);
  const std::size_t nx = pl.fs.reach.getSizeX();
  Cell c;
  ASSERT_TRUE(cellOf(pl.fs.reach, Eigen::Vector2d(1.0, 0.0), c));
  const std::size_t i = static_cast<std::size_t>(c.cy) * nx + c.cx;
  const YawMask m = pl.fs.reach.data()[i];
  ASSERT_TRUE(m & 1u) << "along the corridor is reached";
  ASSERT_FALSE((m >> pl.fs.binOf(M_PI / 2)) & 1u) << "across it is not";

  const auto along = pl.fs.nearestReachedYaw(i, 0.02);
  ASSERT_TRUE(along);
  EXPECT_DOUBLE_EQ(*along, 0.02) << "a reached bin keeps the yaw asked for";
  const auto behind = pl.fs.nearestReachedYaw(i, M_PI + 0.02);
  ASSERT_TRUE(behind);
  EXPECT_DOUBLE_EQ(*behind, M_PI + 0.02) << "the half turn of a reached bin is reached";

  for (const double want : {M_PI / 2, -M_PI / 2, mrpt::DEG2RAD(60.0), mrpt::DEG2RAD(-120.0)})
  {
    const auto got = pl.fs.nearestReachedYaw(i, want);
    ASSERT_TRUE(got) << want;
    EXPECT_TRUE((m >> pl.fs.binOf(*got)) & 1u) << "reached: " << *got;
    // The nearest reached bin: no reached bin is nearer the wanted yaw.
    const double off = std::abs(mrpt::math::wrapToPi(2.0 * (*got - want))) / 2.0;
    for (int k = 0; k < pl.fs.bins; ++k)
    {
      if (!((m >> k) & 1u)) continue;
      EXPECT_LE(off, std::abs(mrpt::math::wrapToPi(2.0 * (pl.fs.binYaw(k) - want))) / 2.0 + 1e-9)
          << "bin " << k << " is nearer " << want;
    }
    // The half turn nearer the wanted yaw: within a quarter turn of it.
    EXPECT_LE(std::abs(mrpt::math::wrapToPi(*got - want)), M_PI / 2 + 1e-9)
        << want << " -> " << *got;
  }

  ASSERT_TRUE(cellOf(pl.fs.reach, Eigen::Vector2d(1.0, 0.65), c));  // in the wall
  EXPECT_FALSE(pl.fs.nearestReachedYaw(static_cast<std::size_t>(c.cy) * nx + c.cx, 0.0));
}

// [sampling] rate_reached_yaw, plan(): next-best-view samples beside a door
// in a corridor are rated, and the target is set, at yaws the omniRob's
// rectangle can stand at; facing the door (the thesis' yaw) it often cannot.
TEST(FootprintPlanner, NextBestViewSamplesAreRatedAtTheYawTheRobotWillStandAt)
{
  // A corridor 2.2 m wide along y, a 1.0 m door in its east wall to unknown.
  octomap::OcTree t(kRes);
  voxplore::test::addRoom(t, -1.1, 1.1, -4.0, 4.0);
  voxplore::test::setColumns(t, 1.1, 1.4, -0.5, 0.5, false);  // the door, seen a little beyond
  voxplore::test::setColumns(t, 1.1, 1.4, -0.55, -0.5, true);  // its jambs
  voxplore::test::setColumns(t, 1.1, 1.4, 0.5, 0.55, true);
  PlannerParams p = omniRobNearest();
  p.strategy = Strategy::NextBestView;
  p.sampling.max_samples = 40;
  const CPose2D robot(0.0, -2.5, M_PI / 2);

  const auto unreachedYaws = [](const PlanResult& r)
  {
    std::size_t n = 0;
    const std::size_t nx = r.footprint->reach.getSizeX();
    for (const CPose2D& s : r.samples)
    {
      Cell c;
      if (!cellOf(r.footprint->reach, Eigen::Vector2d(s.x(), s.y()), c)) return std::size_t(1000);
      const YawMask m = r.footprint->reach.data()[static_cast<std::size_t>(c.cy) * nx + c.cx];
      n += !((m >> r.footprint->binOf(s.phi())) & 1u);
    }
    return n;
  };

  p.sampling.rate_reached_yaw = false;
  const PlanResult facing = plan(t, robot, p);
  ASSERT_TRUE(facing.ok()) << facing.message;
  ASSERT_TRUE(facing.footprint);
  ASSERT_GE(facing.samples.size(), 10u);
  EXPECT_GT(unreachedYaws(facing), 0u) << "facing the door is a yaw some samples cannot stand at";

  p.sampling.rate_reached_yaw = true;
  const PlanResult stood = plan(t, robot, p);
  ASSERT_TRUE(stood.ok()) << stood.message;
  ASSERT_TRUE(stood.footprint);
  ASSERT_EQ(stood.samples.size(), facing.samples.size()) << "the same cells";
  EXPECT_EQ(unreachedYaws(stood), 0u);
  // The target stands at the yaw its sample was rated at.
  const auto at_target = [&](const CPose2D& s)
  { return std::hypot(s.x() - stood.target.x(), s.y() - stood.target.y()) < 1e-9; };
  const auto rated = std::find_if(stood.samples.begin(), stood.samples.end(), at_target);
  ASSERT_NE(rated, stood.samples.end());
  EXPECT_NEAR(std::abs(mrpt::math::wrapToPi(2.0 * (rated->phi() - stood.target.phi()))) / 2.0, 0.0,
              stood.footprint->binWidth() / 2 + 1e-9);
}
