// The thesis' circle model at ordinary doors (issue 12, compact robot): a
// frontier judged by the opening it faces, not by the 2-4 cells the circle
// reaches in a 0.9 m door, and a door the robot has driven through kept
// open when the map's unknown jambs close it to the thesis' reachability.
#include <gtest/gtest.h>
#include <voxplore/exploration/stages.h>

#include <cmath>

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
