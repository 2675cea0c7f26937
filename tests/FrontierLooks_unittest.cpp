// Unknown cells the cameras looked at and left unknown (issue 12's end): a
// look is a 2D sight over Free cells within range whose band lies in a
// camera's view; looks count from stops apart; cells looked at often enough
// are no frontier source; the records survive voxplore-plan's inputs file.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/looks.h>
#include <voxplore/exploration/plan_inputs.h>
#include <voxplore/exploration/scan_rating.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <array>

#include "exploration_test_maps.h"
#include "test_worlds.h"

using namespace voxplore;
using namespace voxplore::exploration;
using mrpt::poses::CPose2D;

namespace
{
constexpr double kRes = 0.05;

/// 12 x 12 m of Free floor round the origin, with a square Unknown pocket
/// of side `side` whose south-west corner is (x, y).
GroundGrid floorWithPocket(double x, double y, double side = 0.2)
{
  GroundGrid g = test::makeGround(-6, 6, -6, 6, kRes, GroundState::Free);
  test::paint(g, x, x + side, y, y + side, GroundState::Unknown);
  test::placeRobot(g, 0.025, 0.025);
  return g;
}

uint8_t maskAt(const std::vector<uint8_t>& mask, const GroundGrid& g, double x, double y)
{
  if (mask.empty()) return 0;
  const Cell c = test::cellAt(g.state, x, y);
  return mask[static_cast<std::size_t>(c.cx) + static_cast<std::size_t>(c.cy) * g.state.getSizeX()];
}

struct LookSetup
{
  ProjectionParams band;
  ScanRatingParams cameras;  // the omniRob ring
  SamplingParams p;
  LookSetup() { p.retire_looks = 2; }  // off by default
};
}  // namespace

TEST(FrontierLooks, AStopCountsTheUnknownItSeesFirstInACamerasView)
{
  const LookSetup s;
  const GroundGrid g = floorWithPocket(2.0, 0.0);  // 2 m ahead of the front camera
  FrontierLooks looks;
  looks.addStop(CPose2D(0.025, 0.025, 0));
  looks.update(g, s.band, s.cameras, s.p);
  EXPECT_TRUE(looks.pending().empty());
  const auto once = looks.retiredMask(g.state, 1);
  EXPECT_EQ(maskAt(once, g, 2.025, 0.075), 1);  // the pocket's face towards the robot
  EXPECT_EQ(maskAt(once, g, 2.175, 0.075), 0);  // behind it: not seen first
  EXPECT_TRUE(looks.retiredMask(g.state, 2).empty());
  EXPECT_TRUE(looks.retiredMask(g.state, 0).empty());
}

TEST(FrontierLooks, LooksCountOnlyFromStopsApart)
{
  const LookSetup s;  // look_spacing_m 0.5
  const GroundGrid g = floorWithPocket(2.0, 0.0);
  FrontierLooks looks;
  for (const double x : {0.025, 0.225})  // 0.2 m apart: one look
    looks.addStop(CPose2D(x, 0.025, 0));
  looks.update(g, s.band, s.cameras, s.p);
  EXPECT_TRUE(looks.retiredMask(g.state, 2).empty());
  looks.addStop(CPose2D(-0.575, 0.025, 0));  // 0.8 m from the last counted
  looks.update(g, s.band, s.cameras, s.p);
  EXPECT_EQ(maskAt(looks.retiredMask(g.state, 2), g, 2.025, 0.075), 1);
}

TEST(FrontierLooks, NoLookBehindAnObstacleOutOfViewOrOutOfRange)
{
  LookSetup s;
  s.p.look_range_m = 3.0;
  const CPose2D robot(0.025, 0.025, 0);
  const auto looked = [&](const GroundGrid& g, const ScanRatingParams& cams)
  {
    FrontierLooks looks;
    looks.addStop(robot);
    looks.update(g, s.band, cams, s.p);
    return !looks.retiredMask(g.state, 1).empty();
  };
  GroundGrid behind = floorWithPocket(2.0, 0.0);
  test::paint(behind, 1.5, 1.55, -1.0, 1.0, GroundState::Occupied);
  EXPECT_FALSE(looked(behind, s.cameras));
  // Within 1 m of the front camera (at the omniRob's rim): below its view.
  EXPECT_FALSE(looked(floorWithPocket(0.8, 0.0), s.cameras));
  EXPECT_FALSE(looked(floorWithPocket(3.5, 0.0), s.cameras));  // beyond look_range_m
  // Only the front camera: a pocket beside the robot is out of its view.
  ScanRatingParams front = s.cameras;
  front.mounts.resize(1);
  EXPECT_TRUE(looked(floorWithPocket(2.0, 0.0), front));
  EXPECT_FALSE(looked(floorWithPocket(0.0, 2.0), front));
  // The whole ring sees it.
  EXPECT_TRUE(looked(floorWithPocket(0.0, 2.0), s.cameras));
}

TEST(FrontierLooks, RetiredUnknownIsNoFrontierSource)
{
  // A 4 x 4 m free square in unknown space: one frontier round it.
  GroundGrid g = test::makeGround(-4, 4, -4, 4, kRes, GroundState::Unknown);
  test::paint(g, -2, 2, -2, 2, GroundState::Free);
  test::placeRobot(g, 0.025, 0.025);
  const CollisionSpace cs = computeCollisionSpace(g, CollisionParams{});
  const FrontierMap all = findFrontiers(g, cs);
  ASSERT_EQ(all.frontiers.size(), 1u);
  // Every unknown cell retired but those east of x = 2: only the east side's
  // cells are frontier cells.
  std::vector<uint8_t> retired(g.state.data().size(), 0);
  for (std::size_t cy = 0; cy < g.state.getSizeY(); ++cy)
    for (std::size_t cx = 0; cx < g.state.getSizeX(); ++cx)
      if (g.state.idx2x(static_cast<int>(cx)) < 2.0)
        retired[cx + cy * g.state.getSizeX()] = 1;
  const FrontierMap east = findFrontiers(g, cs, &retired);
  ASSERT_EQ(east.frontiers.size(), 1u);
  EXPECT_LT(east.frontiers[0].cells.size(), all.frontiers[0].cells.size());
  for (const Cell& c : east.frontiers[0].cells) EXPECT_GT(cellCenter(cs.state, c).x(), 1.5);
  std::fill(retired.begin(), retired.end(), 1);
  EXPECT_TRUE(findFrontiers(g, cs, &retired).frontiers.empty());
  const std::vector<uint8_t> none;
  EXPECT_EQ(findFrontiers(g, cs, &none).frontiers.size(), 1u);
}

TEST(FrontierLooks, RecordsAndPendingStopsRoundTripThroughThePlanInputs)
{
  const LookSetup s;
  const GroundGrid g = floorWithPocket(2.0, 0.0);
  auto looks = std::make_shared<FrontierLooks>();
  looks->addStop(CPose2D(0.025, 0.025, 0));
  looks->update(g, s.band, s.cameras, s.p);
  looks->addStop(CPose2D(-0.6123456789, 0.1, 0.25));
  ASSERT_FALSE(looks->records().empty());

  octomap::OcTree V(kRes);
  test::addRoom(V, -1, 1, -1, 1);
  PlanInputs in;
  in.robot = CPose2D(0, 0, 0);
  in.looks = looks;
  const auto path = test::tempPath("looks_step.txt");
  writePlanInputs(path, in, V);
  std::unique_ptr<octomap::OcTree> V2;
  const PlanInputs back = readPlanInputs(path, V2);
  ASSERT_TRUE(back.looks);
  const auto a = looks->records(), b = back.looks->records();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    EXPECT_EQ(a[i].kx, b[i].kx);
    EXPECT_EQ(a[i].ky, b[i].ky);
    EXPECT_EQ(a[i].n, b[i].n);
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
  }
  ASSERT_EQ(back.looks->pending().size(), 1u);
  EXPECT_EQ(back.looks->pending()[0], looks->pending()[0]);

  // Without looks, none come back.
  in.looks.reset();
  writePlanInputs(path, in, V);
  EXPECT_FALSE(readPlanInputs(path, V2).looks);
}

TEST(FrontierLooks, OnlySmallClosedPocketsAreRetired)
{
  LookSetup s;
  s.p.look_range_m = 6.0;
  s.p.retire_pocket_m2 = 1.0;
  // A 0.4 m pocket 4.5 m ahead (0.2 m would be a thin pocket, no open
  // unknown); and a wedge of unknown from there to the grid's border (open
  // to the unknown beyond it).
  GroundGrid small = floorWithPocket(4.5, 0.0, 0.4);
  GroundGrid big = floorWithPocket(4.5, 0.0, 0.4);
  test::paint(big, 4.5, 6.0, -0.5, 0.5, GroundState::Unknown);
  for (GroundGrid* g : {&small, &big})
    for (const double pocket_m2 : {1.0, 0.0})
    {
      s.p.retire_pocket_m2 = pocket_m2;
      const CollisionSpace cs = computeCollisionSpace(*g, CollisionParams{});
      FrontierLooks looks;
      for (const double x : {0.025, -0.575}) looks.addStop(CPose2D(x, 0.025, 0));
      double m2 = 0;
      const auto mask = retireLooked(looks, *g, cs, s.band, s.cameras, s.p, m2);
      const bool expected = g == &small || pocket_m2 == 0;  // 0: any pocket
      EXPECT_EQ(maskAt(mask, *g, 4.525, 0.075) == 1, expected) << pocket_m2;
      EXPECT_EQ(m2 > 0, expected) << pocket_m2;
    }
}

TEST(FrontierLooks, PlanTakesTheLookedAtFaceOfAPocketFromTheFrontiers)
{
  // An 8 x 6 m closed room, all seen but a 0.6 m pocket 4 m east of the
  // robot: the only frontier rings the pocket.
  octomap::OcTree V(kRes);
  const float free = test::freeLog(V), occ = test::occLog(V);
  for (const auto& [x0, x1, y0, y1] : {std::array<double, 4>{-2.0, 3.8, -3.0, 3.0},
                                       std::array<double, 4>{4.4, 6.0, -3.0, 3.0},
                                       std::array<double, 4>{3.8, 4.4, -3.0, -0.3},
                                       std::array<double, 4>{3.8, 4.4, 0.3, 3.0}})
    test::fillBox(V, x0, x1, y0, y1, 0.0, 0.6, free);
  test::fillBox(V, -2.05, 6.05, -3.05, -3.0, 0.0, 0.6, occ);  // the walls
  test::fillBox(V, -2.05, 6.05, 3.0, 3.05, 0.0, 0.6, occ);
  test::fillBox(V, -2.05, -2.0, -3.0, 3.0, 0.0, 0.6, occ);
  test::fillBox(V, 6.0, 6.05, -3.0, 3.0, 0.0, 0.6, occ);
  V.updateInnerOccupancy();
  PlannerParams params;
  params.collision.r_coll_m = 0.4;
  params.collision.model = CollisionParams::Model::Circle;
  params.sampling.retire_looks = 2;
  params.sampling.th_f2_m = 0;  // every frontier counts
  const CPose2D robot(0.025, 0.025, 0);
  const auto frontierCells = [](const PlanResult& r)
  {
    std::size_t n = 0;
    for (const auto& f : r.frontiers->frontiers) n += f.cells.size();
    return n;
  };
  const PlanResult without = plan(V, robot, params);
  ASSERT_TRUE(without.frontiers);
  ASSERT_EQ(without.frontiers->frontiers.size(), 1u);
  EXPECT_TRUE(without.retired.empty());

  FrontierLooks looks;
  for (const double x : {0.025, -0.575}) looks.addStop(CPose2D(x, 0.025, 0));
  const PlanResult with = plan(V, robot, params, {}, 0, {}, {}, {}, {}, nullptr, &looks);
  ASSERT_TRUE(with.frontiers);
  EXPECT_TRUE(looks.pending().empty());
  EXPECT_GT(with.retired_m2, 0.0);
  EXPECT_LT(with.retired_m2, 0.36);  // the face towards the robot, not the pocket
  EXPECT_LT(frontierCells(with), frontierCells(without));
  // The frontier cells left do not border the west face.
  for (const auto& f : with.frontiers->frontiers)
    for (const Cell& c : f.cells) EXPECT_GT(cellCenter(with.space->state, c).x(), 3.8);

  // Off: the looks change nothing.
  params.sampling.retire_looks = 0;
  FrontierLooks off;
  off.addStop(robot);
  EXPECT_EQ(frontierCells(plan(V, robot, params, {}, 0, {}, {}, {}, {}, nullptr, &off)),
            frontierCells(without));
}
