// The exploration planner end to end on synthetic maps: a plan through a
// doorway, "done" on a closed known room, determinism, the nearest-frontier
// baseline, blacklisting, parameters and the PNG.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/exploration/Planner.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "exploration_test_maps.h"
#include "expect_error.h"
#include "test_worlds.h"

using namespace voxplore;
using namespace voxplore::exploration;
using mrpt::poses::CPose2D;

namespace
{
// 6 x 4 m room around the origin with a 1.8 m doorway in the east wall
// (x = 3); unknown beyond.
octomap::OcTree room(double door_half_width_m)
{
  octomap::OcTree t(0.05);
  test::addRoom(t, -3.0, 3.0, -2.0, 2.0);
  if (door_half_width_m > 0)  // open the east wall (one voxel thick at x = 3)
    test::setColumns(t, 3.0, 3.05, -door_half_width_m, door_half_width_m, false);
  t.updateInnerOccupancy();
  return t;
}

octomap::OcTree doorRoom() { return room(0.9); }

PlannerParams params()
{
  PlannerParams p;
  p.collision.r_coll_m = 0.4;  // a compact robot, so the doorway is passable
  p.collision.model = CollisionParams::Model::Circle;  // the thesis' disc
  return p;
}
}  // namespace

TEST(Planner, PlansThroughTheDoorway)
{
  const auto V = doorRoom();
  const CPose2D robot(-1.5, 0.0, 0.0);
  const auto r = plan(V, robot, params());
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_TRUE(r.frontier);
  EXPECT_EQ(r.frontiers->frontiers.size(), 1u);
  EXPECT_NEAR(r.frontier->center.x(), 3.0, 0.3);  // at the doorway
  EXPECT_NEAR(r.frontier->center.y(), 0.0, 0.3);
  ASSERT_FALSE(r.samples.empty());
  EXPECT_LE(r.samples.size(), 15u);
  EXPECT_EQ(r.ratings.size(), r.samples.size());
  ASSERT_FALSE(r.waypoints.empty());
  EXPECT_NEAR(r.waypoints.back().x(), r.target.x(), 1e-9);
  // Every waypoint is in Free space, and the target faces the frontier.
  for (const auto& w : r.waypoints)
  {
    Cell c;
    ASSERT_TRUE(cellOf(r.space->state, w, c));
    EXPECT_EQ(*r.space->state.cellByIndex(c.cx, c.cy), SpaceState::Free) << w.transpose();
  }
  const double yaw_to_frontier =
      std::atan2(r.frontier->center.y() - r.target.y(), r.frontier->center.x() - r.target.x());
  EXPECT_NEAR(mrpt::math::wrapToPi(r.target.phi() - yaw_to_frontier), 0.0, 1e-6);
  // In the open room every sample has a path: by gain alone (the thesis,
  // travel_cost_per_m 0) the target is the best-rated one.
  auto thesis = params();
  thesis.sampling.travel_cost_per_m = 0;
  const auto by_gain = plan(V, robot, thesis);
  ASSERT_TRUE(by_gain.ok()) << by_gain.message;
  const auto best = bestRated(by_gain.ratings);
  ASSERT_TRUE(best);
  EXPECT_EQ(by_gain.target, by_gain.samples[*best]);
  EXPECT_GE(r.ms.total, r.ms.rating);
}

// The seen gate's count ([explore] seen_gate): the plan's frontier cells
// that still border unknown, looked up by their centres in another grid (a
// grown map's: other bounds, the same lattice).
TEST(Planner, FrontierCellsLeftCountsThoseStillFacingUnknown)
{
  const auto t = doorRoom();
  const PlanResult r = plan(t, CPose2D(0, 0, 0), params());
  ASSERT_TRUE(r.frontier.has_value());
  ASSERT_TRUE(r.ground != nullptr);
  const std::size_t n = r.frontier->cells.size();
  ASSERT_GE(n, 4u);
  EXPECT_EQ(frontierCellsLeft(*r.frontier, *r.ground, *r.ground, true), n);
  // The same states on a grid 1 m larger on every side.
  const auto& s = r.ground->state;
  GroundGrid big = test::makeGround(s.getXMin() - 1.0, s.getXMax() + 1.0, s.getYMin() - 1.0,
                                    s.getYMax() + 1.0, s.getResolution(), GroundState::Unknown);
  ASSERT_EQ(big.state.getSizeX(), s.getSizeX() + 40);
  for (std::size_t cy = 0; cy < s.getSizeY(); ++cy)
    for (std::size_t cx = 0; cx < s.getSizeX(); ++cx)
    {
      const Cell c{static_cast<int>(cx), static_cast<int>(cy)};
      const Cell k = test::cellAt(big.state, s.idx2x(c.cx), s.idx2y(c.cy));
      *big.state.cellByIndex(k.cx, k.cy) = *s.cellByIndex(cx, cy);
    }
  EXPECT_EQ(frontierCellsLeft(*r.frontier, *r.ground, big, true), n);
  // The south half of what lies beyond the doorway seen: about half left.
  test::paint(big, 3.05, 8.0, -3.0, 0.0, GroundState::Free);
  const std::size_t half = frontierCellsLeft(*r.frontier, *r.ground, big, true);
  EXPECT_GT(half, n / 4);
  EXPECT_LT(half, 3 * n / 4);
  // A wall seen one cell behind what is still unknown: that unknown is an
  // unseen wall base, no open unknown with ignore_beside_obstacles.
  test::paint(big, 3.1, 3.15, 0.0, 3.0, GroundState::Occupied);
  EXPECT_EQ(frontierCellsLeft(*r.frontier, *r.ground, big, false), half);
  EXPECT_EQ(frontierCellsLeft(*r.frontier, *r.ground, big, true), 0u);
  // All of it seen: none left.
  test::paint(big, 3.05, 8.0, -3.0, 3.0, GroundState::Free);
  EXPECT_EQ(frontierCellsLeft(*r.frontier, *r.ground, big, true), 0u);
}

TEST(Planner, FullyKnownClosedRoomIsDone)
{
  const auto V = room(0.0);
  const auto r = plan(V, CPose2D(0, 0, 0), params());
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.done, DoneReason::NoFrontier) << r.message;
  EXPECT_TRUE(r.waypoints.empty());
}

TEST(Planner, SameMapSameSeedSamePlan)
{
  const auto V = doorRoom();
  const auto a = plan(V, CPose2D(-1.5, 0.3, 0.2), params(), {}, 7);
  const auto b = plan(V, CPose2D(-1.5, 0.3, 0.2), params(), {}, 7);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_EQ(a.samples.size(), b.samples.size());
  for (std::size_t i = 0; i < a.samples.size(); i++)
  {
    EXPECT_EQ(a.samples[i], b.samples[i]);
    EXPECT_EQ(a.ratings[i].gain, b.ratings[i].gain);
  }
  ASSERT_EQ(a.waypoints.size(), b.waypoints.size());
  for (std::size_t i = 0; i < a.waypoints.size(); i++) EXPECT_EQ(a.waypoints[i], b.waypoints[i]);
  auto p = params();
  p.seed = 2;
  const auto c = plan(V, CPose2D(-1.5, 0.3, 0.2), p, {}, 7);
  ASSERT_TRUE(c.ok());
  bool differs = c.samples.size() != a.samples.size();
  for (std::size_t i = 0; !differs && i < a.samples.size(); i++) differs = c.samples[i] != a.samples[i];
  EXPECT_TRUE(differs) << "another seed draws other samples";
}

TEST(Planner, NearestFrontierBaselineDrivesTowardsTheFrontier)
{
  const auto V = doorRoom();
  auto p = params();
  p.strategy = Strategy::NearestFrontier;
  const auto r = plan(V, CPose2D(-1.5, 0.0, 0.0), p);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.samples.empty());
  EXPECT_TRUE(r.ratings.empty());
  EXPECT_LT((Eigen::Vector2d(r.target.x(), r.target.y()) - r.frontier->centroid).norm(), 1.0);
}

TEST(Planner, BlacklistedFrontierIsSkipped)
{
  const auto V = doorRoom();
  const auto first = plan(V, CPose2D(-1.5, 0.0, 0.0), params());
  ASSERT_TRUE(first.ok());
  const auto r = plan(V, CPose2D(-1.5, 0.0, 0.0), params(), {first.frontier->center});
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.done, DoneReason::NoReachableFrontier) << r.message;
}

TEST(Planner, FrontierBehindTooNarrowGapIsNotPlanned)
{
  // The omniRob's collision radius (0.77 m with discretisation) does not fit
  // a 1.2 m doorway: the frontier beyond is unreachable, planning is done.
  const auto V = room(0.6);
  PlannerParams p;  // omniRob r_coll 0.698
  p.collision.model = CollisionParams::Model::Circle;  // the thesis
  const auto r = plan(V, CPose2D(-1.5, 0.0, 0.0), p);
  EXPECT_FALSE(r.ok()) << r.message;
  // The default (model = footprint) plans the omniRob's rectangle, which
  // the 1.2 m doorway lets through; so does auto (its 1.54 m circle).
  EXPECT_TRUE(PlannerParams{}.collision.usesFootprint(V.getResolution()));
  const auto fp = plan(V, CPose2D(-1.5, 0.0, 0.0), PlannerParams{});
  EXPECT_TRUE(fp.ok()) << fp.message;
  CollisionParams omni_auto;
  omni_auto.model = CollisionParams::Model::Auto;
  EXPECT_TRUE(omni_auto.usesFootprint(V.getResolution()));
  // The compact robot plans its footprint by default, its circle under auto.
  CollisionParams compact;
  compact.r_coll_m = 0.31;
  EXPECT_TRUE(compact.usesFootprint(V.getResolution()));
  compact.model = CollisionParams::Model::Auto;
  EXPECT_FALSE(compact.usesFootprint(V.getResolution()));
}

TEST(Planner, ParamsRoundTripAndErrors)
{
  PlannerParams p;
  p.strategy = Strategy::NearestFrontier;
  p.seed = 11;
  p.sampling.max_samples = 9;
  p.path.max_segment_m = 0.8;
  mrpt::config::CConfigFileMemory m1, m2;
  p.save(m1);
  PlannerParams q;
  q.load(m1);
  q.save(m2);
  EXPECT_EQ(m1.getContent(), m2.getContent());
  EXPECT_EQ(q.strategy, Strategy::NearestFrontier);
  mrpt::config::CConfigFileMemory bad;
  bad.write("planner", "strategy", "random");
  EXPECT_THROW(q.load(bad), std::exception);
  mrpt::config::CConfigFileMemory typo;
  typo.write("sampling", "max_sampels", 3);
  EXPECT_THROW(q.load(typo), std::exception);
  mrpt::config::CConfigFileMemory negative;
  negative.write("sampling", "unreached_min_unknown_m2", -1.0);
  EXPECT_THROW(q.load(negative), std::exception);
  mrpt::config::CConfigFileMemory shallow;
  shallow.write("sampling", "unreached_min_depth_m", -0.5);
  EXPECT_THROW(q.load(shallow), std::exception);
}

TEST(Planner, AutoFootprintMarginsFollowTheRobotsWidthAgainstTheDoor)
{
  // "auto" margins: exact (whole squares, cell centres) when the rectangle
  // with a cell lost at each jamb and the centres' spacing fits auto_door_m,
  // trimmed otherwise. At 5 cm the omniRob needs 0.712 + 0.04 + 0.15 = 0.902
  // m (> 0.85: trimmed), the compact robot 0.36 + 0.10 + 0.15 = 0.61 m (its
  // "auto" margin is 0.05 m, see the next test).
  CollisionParams omni;
  ASSERT_EQ(omni.footprint_square_share, CollisionParams::kAuto);
  EXPECT_TRUE(omni.footprintTrimmed(0.05));
  EXPECT_DOUBLE_EQ(omni.squareShareInForce(0.05), 0.5);
  EXPECT_DOUBLE_EQ(omni.lateralInForce(0.05), 0.025);
  CollisionParams compact;
  compact.footprint_length_m = 0.50;
  compact.footprint_width_m = 0.36;
  EXPECT_FALSE(compact.footprintTrimmed(0.05));
  EXPECT_DOUBLE_EQ(compact.squareShareInForce(0.05), 1.0);
  EXPECT_DOUBLE_EQ(compact.lateralInForce(0.05), 0.0);
  // The boundary: a door just narrower than the compact robot needs.
  compact.auto_door_m = 0.549;
  EXPECT_TRUE(compact.footprintTrimmed(0.05));
  // An explicit value wins over auto.
  omni.footprint_square_share = 1.0;
  omni.footprint_lateral_m = 0.0;
  EXPECT_DOUBLE_EQ(omni.squareShareInForce(0.05), 1.0);
  EXPECT_DOUBLE_EQ(omni.lateralInForce(0.05), 0.0);
  // The ini: "auto" and numbers round-trip; anything else names the key.
  mrpt::config::CConfigFileMemory m;
  m.write("collision", "footprint_square_share", "auto");
  m.write("collision", "footprint_lateral_m", "0.01");
  CollisionParams loaded;
  loaded.loadFromConfigFile(m, "collision");
  EXPECT_EQ(loaded.footprint_square_share, CollisionParams::kAuto);
  EXPECT_DOUBLE_EQ(loaded.footprint_lateral_m, 0.01);
  EXPECT_EQ(test::savedText(loaded, "collision", "footprint_square_share"), "auto");
  m.write("collision", "footprint_square_share", "half");
  test::expectErrorNaming([&] { loaded.loadFromConfigFile(m, "collision"); },
                          "footprint_square_share", "'half'");
  m.write("collision", "footprint_square_share", "1.5");
  EXPECT_THROW(loaded.loadFromConfigFile(m, "collision"), std::exception);
}

TEST(Planner, AutoFootprintMarginIsWiderWhereTheDoorLeavesRoom)
{
  // footprint_margin_m "auto": auto_margin_max_m (0.05) when the rectangle
  // with it and exact margins still fits auto_door_m, else auto_margin_min_m
  // (0.02). The omniRob: 0.712 + 0.10 + 0.15 = 0.962 > 0.85, so 0.02 (and
  // trimmed, as before); the compact robot: 0.61 <= 0.85, so 0.05.
  CollisionParams omni;
  ASSERT_EQ(omni.footprint_margin_m, CollisionParams::kAuto);
  EXPECT_DOUBLE_EQ(omni.marginInForce(0.05), 0.02);
  EXPECT_NEAR(omni.exactDoorM(0.05), 0.902, 1e-12);
  EXPECT_TRUE(omni.footprintTrimmed(0.05));
  CollisionParams compact;
  compact.footprint_length_m = 0.50;
  compact.footprint_width_m = 0.36;
  EXPECT_DOUBLE_EQ(compact.marginInForce(0.05), 0.05);
  EXPECT_NEAR(compact.exactDoorM(0.05), 0.61, 1e-12);
  EXPECT_FALSE(compact.footprintTrimmed(0.05));
  // A door between the two needs: the narrow margin, still exact.
  compact.auto_door_m = 0.60;
  EXPECT_DOUBLE_EQ(compact.marginInForce(0.05), 0.02);
  EXPECT_FALSE(compact.footprintTrimmed(0.05));
  // The footprint space keeps the margin in force.
  compact.model = CollisionParams::Model::Footprint;
  compact.auto_door_m = 0.85;
  compact.r_coll_m = std::hypot(0.25, 0.18);
  const GroundGrid g = test::makeGround(-2.0, 2.0, -2.0, 2.0, 0.05, GroundState::Free);
  const CollisionSpace cs = computeCollisionSpace(g, compact);
  const FootprintSpace fs = computeFootprintSpace(g, cs, compact, CPose2D(0, 0, 0));
  EXPECT_DOUBLE_EQ(fs.margin_m, 0.05);
  // An explicit number wins.
  compact.footprint_margin_m = 0.03;
  EXPECT_DOUBLE_EQ(compact.marginInForce(0.05), 0.03);
  // The ini: "auto" round-trips; a turn margin under the widest auto margin
  // is an error naming the key.
  mrpt::config::CConfigFileMemory m;
  m.write("collision", "footprint_margin_m", "auto");
  m.write("collision", "auto_margin_max_m", "0.04");
  CollisionParams loaded;
  loaded.loadFromConfigFile(m, "collision");
  EXPECT_EQ(loaded.footprint_margin_m, CollisionParams::kAuto);
  EXPECT_DOUBLE_EQ(loaded.auto_margin_max_m, 0.04);
  EXPECT_EQ(test::savedText(loaded, "collision", "footprint_margin_m"), "auto");
  m.write("collision", "auto_margin_max_m", "0.08");
  test::expectErrorNaming([&] { loaded.loadFromConfigFile(m, "collision"); },
                          "footprint_turn_margin_m",
                          "a turn margin of 0.05 under auto_margin_max_m 0.08");
  m.write("collision", "auto_margin_max_m", "0.01");
  EXPECT_THROW(loaded.loadFromConfigFile(m, "collision"), std::exception);
}

TEST(Planner, ObstacleZMaxAutoIsOnWithExactFootprintMargins)
{
  // [projection] obstacle_z_max_m "auto" (the default): auto_obstacle_z_max_m
  // (0.60 m) where the planner plans the footprint with exact margins (the
  // compact robot), off where they are trimmed (the omniRob) and for the
  // circle.
  PlannerParams omni;
  ASSERT_EQ(omni.projection.obstacle_z_max_m, ProjectionParams::kAuto);
  EXPECT_EQ(omni.projectionInForce(0.05).obstacle_z_max_m, 0.0);
  PlannerParams compact;
  compact.setFootprint(0.50, 0.36);
  EXPECT_DOUBLE_EQ(compact.projectionInForce(0.05).obstacle_z_max_m, 0.60);
  // What plan() projects: a box at 0.50-0.60 m in a known room closes its
  // column for the compact robot only.
  octomap::OcTree t(0.05);
  test::fillBox(t, -3.0, 1.0, -2.0, 2.0, 0.1, 0.5, test::freeLog(t));
  test::fillBox(t, -1.6, -1.5, 0.5, 0.6, 0.5, 0.6, test::occLog(t));
  const CPose2D robot(-2.0, 0.0, 0.0);
  const auto box_column = [&](const PlannerParams& p)
  {
    const PlanResult r = plan(t, robot, p);
    Cell c;
    EXPECT_TRUE(cellOf(r.ground->state, Eigen::Vector2d(-1.55, 0.55), c));
    return *r.ground->state.cellByIndex(c.cx, c.cy);
  };
  EXPECT_EQ(box_column(compact), GroundState::Occupied);
  EXPECT_EQ(box_column(omni), GroundState::Free);
  PlannerParams compact_circle = compact;
  compact_circle.collision.model = CollisionParams::Model::Circle;
  EXPECT_EQ(compact_circle.projectionInForce(0.05).obstacle_z_max_m, 0.0);
  // An explicit height wins, for either robot.
  omni.projection.obstacle_z_max_m = 0.60;
  EXPECT_EQ(box_column(omni), GroundState::Occupied);
  compact.projection.obstacle_z_max_m = 0;
  EXPECT_EQ(box_column(compact), GroundState::Free);
  // The ini: "auto" round-trips; a negative height is an error naming the key.
  mrpt::config::CConfigFileMemory m;
  m.write("projection", "obstacle_z_max_m", "auto");
  m.write("projection", "auto_obstacle_z_max_m", "0.55");
  ProjectionParams loaded;
  loaded.obstacle_z_max_m = 0.3;
  loaded.loadFromConfigFile(m, "projection");
  EXPECT_EQ(loaded.obstacle_z_max_m, ProjectionParams::kAuto);
  EXPECT_DOUBLE_EQ(loaded.auto_obstacle_z_max_m, 0.55);
  EXPECT_EQ(test::savedText(loaded, "projection", "obstacle_z_max_m"), "auto");
  m.write("projection", "obstacle_z_max_m", "-0.5");
  test::expectErrorNaming([&] { loaded.loadFromConfigFile(m, "projection"); }, "obstacle_z_max_m",
                          "an obstacle band up to -0.5 m");
}

TEST(Planner, RendersThePlan)
{
  const auto V = doorRoom();
  const CPose2D robot(-1.5, 0.0, 0.0);
  const auto r = plan(V, robot, params());
  const auto png = test::tempPath("plan.png");
  renderPlan(r, robot, png, {CPose2D(-2, 0, 0), robot}, 3);
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  EXPECT_THROW(renderPlan(r, robot, "/nonexistent_dir/plan.png"), std::runtime_error);
}

TEST(Planner, AllFrontiersSkippedSaysWhy)
{
  // The doorway's frontier with a sample ring farther than the room reaches:
  // no sample space, so the frontier is skipped and planning ends saying so.
  const auto V = doorRoom();
  PlannerParams p = params();
  p.sampling.d_min_sample_m = 9.0;
  p.sampling.d_max_sample_m = 10.0;
  const auto r = plan(V, CPose2D(-1.5, 0.0, 0.0), p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.done, DoneReason::AllSkipped) << r.message;
  ASSERT_EQ(r.skip_reasons.size(), r.skipped_frontiers.size());
  ASSERT_FALSE(r.skip_reasons.empty());
  EXPECT_EQ(r.skip_reasons.front(), SkipReason::NoSamples);
  EXPECT_NE(r.message.find("1 no sample space"), std::string::npos) << r.message;
  // The same map planned normally skips nothing.
  const auto ok = plan(V, CPose2D(-1.5, 0.0, 0.0), params());
  ASSERT_TRUE(ok.ok()) << ok.message;
  EXPECT_TRUE(ok.skip_reasons.empty());
}

TEST(Planner, SensedObstaclesTheMapDoesNotHoldCloseTheWay)
{
  // The driver sensed points in the doorway (an obstacle under the
  // projection's z_min, or the map off by a pose error): their cells are
  // Occupied for the planner, which then has no way to the frontier beyond.
  const auto V = doorRoom();
  const CPose2D robot(-1.5, 0.0, 0.0);
  ASSERT_TRUE(plan(V, robot, params()).ok());
  std::vector<Eigen::Vector2d> sensed;
  for (double y = -0.9; y <= 0.9 + 1e-9; y += 0.05) sensed.emplace_back(2.6, y);
  sensed.emplace_back(robot.x(), robot.y());  // never the robot's own cell
  const auto r = plan(V, robot, params(), {}, 0, {}, sensed);
  EXPECT_FALSE(r.ok()) << r.message;
  Cell c;
  ASSERT_TRUE(cellOf(r.ground->state, Eigen::Vector2d(2.6, 0.0), c));
  EXPECT_EQ(*r.ground->state.cellByIndex(c.cx, c.cy), GroundState::Occupied);
  EXPECT_NE(*r.ground->state.cellByIndex(r.ground->robot.cx, r.ground->robot.cy),
            GroundState::Occupied);
}

TEST(Planner, ALowObstacleUnderAnUnseenTableTopIsNoFrontier)
{
  // A closed, fully known room but for a table: the 0.5 x 0.5 m of floor
  // under its top never seen (columns unknown, deeper than
  // min_open_unknown_depth_m, so open), and round its rim the points of a
  // 3-5 cm base (OctoMapLayer's low cells, two cells wide).
  auto V = room(0.0);
  test::fillBox(V, 0.5, 1.0, 0.5, 1.0, 0.0, 0.6, 0.0f);
  V.updateInnerOccupancy();
  std::vector<Eigen::Vector2d> low;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      if (std::min({i, j, 9 - i, 9 - j}) < 2) low.emplace_back(0.525 + 0.05 * i, 0.525 + 0.05 * j);
  const CPose2D robot(-1.5, 0.0, 0.0);
  auto p = params();
  const auto bare = plan(V, robot, p);
  ASSERT_TRUE(bare.ok()) << "the unseen floor under the table is a frontier";
  EXPECT_NEAR(bare.frontier->center.x(), 0.75, 0.35);
  EXPECT_NEAR(bare.frontier->center.y(), 0.75, 0.35);

  p.collision.low_obstacles_on_unknown = false;  // eighteenth session: Free cells only
  EXPECT_TRUE(plan(V, robot, p, {}, 0, {}, {}, {}, low).ok()) << "still a frontier";

  p.collision.low_obstacles_on_unknown = true;
  const auto r = plan(V, robot, p, {}, 0, {}, {}, {}, low);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.done, DoneReason::NoFrontier) << r.message;
  const auto index = [&](double x, double y)
  {
    Cell c;
    EXPECT_TRUE(cellOf(r.ground->state, Eigen::Vector2d(x, y), c));
    return static_cast<std::size_t>(c.cy) * r.ground->state.getSizeX() + c.cx;
  };
  ASSERT_EQ(r.ground->low_was.size(), r.ground->state.data().size());
  EXPECT_EQ(r.ground->state.data()[index(0.525, 0.525)], GroundState::Occupied);
  EXPECT_EQ(r.ground->low_was[index(0.525, 0.525)], 2) << "stamped on an Unknown cell";
  EXPECT_EQ(r.ground->low_was[index(-1.0, -1.0)], 0);
  EXPECT_EQ(r.space->open_unknown[index(0.525, 0.525)], 0) << "a stamped cell is closed";
  // The unknown inside the rim, beside stamped cells, stays open as the
  // voxel columns have it (an obstacle would close it: its unseen base).
  EXPECT_EQ(r.ground->state.data()[index(0.625, 0.775)], GroundState::Unknown);
  EXPECT_EQ(r.space->open_unknown[index(0.625, 0.775)], 1);
}

TEST(Planner, AReplannedFrontierIsApproachedNotViewedAgain)
{
  // Next-best-view targets see the frontier from 1-3 m; a frontier planned
  // before whose view did not clear it is approached: the target is its
  // nearest reachable cell (a narrow opening's far side is seen from there).
  const auto V = doorRoom();
  const CPose2D robot(-1.5, 0.0, 0.0);
  const auto viewed = plan(V, robot, params());
  ASSERT_TRUE(viewed.ok()) << viewed.message;
  ASSERT_TRUE(viewed.frontier);
  EXPECT_FALSE(viewed.approached);
  const Eigen::Vector2d fc = viewed.frontier->center;
  const Eigen::Vector2d t1(viewed.target.x(), viewed.target.y());
  EXPECT_GE((t1 - fc).norm(), 1.0 - 0.05);
  const auto approached = plan(V, robot, params(), {}, 0, {}, {}, {fc});
  ASSERT_TRUE(approached.ok()) << approached.message;
  EXPECT_TRUE(approached.approached);
  const Eigen::Vector2d t2(approached.target.x(), approached.target.y());
  EXPECT_LT((t2 - fc).norm(), 0.6) << t2.transpose();
  // The nearest strategy with the circle is not affected (its target is the
  // nearest cell anyway; the footprint's view stand-off is: FootprintPlanning).
  PlannerParams nearest = params();
  nearest.strategy = Strategy::NearestFrontier;
  EXPECT_FALSE(plan(V, robot, nearest, {}, 0, {}, {}, {fc}).approached);
}

TEST(Planner, SamplesAreTriedByGainDiscountedByTheirTravel)
{
  // The thesis takes the sample with the most gain; with travel_cost_per_m
  // each sample's gain is discounted by exp(-lambda x its travel distance
  // over G), and the target is the sample with the best utility.
  const auto V = doorRoom();
  const CPose2D robot(-1.5, 0.0, 0.0);
  auto p = params();
  p.sampling.travel_cost_per_m = 0;  // the thesis
  const auto by_gain = plan(V, robot, p);
  ASSERT_TRUE(by_gain.ok()) << by_gain.message;
  p.sampling.travel_cost_per_m = 1.5;
  const auto r = plan(V, robot, p);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.samples.size(), by_gain.samples.size()) << "the same samples, rated the same";
  const auto travel = [&](const CPose2D& s) {
    return double(test::at(r.frontiers->distance_m, s.x(), s.y()));
  };
  std::size_t best = 0;
  double best_u = -1;
  for (std::size_t i = 0; i < r.samples.size(); i++)
  {
    ASSERT_EQ(r.ratings[i].gain, by_gain.ratings[i].gain);
    ASSERT_GE(travel(r.samples[i]), 0.0) << "samples lie in the reachable space";
    const double u = r.ratings[i].gain * std::exp(-1.5 * travel(r.samples[i]));
    if (u > best_u)
    {
      best_u = u;
      best = i;
    }
  }
  EXPECT_EQ(r.target, r.samples[best]);
  // Here the discount changes the choice: a nearer sample with less gain.
  EXPECT_NE(r.target, by_gain.target);
  EXPECT_LT(travel(r.target), travel(by_gain.target));
  EXPECT_LT(r.ratings[best].gain, r.ratings[*bestRated(by_gain.ratings)].gain);
}

TEST(Planner, SeveralFrontiersRatedTogetherTheBestViewWins)
{
  // A 6 x 4 m room, a 2 m opening in the west wall 1.5 m from the robot (the
  // nearest frontier) and the east wall open over 3.6 m (4.5 m away). The
  // thesis views the nearest frontier; with frontiers_rated = 2 both
  // frontiers' samples are rated and the wide opening's view wins, unless
  // the travel discount makes the near door worth more.
  octomap::OcTree V(0.05);
  test::addRoom(V, -3.0, 3.0, -2.0, 2.0);
  test::setColumns(V, -3.05, -3.0, -1.0, 1.0, false);
  test::setColumns(V, 3.0, 3.05, -1.8, 1.8, false);
  V.updateInnerOccupancy();
  const CPose2D robot(-1.5, 0.0, 0.0);
  auto p = params();
  p.sampling.travel_cost_per_m = 0;  // by gain alone first
  const auto one = plan(V, robot, p);
  ASSERT_TRUE(one.ok()) << one.message;
  ASSERT_EQ(one.frontiers->frontiers.size(), 2u);
  EXPECT_LT(one.frontier->center.x(), 0.0) << "the nearest frontier, the west door";
  EXPECT_EQ(one.message.find("rated"), std::string::npos) << one.message;
  p.sampling.frontiers_rated = 2;
  const auto two = plan(V, robot, p);
  ASSERT_TRUE(two.ok()) << two.message;
  EXPECT_GT(two.frontier->center.x(), 0.0) << "the east opening";
  EXPECT_GT(two.target.x(), 0.0);
  EXPECT_NE(two.message.find("best of 2 rated"), std::string::npos) << two.message;
  EXPECT_GT(two.samples.size(), one.samples.size()) << "both frontiers' samples";
  EXPECT_EQ(two.frontier->center, two.frontiers->frontiers[two.frontier_index].center);
  p.sampling.travel_cost_per_m = 3.0;
  const auto near = plan(V, robot, p);
  ASSERT_TRUE(near.ok()) << near.message;
  EXPECT_LT(near.frontier->center.x(), 0.0) << "a steep discount keeps the near door";
  // The nearest strategy rates nothing and keeps the nearest frontier.
  p.strategy = Strategy::NearestFrontier;
  const auto nearest = plan(V, robot, p);
  ASSERT_TRUE(nearest.ok()) << nearest.message;
  EXPECT_LT(nearest.frontier->center.x(), 0.0);
}

namespace
{
// The robot's 6 x 2 m room, a 0.6 m door in its north wall (y = 0) that the
// 0.4 m circle cannot pass, and the room behind it (6 x 3 m, closed) known
// free in its first 0.95 m, as seen through the door, and along its walls
// (0.2 m): the rest is a closed pocket of unknown (5.6 x 1.8 m). With
// `outside`, the strips along its walls are unseen: G does not hold the
// far walls, and the pocket reaches the grid's border (the outside).
octomap::OcTree seenThroughNarrowDoor(bool outside = false)
{
  octomap::OcTree t(0.05);
  test::addRoom(t, -3.0, 3.0, -2.0, 0.0);
  test::setColumns(t, -0.3, 0.3, 0.0, 0.05, false);   // the door
  test::setColumns(t, -3.0, 3.0, 0.05, 1.0, false);   // seen through it
  test::setColumns(t, -3.05, -3.0, 0.0, 3.05, true);  // the far room's walls
  test::setColumns(t, 3.0, 3.05, 0.0, 3.05, true);
  test::setColumns(t, -3.05, 3.05, 3.0, 3.05, true);
  if (!outside)
  {
    test::setColumns(t, -3.0, -2.8, 1.0, 3.0, false);
    test::setColumns(t, 2.8, 3.0, 1.0, 3.0, false);
    test::setColumns(t, -2.8, 2.8, 2.8, 3.0, false);
  }
  t.updateInnerOccupancy();
  return t;
}
}  // namespace

TEST(Planner, UnreachedFrontiersAreViewedFromTheReachOnceNothingElseIsLeft)
{
  const CPose2D robot(-1.5, -1.0, 0.0);
  const auto V = seenThroughNarrowDoor();
  // Reachable frontiers only (the thesis): nothing to do, the far room's
  // known floor cut off.
  const auto thesis = plan(V, robot, params());
  EXPECT_EQ(thesis.done, DoneReason::NoFrontier) << thesis.message;
  for (const auto strategy : {Strategy::NextBestView, Strategy::NearestFrontier})
  {
    PlannerParams p = params();
    p.strategy = strategy;
    p.sampling.unreached_frontiers = true;
    const auto r = plan(V, robot, p);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_TRUE(r.frontier);
    EXPECT_TRUE(r.frontier->unreached);
    EXPECT_GT(r.frontier->center.y(), 0.7);  // in the far room, not the door
    EXPECT_NEAR(r.frontier->unknown_m2, 5.6 * 1.8, 0.5);
    EXPECT_NE(r.message.find("unreached"), std::string::npos) << r.message;
    // The view stays on the robot's side of the wall, in sight of the frontier.
    EXPECT_LT(r.target.y(), -0.3);
    EXPECT_LE(std::abs(r.target.y() - r.frontier->center.y()), p.sampling.d_max_sample_m + 1.0);
    ASSERT_FALSE(r.waypoints.empty());
    for (const auto& w : r.waypoints) EXPECT_LT(w.y(), -0.3);
    // A smaller pocket than asked for, or one open to the outside, is left.
    p.sampling.unreached_min_unknown_m2 = 20.0;
    EXPECT_EQ(plan(V, robot, p).done, DoneReason::NoFrontier);
    p.sampling.unreached_min_unknown_m2 = 8.0;
    EXPECT_EQ(plan(seenThroughNarrowDoor(true), robot, p).done, DoneReason::NoFrontier);
    // No cell of it min_depth_m beyond the reach (the floor along a wall:
    // here none within d_max_sample_m, 3 m, lies 3.5 m beyond it): left.
    p.sampling.unreached_min_depth_m = 3.5;
    EXPECT_EQ(plan(V, robot, p).done, DoneReason::NoFrontier);
    p.sampling.unreached_min_depth_m = 1.0;
    // Farther than d_max_sample_m from the reach: left too.
    p.sampling.d_max_sample_m = 1.2;
    EXPECT_FALSE(plan(V, robot, p).ok());
  }
}

TEST(Planner, UnreachedFrontiersWaitForTheReachedOnes)
{
  // The doorway room (a reachable frontier) with the flag on plans as before.
  const auto V = doorRoom();
  PlannerParams p = params();
  const auto before = plan(V, CPose2D(-1.5, 0.0, 0.0), p);
  p.sampling.unreached_frontiers = true;
  const auto now = plan(V, CPose2D(-1.5, 0.0, 0.0), p);
  ASSERT_TRUE(before.ok() && now.ok()) << now.message;
  EXPECT_FALSE(now.frontier->unreached);
  EXPECT_EQ(now.frontiers->frontiers.size(), before.frontiers->frontiers.size());
  EXPECT_NEAR(now.target.x(), before.target.x(), 1e-12);
  EXPECT_NEAR(now.target.y(), before.target.y(), 1e-12);
}
