// A planning step saved by a run and planned again (voxplore-plan): the
// inputs round-trip exactly, the same inputs give the same plan, the map
// keeps its log-odds, and bad files are refused naming the file and line.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <octomap/OcTree.h>
#include <voxplore/apps/PlanApp.h>
#include <voxplore/exploration/plan_inputs.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "exploration_test_maps.h"
#include "test_worlds.h"

using namespace voxplore;
using namespace voxplore::exploration;

namespace
{
// 6 x 4 m room with a 1.8 m doorway east, unknown beyond (as in Planner_unittest).
octomap::OcTree doorRoom()
{
  octomap::OcTree t(0.05);
  test::addRoom(t, -3.0, 3.0, -2.0, 2.0);
  test::setColumns(t, 3.0, 3.05, -0.9, 0.9, false);
  t.updateInnerOccupancy();
  return t;
}

PlanInputs someInputs()
{
  PlanInputs in;
  in.robot = mrpt::poses::CPose2D(-1.5, 0.1, 0.3);
  in.step = 7;
  in.blacklist = {{-2.5, 1.5}};
  in.sensed_obstacles = {{0.1234567890123, -0.5}};
  in.low_obstacles = {{0.425, -0.275}, {-0.025, 0.975}};
  in.approach = {{2.0, 1.0}, {1.0, -1.0}};
  in.swept = {{-2.0, 0.0, 0.0}, {-1.75, 0.05, 0.1}, {-1.5, 0.1, 0.3}};
  in.region = {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}};
  return in;
}
}  // namespace

TEST(PlanInputs, RoundTripExactlyWithTheMapsLogOdds)
{
  const auto V = doorRoom();
  const PlanInputs in = someInputs();
  const auto path = test::tempPath("step_008.txt");
  writePlanInputs(path, in, V);
  std::unique_ptr<octomap::OcTree> V2;
  const PlanInputs back = readPlanInputs(path, V2);
  EXPECT_EQ(back.robot, in.robot);
  EXPECT_EQ(back.step, in.step);
  EXPECT_EQ(back.blacklist, in.blacklist);
  EXPECT_EQ(back.sensed_obstacles, in.sensed_obstacles);
  EXPECT_EQ(back.low_obstacles, in.low_obstacles);
  EXPECT_EQ(back.approach, in.approach);
  EXPECT_EQ(back.swept, in.swept);
  EXPECT_EQ(back.region, in.region);
  ASSERT_TRUE(V2);
  EXPECT_EQ(V2->size(), V.size());
  const auto* n = V2->search(0.0, 0.0, 0.3);
  ASSERT_NE(n, nullptr);
  EXPECT_FLOAT_EQ(n->getLogOdds(), V.search(0.0, 0.0, 0.3)->getLogOdds());
}

TEST(PlanInputs, TheSameInputsPlanTheSameStepAgain)
{
  const auto V = doorRoom();
  PlanInputs in = someInputs();
  in.region.clear();
  in.blacklist.clear();
  in.approach.clear();
  PlannerParams p;
  p.collision.r_coll_m = 0.4;
  p.collision.model = CollisionParams::Model::Circle;  // the thesis' disc
  // Low obstacles (a sill) across a fifth of the door: the run planned with them,
  // and voxplore-plan must do the same.
  in.low_obstacles.clear();
  for (double y = -0.875; y < -0.5; y += 0.05) in.low_obstacles.emplace_back(2.975, y);
  const auto without = plan(V, in.robot, p, in.blacklist, in.step, in.swept, in.sensed_obstacles,
                            in.approach);
  const auto direct = plan(V, in.robot, p, in.blacklist, in.step, in.swept, in.sensed_obstacles,
                           in.approach, in.low_obstacles);
  ASSERT_TRUE(direct.ok()) << direct.message;
  ASSERT_TRUE(without.ok()) << without.message;
  ASSERT_NE(direct.waypoints, without.waypoints) << "the sill should change the plan";
  // The sill's cell beside the jamb stays as V has it (a wall base leaking
  // into the cell in front of it looks the same); the others are Occupied.
  const auto stateAt = [&](double x, double y)
  {
    Cell c;
    EXPECT_TRUE(cellOf(direct.ground->state, Eigen::Vector2d(x, y), c));
    return *direct.ground->state.cellByIndex(c.cx, c.cy);
  };
  EXPECT_EQ(stateAt(3.025, -0.925), GroundState::Occupied) << "the jamb";
  EXPECT_NE(stateAt(2.975, -0.875), GroundState::Occupied);
  EXPECT_EQ(stateAt(2.975, -0.825), GroundState::Occupied);
  EXPECT_EQ(stateAt(2.975, -0.525), GroundState::Occupied);

  const auto dir = test::tempPath("plan_run");
  std::filesystem::create_directories(dir);
  const std::string inputs = dir + "/step_008.txt", ini = dir + "/params.ini";
  writePlanInputs(inputs, in, V);
  mrpt::config::CConfigFileMemory m;
  p.save(m);
  std::ofstream(ini) << m.getContent();
  apps::PlanOptions o;
  o.inputs = inputs;
  o.config = ini;
  o.png = dir + "/step.png";
  o.probes = {{in.robot.x(), in.robot.y(), 0.0}, {1e4, 0.0, 0.0}};
  o.probe_radius = 2;
  std::ostringstream report;
  const auto again = apps::PlanApp{}.execute(o, report);
  ASSERT_TRUE(again.ok()) << report.str();
  EXPECT_EQ(again.target, direct.target);
  EXPECT_EQ(again.waypoints, direct.waypoints);
  EXPECT_TRUE(std::filesystem::exists(o.png));
  EXPECT_NE(report.str().find("chosen"), std::string::npos) << report.str();
  EXPECT_NE(report.str().find("known floor cut off"), std::string::npos) << report.str();
  // The probe at the robot: 5 rows of G | collision space, the robot's cell
  // (free, its collision state Free in the circle model) in the middle.
  EXPECT_NE(report.str().find("outside the grid"), std::string::npos) << report.str();
  const auto at = report.str().find("G | collision space");
  ASSERT_NE(at, std::string::npos) << report.str();
  std::istringstream rows(report.str().substr(report.str().find('\n', at) + 1));
  std::string row;
  for (int k = 0; k < 3; ++k) std::getline(rows, row);
  EXPECT_EQ(row, "  ..*.. | ..*..") << report.str();
}

TEST(PlanInputs, BadFilesAreRefusedNamingTheFileAndLine)
{
  const auto V = doorRoom();
  const auto path = test::tempPath("bad_step.txt");
  writePlanInputs(path, someInputs(), V);
  std::unique_ptr<octomap::OcTree> out;
  const auto expectError = [&](const std::string& text, const std::string& part)
  {
    std::ofstream(path) << text;
    try
    {
      readPlanInputs(path, out);
      ADD_FAILURE() << "accepted: " << text;
    }
    catch (const std::runtime_error& e)
    {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectError("robot 1 2 0\nxx 1 2\n", path + ":2: unknown tag 'xx'");
  expectError("robot 1 2 0\nbl 1\n", path + ":2: expected two numbers");
  expectError("robot 1 2\n", path + ":1: expected three numbers");
  expectError("robot 1 2 0 9\n", "trailing '9'");
  expectError("bl 1 2\n", "no 'robot x y yaw' line");
  std::filesystem::remove(path + ".ot");
  expectError("robot 1 2 0\n", "cannot read the map '" + path + ".ot'");
  EXPECT_THROW(readPlanInputs(test::tempPath("missing.txt"), out), std::runtime_error);
}
