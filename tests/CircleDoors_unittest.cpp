// The thesis' circle model at ordinary doors (issue 12, compact robot): a
// frontier judged by the opening it faces, not by the 2-4 cells the circle
// reaches in a 0.9 m door, and a door the robot has driven through kept
// open when the map's unknown jambs close it to the thesis' reachability.
#include <gtest/gtest.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "exploration_test_maps.h"

using namespace voxplore::exploration;
using namespace voxplore::test;

namespace
{
constexpr double kRes = 0.05;
constexpr double kCompactRcoll = 0.311;  // the compact robot's circumradius [m]

CollisionParams compact()
{
  CollisionParams p;
  p.r_coll_m = kCompactRcoll;
  p.model = CollisionParams::Model::Circle;
  return p;
}

/// A known room [0, 6) x [0, 4) (the robot in it) with a door of
/// `door_m` in its north wall (y in [4, 4.15)) centred on x = 3, and
/// beyond it a room [1, 5) x [4.15, 8) that is `far` (Free: seen, Unknown:
/// not yet).
GroundGrid roomWithDoor(double door_m, GroundState far)
{
  GroundGrid g = makeGround(-0.5, 6.5, -0.5, 8.5, kRes, GroundState::Occupied);
  paint(g, 0.0, 6.0, 0.0, 4.0, GroundState::Free);
  paint(g, 3.0 - door_m / 2, 3.0 + door_m / 2, 4.0, 4.15, GroundState::Free);
  paint(g, 1.0, 5.0, 4.15, 8.0, far);
  g.robot = {g.state.x2idx(3.0), g.state.y2idx(2.0)};
  return g;
}

SpaceState stateAt(const CollisionSpace& cs, double x, double y)
{
  return *cs.state.cellByIndex(cs.state.x2idx(x), cs.state.y2idx(y));
}
}  // namespace

TEST(CircleDoors, AFrontierInADoorIsJudgedByTheDoorsWidth)
{
  const GroundGrid g = roomWithDoor(0.9, GroundState::Unknown);
  const CollisionSpace cs = computeCollisionSpace(g, compact());
  const FrontierMap fm = findFrontiers(g, cs);
  ASSERT_EQ(fm.frontiers.size(), 1u);
  const Frontier& f = fm.frontiers[0];
  // The circle reaches a sliver of the door: below th_f2, so the thesis
  // calls the building explored ...
  EXPECT_LE(f.size_m, 0.25);
  SamplingParams p;
  EXPECT_FALSE(chooseFrontier(fm.frontiers, p, {}).has_value());
  // ... the opening it faces is the door.
  EXPECT_NEAR(f.opening_m, 0.9, 0.15);
  p.judge_opening = true;
  EXPECT_EQ(chooseFrontier(fm.frontiers, p, {}), std::optional<std::size_t>(0));
}

TEST(CircleDoors, AnOpeningIsCountedOnceForTheFrontierNearestToIt)
{
  // Two doors 2 m apart: each frontier gets its own door, not both.
  GroundGrid g = roomWithDoor(0.9, GroundState::Unknown);
  paint(g, 0.55, 1.45, 4.0, 4.15, GroundState::Free);
  paint(g, 0.0, 1.0, 4.15, 8.0, GroundState::Unknown);
  const CollisionSpace cs = computeCollisionSpace(g, compact());
  const FrontierMap fm = findFrontiers(g, cs);
  ASSERT_EQ(fm.frontiers.size(), 2u);
  for (const Frontier& f : fm.frontiers) EXPECT_NEAR(f.opening_m, 0.9, 0.15);
}

TEST(CircleDoors, ADoorTheRobotWentThroughStaysOpenWhenItsJambsAreUnknown)
{
  // A 0.7 m door in a 0.3 m wall mapped as unknown (a double wall after
  // drift: deeper than min_open_unknown_depth, so open unknown): the door is
  // MaybeCollision from jamb to jamb, and the thesis' reachability (Free
  // cells, one band into MaybeCollision) stops in it.
  GroundGrid g = roomWithDoor(0.0, GroundState::Free);
  paint(g, 0.0, 6.0, 4.0, 4.3, GroundState::Unknown);
  paint(g, 1.0, 5.0, 4.3, 8.0, GroundState::Free);
  paint(g, 2.65, 3.35, 4.0, 4.3, GroundState::Free);
  CollisionParams p = compact();
  CollisionSpace cs = computeCollisionSpace(g, p);
  ASSERT_EQ(stateAt(cs, 3.0, 4.17), SpaceState::MaybeCollision);
  const auto reachedBeyond = [&](const CollisionSpace& space)
  { return *findFrontiers(g, space).distance_m.cellByIndex(g.state.x2idx(3.0), g.state.y2idx(6.0)) >= 0; };
  ASSERT_FALSE(reachedBeyond(cs));
  // The robot drove in through the door's middle.
  SweptPath swept;
  for (double y = 6.0; y >= 2.0; y -= 0.03) swept.emplace_back(3.0 + 0.01, y, -M_PI / 2);
  p.swept_passage = true;
  EXPECT_GT(openSweptPassages(cs, swept, p), 0u);
  EXPECT_EQ(stateAt(cs, 3.0, 4.17), SpaceState::Free);
  EXPECT_TRUE(reachedBeyond(cs));
  // Only the cells round the swept line open: the door's side cells stay.
  EXPECT_EQ(stateAt(cs, 3.0 + 0.2, 4.17), SpaceState::MaybeCollision);
}

TEST(CircleDoors, ASweptPathNearerAnObstacleThanTheBodyAndMarginOpensNothing)
{
  // The robot's recorded path 0.2 m from a wall (a map shifted after it
  // drove there): closer than r_coll + margin, nothing opens.
  const GroundGrid g = roomWithDoor(0.9, GroundState::Free);
  CollisionParams p = compact();
  p.swept_passage = true;
  CollisionSpace cs = computeCollisionSpace(g, p);
  SweptPath swept;
  for (double x = 1.0; x <= 5.0; x += 0.03) swept.emplace_back(x, 0.2, 0.0);
  EXPECT_EQ(openSweptPassages(cs, swept, p), 0u);
  // Nor through a door of occupied jambs narrower than the body and margin
  // (0.6 m: 0.325 m from its middle to the jambs' cell centres).
  const GroundGrid narrow = roomWithDoor(0.6, GroundState::Free);
  CollisionSpace cn = computeCollisionSpace(narrow, p);
  SweptPath through;
  for (double y = 2.0; y <= 6.0; y += 0.03) through.emplace_back(3.0, y, M_PI / 2);
  EXPECT_EQ(openSweptPassages(cn, through, p), 0u);
  EXPECT_EQ(stateAt(cn, 3.0, 4.07), SpaceState::Collision);
}

TEST(CircleDoors, TheFloorBeyondADoorTheCircleCannotPassIsReportedCutOff)
{
  // Beyond the door a known room [1, 5) x [4.15, 8): 15.4 m^2.
  const CollisionParams p = compact();
  const GroundGrid open = roomWithDoor(0.9, GroundState::Free);
  const CollisionSpace cs_open = computeCollisionSpace(open, p);
  EXPECT_LT(cutOffFloorM2(open, cs_open, findFrontiers(open, cs_open)), 0.5);
  const GroundGrid shut = roomWithDoor(0.6, GroundState::Free);
  const CollisionSpace cs_shut = computeCollisionSpace(shut, p);
  const double cut = cutOffFloorM2(shut, cs_shut, findFrontiers(shut, cs_shut));
  // The far room (15.4 m^2) and the door's own cells (0.09 m^2): the
  // nearest reachable centre stays more than r + l_res short of them.
  EXPECT_NEAR(cut, 15.4 + 0.09, 0.1);
}

TEST(CircleDoors, AFrontierIsJudgedByTheOpenUnknownItBorders)
{
  // The door to an unseen room faces the room's 4 x 3.85 m of open unknown;
  // a 0.5 m square the cameras never saw in the known room (under a table)
  // is a closed pocket of 0.25 m^2.
  GroundGrid g = roomWithDoor(0.9, GroundState::Unknown);
  paint(g, 0.5, 1.0, 1.0, 1.5, GroundState::Unknown);
  const CollisionSpace cs = computeCollisionSpace(g, compact());
  const FrontierMap fm = findFrontiers(g, cs);
  ASSERT_EQ(fm.frontiers.size(), 2u);
  const auto door = std::find_if(fm.frontiers.begin(), fm.frontiers.end(),
                                 [](const Frontier& f) { return f.center.y() > 3.0; });
  const auto pocket = std::find_if(fm.frontiers.begin(), fm.frontiers.end(),
                                   [](const Frontier& f) { return f.center.y() < 3.0; });
  ASSERT_NE(door, fm.frontiers.end());
  ASSERT_NE(pocket, fm.frontiers.end());
  const std::size_t door_i = static_cast<std::size_t>(door - fm.frontiers.begin());
  const std::size_t pocket_i = static_cast<std::size_t>(pocket - fm.frontiers.begin());
  // The unknown cells beside the walls are no open unknown (unseen wall bases).
  EXPECT_NEAR(door->unknown_m2, (4.0 - 0.1) * (3.85 - 0.1), 0.3);
  EXPECT_NEAR(pocket->unknown_m2, 0.25, 0.03);
  EXPECT_GT(pocket->size_m, 1.0) << "the circle's band round the pocket is a long frontier";

  // The thesis chooses the pocket (the door's sliver is under th_f2).
  SamplingParams p;
  EXPECT_EQ(chooseFrontier(fm.frontiers, p, {}), std::optional<std::size_t>(pocket_i));
  // Closed pockets left alone: nothing longer than th_f2 is left.
  p.enclosed_unknown_m2 = 2.0;
  EXPECT_TRUE(p.enclosed(*pocket));
  EXPECT_FALSE(p.enclosed(*door));
  EXPECT_FALSE(chooseFrontier(fm.frontiers, p, {}).has_value());
  // The door judged by its opening, since it faces more than 2 m^2; the
  // pocket would be judged by its cells.
  p.judge_opening = true;
  p.judge_opening_min_unknown_m2 = 2.0;
  EXPECT_EQ(chooseFrontier(fm.frontiers, p, {}), std::optional<std::size_t>(door_i));
  EXPECT_NEAR(p.judgedLength(*door), door->opening_m, 1e-12);
  EXPECT_NEAR(p.judgedLength(*pocket), pocket->size_m, 1e-12);
}

TEST(CircleDoors, OpenUnknownThatReachesTheGridsBorderIsUnbounded)
{
  // The unseen room's far wall unknown too: its pocket runs off the grid.
  GroundGrid g = roomWithDoor(0.9, GroundState::Unknown);
  paint(g, 1.0, 5.0, 4.15, 8.5, GroundState::Unknown);
  const CollisionSpace cs = computeCollisionSpace(g, compact());
  const FrontierMap fm = findFrontiers(g, cs);
  ASSERT_EQ(fm.frontiers.size(), 1u);
  EXPECT_TRUE(std::isinf(fm.frontiers[0].unknown_m2));
}
