// Room segmentation of G (issue 12) on ground grids with known answers: two
// rooms split at a 0.9 m door, joined by a 1.8 m opening, a closet too small
// to be a room, a half-seen room that keeps its shape as the rest is seen,
// and the frontier choice that finishes the robot's room first.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <octomap/OcTree.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/rooms.h>

#include <set>

#include "expect_error.h"
#include "exploration_test_maps.h"

using namespace voxplore::exploration;
using namespace voxplore::test;
using mrpt::poses::CPose2D;

namespace
{
constexpr double kRes = 0.05;

/// Room A [0, 5) x [0, 6) and room B [5.15, 10) x [0, 6), a 0.15 m wall
/// between them with an opening over y in [2.5, 2.5 + opening_m); occupied
/// everywhere else (the outer walls), B's cells east of b_known_to_x Unknown.
GroundGrid twoRooms(double opening_m, double b_known_to_x = 10.0)
{
  GroundGrid g = makeGround(-0.2, 10.2, -0.2, 6.2, kRes, GroundState::Occupied);
  paint(g, 0.0, 5.0, 0.0, 6.0, GroundState::Free);
  paint(g, 5.15, 10.0, 0.0, 6.0, GroundState::Free);
  paint(g, 5.0, 5.15, 2.5, 2.5 + opening_m, GroundState::Free);
  if (b_known_to_x < 10.0) paint(g, b_known_to_x, 10.0, 0.0, 6.0, GroundState::Unknown);
  g.robot = {g.state.x2idx(2.5), g.state.y2idx(3.0)};
  return g;
}

RoomMap rooms(const GroundGrid& g, const RoomParams& p = {})
{
  return segmentRooms(g, computeCollisionSpace(g, CollisionParams{}), p);
}

int32_t roomAtXY(const RoomMap& rm, double x, double y)
{
  return rm.roomAt({rm.label.x2idx(x), rm.label.y2idx(y)});
}

/// Every Free cell of g has a room, every other cell none.
void expectEveryFreeCellLabelled(const GroundGrid& g, const RoomMap& rm)
{
  for (std::size_t i = 0; i < g.state.data().size(); ++i)
  {
    const bool free = g.state.data()[i] == GroundState::Free;
    EXPECT_EQ(rm.label.data()[i] >= 0, free) << "cell " << i;
  }
}
}  // namespace

TEST(Rooms, ADoorSplitsTwoRoomsAndEveryFreeCellJoinsOne)
{
  const GroundGrid g = twoRooms(0.9);
  const RoomMap rm = rooms(g);
  ASSERT_EQ(rm.area_m2.size(), 2u);
  const int32_t a = roomAtXY(rm, 2.5, 3.0), b = roomAtXY(rm, 7.5, 3.0);
  EXPECT_GE(a, 0);
  EXPECT_GE(b, 0);
  EXPECT_NE(a, b);
  // Corners and wall sides (outside the cores) belong to their own room.
  EXPECT_EQ(roomAtXY(rm, 0.02, 0.02), a);
  EXPECT_EQ(roomAtXY(rm, 4.97, 5.97), a);
  EXPECT_EQ(roomAtXY(rm, 5.17, 0.02), b);
  EXPECT_EQ(roomAtXY(rm, 9.97, 5.97), b);
  expectEveryFreeCellLabelled(g, rm);
  // Areas: 30 m^2 and 29.1 m^2, the door's 0.135 m^2 to one of them.
  EXPECT_NEAR(rm.area_m2[static_cast<std::size_t>(a)] + rm.area_m2[static_cast<std::size_t>(b)],
              30.0 + 29.1 + 0.9 * 0.15, 1e-6);
  EXPECT_NEAR(rm.area_m2[static_cast<std::size_t>(a)], 30.0, 0.2);
}

TEST(Rooms, AnOpeningWiderThanADoorJoinsThem)
{
  const RoomMap rm = rooms(twoRooms(1.8));
  ASSERT_EQ(rm.area_m2.size(), 1u);
  EXPECT_EQ(roomAtXY(rm, 2.5, 3.0), roomAtXY(rm, 7.5, 3.0));
  // ... and the door width is the parameter that decides.
  RoomParams wide;
  wide.door_width_m = 2.0;
  EXPECT_EQ(rooms(twoRooms(1.8), wide).area_m2.size(), 2u);
}

TEST(Rooms, AClosetSmallerThanARoomJoinsTheRoomBeforeIt)
{
  GroundGrid g = twoRooms(0.9);
  // A 1.4 x 1.2 m closet north of room A behind a 0.8 m door: its core
  // (clearance > 0.55 m) is under 0.1 m^2.
  auto& st = g.state;
  GroundGrid big = makeGround(-0.2, 10.2, -0.2, 8.0, kRes, GroundState::Occupied);
  for (int cy = 0; cy < static_cast<int>(st.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(st.getSizeX()); ++cx)
      *big.state.cellByIndex(cx, cy) = *st.cellByIndex(cx, cy);
  paint(big, 1.0, 2.4, 6.15, 7.35, GroundState::Free);
  paint(big, 1.2, 2.0, 6.0, 6.15, GroundState::Free);
  big.robot = g.robot;
  const RoomMap rm = rooms(big);
  EXPECT_EQ(rm.area_m2.size(), 2u);
  EXPECT_EQ(roomAtXY(rm, 1.7, 7.0), roomAtXY(rm, 2.5, 3.0));
  expectEveryFreeCellLabelled(big, rm);
  // With no area limit the closet's core is a room of its own.
  RoomParams any;
  any.min_room_area_m2 = 0;
  const RoomMap rm0 = rooms(big, any);
  EXPECT_EQ(rm0.area_m2.size(), 3u);
  EXPECT_NE(roomAtXY(rm0, 1.7, 7.0), roomAtXY(rm0, 2.5, 3.0));
}

TEST(Rooms, AHalfSeenRoomKeepsItsShapeAsTheRestIsSeen)
{
  // B seen up to x = 7 (unknown is no wall: B is a room up to its frontier),
  // then whole: room A's cells are the same cells, and B's first part stays B.
  const GroundGrid part = twoRooms(0.9, 7.0), whole = twoRooms(0.9);
  const RoomMap rp = rooms(part), rw = rooms(whole);
  ASSERT_EQ(rp.area_m2.size(), 2u);
  ASSERT_EQ(rw.area_m2.size(), 2u);
  const int32_t ap = roomAtXY(rp, 2.5, 3.0), aw = roomAtXY(rw, 2.5, 3.0);
  const int32_t bp = roomAtXY(rp, 6.0, 3.0), bw = roomAtXY(rw, 6.0, 3.0);
  ASSERT_NE(ap, bp);
  std::size_t b_cells = 0;
  for (std::size_t i = 0; i < rp.label.data().size(); ++i)
  {
    EXPECT_EQ(rp.label.data()[i] == ap, rw.label.data()[i] == aw) << "cell " << i;
    if (rp.label.data()[i] == bp)
    {
      ++b_cells;
      EXPECT_EQ(rw.label.data()[i], bw) << "cell " << i;
    }
  }
  EXPECT_GT(b_cells, 600u);  // B's seen 1.85 x 6 m
}

TEST(Rooms, NoFreeCellNoRoomAndBadParametersAreRefused)
{
  const GroundGrid g = makeGround(0, 2, 0, 2, kRes, GroundState::Unknown);
  EXPECT_TRUE(rooms(g).area_m2.empty());
  mrpt::config::CConfigFileMemory bad;
  bad.write("rooms", "door_width_m", 0);
  RoomParams p;
  EXPECT_THROW(p.loadFromConfigFile(bad, "rooms"), std::exception);
  PlannerParams pp;
  mrpt::config::CConfigFileMemory typo;
  typo.write("rooms", "finish_rooms", true);
  EXPECT_THROW(pp.load(typo), std::exception);
}

TEST(Sampling, ChooseFrontierTakesThePreferredOnesFirstWhateverTheirLength)
{
  std::vector<Frontier> fs(3);
  const double sizes[] = {0.5, 2.0, 0.2}, dists[] = {6.0, 3.0, 1.0};
  for (int i = 0; i < 3; ++i)
  {
    fs[i].size_m = sizes[i];
    fs[i].distance_m = dists[i];
    fs[i].center = {double(i), 0.0};
  }
  const SamplingParams p;  // th_f1 = 1.0, th_f2 = 0.25
  const std::vector<uint8_t> first{1, 0, 1};
  EXPECT_EQ(chooseFrontier(fs, p, {}), std::optional<std::size_t>(1));
  EXPECT_EQ(chooseFrontier(fs, p, {}, {}, nullptr, &first), std::optional<std::size_t>(0));
  // Below th_f2 a preferred one is still none; skipped, the thesis' order.
  EXPECT_EQ(chooseFrontier(fs, p, {}, {0}, nullptr, &first), std::optional<std::size_t>(1));
  const std::vector<uint8_t> none{0, 0, 0};
  EXPECT_EQ(chooseFrontier(fs, p, {}, {}, nullptr, &none), std::optional<std::size_t>(1));
}

namespace
{
// Room A [-3, 3] x [-2, 2] with a 1.2 m opening to unknown in its west wall
// (a frontier of 0.3 m, the cells the robot's centre reaches: below th_f1)
// and a 1.0 m door in its east wall into a 2 m corridor B [3.05, 9] x [-1, 1]
// open to unknown at its east end (a frontier of 1.1 m, above th_f1).
octomap::OcTree roomAndCorridor()
{
  octomap::OcTree t(kRes);
  addRoom(t, -3.0, 3.0, -2.0, 2.0);
  addRoom(t, 3.05, 9.0, -1.0, 1.0);
  setColumns(t, -3.05, -3.0, -0.6, 0.6, false);
  setColumns(t, 3.0, 3.05, -0.5, 0.5, false);
  setColumns(t, 9.0, 9.05, -1.0, 1.0, false);
  t.updateInnerOccupancy();
  return t;
}

PlannerParams compact()
{
  PlannerParams p;
  p.collision.r_coll_m = 0.4;
  p.collision.model = CollisionParams::Model::Circle;  // the thesis' disc
  return p;
}
}  // namespace

TEST(Planner, FinishRoomTakesTheRobotsRoomsShortFrontierBeforeALongOneElsewhere)
{
  const auto V = roomAndCorridor();
  const CPose2D robot(-1.0, 0.0, 0.0);
  PlannerParams p = compact();
  p.frontier_tiers = true;  // the thesis' order
  const auto thesis = plan(V, robot, p);
  ASSERT_TRUE(thesis.ok()) << thesis.message;
  ASSERT_EQ(thesis.rooms->area_m2.size(), 2u);
  ASSERT_EQ(thesis.frontiers->frontiers.size(), 2u);
  EXPECT_LT(thesis.frontiers->frontiers[0].size_m, p.sampling.th_f1_m);  // the reached cells only
  EXPECT_GT(thesis.frontiers->frontiers[1].size_m, p.sampling.th_f1_m);
  EXPECT_NEAR(thesis.frontier->center.x(), 9.0, 0.2);  // the long one, in B
  p.rooms.finish_room = true;
  const auto finish = plan(V, robot, p);
  ASSERT_TRUE(finish.ok()) << finish.message;
  EXPECT_NEAR(finish.frontier->center.x(), -3.0, 0.2);  // the short one, in A
  ASSERT_GE(finish.robot_room, 0);
  const auto& fs = finish.frontiers->frontiers;
  for (std::size_t i = 0; i < fs.size(); ++i)
    EXPECT_EQ(finish.frontier_rooms[i] == finish.robot_room, fs[i].center.x() < 0) << i;
  // A room frontier that gives no target (here blacklisted) lets the rest go.
  const auto fallback = plan(V, robot, p, {{-3.0, 0.0}});
  ASSERT_TRUE(fallback.ok()) << fallback.message;
  EXPECT_NEAR(fallback.frontier->center.x(), 9.0, 0.2);
  // The nearest baseline keeps the thesis' order.
  p.strategy = Strategy::NearestFrontier;
  const auto nearest = plan(V, robot, p);
  ASSERT_TRUE(nearest.ok()) << nearest.message;
  EXPECT_NEAR(nearest.frontier->center.x(), 9.0, 0.2);
}

TEST(Planner, WithoutFrontierTiersNextBestViewTakesTheNearShortFrontierFirst)
{
  const auto V = roomAndCorridor();
  const CPose2D robot(-1.0, 0.0, 0.0);
  PlannerParams p = compact();
  EXPECT_FALSE(p.frontier_tiers);  // one tier by default
  p.frontier_tiers = true;         // the thesis' tiers
  const auto tiers = plan(V, robot, p);
  ASSERT_TRUE(tiers.ok()) << tiers.message;
  ASSERT_EQ(tiers.frontiers->frontiers.size(), 2u);
  EXPECT_NEAR(tiers.frontier->center.x(), 9.0, 0.2);  // the long one, 10 m away, in B
  p.frontier_tiers = false;
  const auto one = plan(V, robot, p);
  ASSERT_TRUE(one.ok()) << one.message;
  EXPECT_NEAR(one.frontier->center.x(), -3.0, 0.2);  // the short one, 2 m away, in A
  // So does the tour, now over both.
  p.frontier_order = FrontierOrder::Tour;
  const auto tour = plan(V, robot, p);
  ASSERT_TRUE(tour.ok()) << tour.message;
  EXPECT_NEAR(tour.frontier->center.x(), -3.0, 0.2);
  EXPECT_EQ(tour.tour.order.size(), 2u);
  // The nearest baseline keeps the thesis' tiers whatever the key says.
  p.frontier_order = FrontierOrder::Nearest;
  p.strategy = Strategy::NearestFrontier;
  const auto nearest = plan(V, robot, p);
  ASSERT_TRUE(nearest.ok()) << nearest.message;
  EXPECT_NEAR(nearest.frontier->center.x(), 9.0, 0.2);
  // The key round-trips and a word that is no boolean names it.
  mrpt::config::CConfigFileMemory ini;
  PlannerParams q = compact();
  q.frontier_tiers = true;
  q.save(ini);
  PlannerParams back;
  back.load(ini);
  EXPECT_TRUE(back.frontier_tiers);
  ini.write("planner", "frontier_tiers", "sometimes");
  expectErrorNaming([&] { back.load(ini); }, "frontier_tiers", "frontier_tiers = sometimes");
}
