// Navigation: the holonomic command model, the [navigation] parameters, and
// StopAndScanDriver (MRPT's reactive navigator) driving an ideal robot and
// the simulated omniRob / compact robot through dlr_test_room.world.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/nav/reactive/CLogFileRecord.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/apps/SimRobot.h>
#include <voxplore/common/config.h>
#include <voxplore/navigation/StopAndScanDriver.h>
#include <voxplore/navigation/holo_ramp.h>
#include <voxplore/sim/SimConfig.h>
#include <voxplore/sim/world_loading.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "FootprintGuard.h"  // libs/navigation/src (internal)
#include "test_worlds.h"

using namespace voxplore;
using Eigen::Vector2d;
using navigation::DriveOutcome;
using navigation::DriverParams;
using navigation::StopAndScanDriver;

namespace
{
// ---------------------------------------------------------------------------
// An ideal omnidirectional robot in free space with its own simulated clock.
class IdealRobot : public navigation::RobotInterface
{
 public:
  explicit IdealRobot(double t0_s = 1.0e9) : t_s_(t0_s), previous_(mrpt::Clock::getActiveClock())
  {
    mrpt::Clock::setSimulatedTime(now());
    mrpt::Clock::setActiveClock(mrpt::Clock::Simulated);
  }
  ~IdealRobot() override { mrpt::Clock::setActiveClock(previous_); }
  void setVelocity(double vx, double vy, double w) override { v_ = {vx, vy, w}; }
  void stop() override { v_ = {0, 0, 0}; }
  mrpt::poses::CPose2D pose() const override { return pose_; }
  mrpt::poses::CPose2D odometry() const override { return pose_; }
  mrpt::math::TTwist2D velocity() const override { return v_; }
  bool obstacles(mrpt::maps::CSimplePointsMap& out) override
  {
    out.clear();
    return sensors_ok;
  }
  mrpt::Clock::time_point now() const override { return mrpt::Clock::fromDouble(t_s_); }
  void step(double dt) override
  {
    const double mid = pose_.phi() + 0.5 * v_.omega * dt;
    const mrpt::poses::CPose2D next(
        pose_.x() + (std::cos(mid) * v_.vx - std::sin(mid) * v_.vy) * dt,
        pose_.y() + (std::sin(mid) * v_.vx + std::cos(mid) * v_.vy) * dt,
        mrpt::math::wrapToPi(pose_.phi() + v_.omega * dt));
    if (next.x() > invisible_wall_x)
      bumps_++;  // refused, like sim::OmniRobot
    else
      pose_ = next;
    t_s_ += dt;
    if (advance_mrpt_clock) mrpt::Clock::setSimulatedTime(now());
  }
  std::optional<std::size_t> collisionCount() const override { return bumps_; }

  bool sensors_ok = true;
  bool advance_mrpt_clock = true;
  double invisible_wall_x = 1e9;  ///< an obstacle the sensors miss: only the bumper finds it

 private:
  double t_s_;
  mrpt::Clock::Source previous_;
  mrpt::poses::CPose2D pose_{0, 0, 0};
  mrpt::math::TTwist2D v_{0, 0, 0};
  std::size_t bumps_ = 0;
};

// ---------------------------------------------------------------------------
// dlr_test_room with the simulated robot behind RobotInterface.
std::string testRoom()
{
  return test::sourceDir() + "/simulated_worlds/dlr_test_room.world";
}

struct SimRig
{
  sim::SimConfig cfg;
  std::unique_ptr<sim::Simulator> sim;
  std::unique_ptr<apps::SimRobot> robot;
  std::unique_ptr<StopAndScanDriver> driver;

  explicit SimRig(const std::string& profile, const std::string& world = testRoom(),
                  const std::optional<mrpt::poses::CPose2D>& start = std::nullopt,
                  std::optional<double> shape_margin_m = std::nullopt,
                  const std::function<void(DriverParams&)>& tweak = {})
  {
    cfg = sim::SimConfig::defaults(profile);
    sim = std::make_unique<sim::Simulator>(sim::loadWorld(world, start), cfg.robot, cfg.cameras,
                                           cfg.sim);
    robot = std::make_unique<apps::SimRobot>(*sim);
    auto p = DriverParams::forFootprint(cfg.robot.length_m, cfg.robot.width_m);
    if (shape_margin_m) p.shape_margin_m = *shape_margin_m;
    p.max_v_mps = cfg.robot.max_v_mps;
    p.max_w = cfg.robot.max_w;
    if (tweak) tweak(p);
    driver = std::make_unique<StopAndScanDriver>(*robot, p);
  }
  std::size_t collisions() const { return sim->robot().collisions(); }
};

// A lap round the meeting table (group x 3.8..6.2, y 2.875..5.125) from the
// start (2, 4): down the west side, east along y = 1.45, up between the two
// furniture groups at x = 7.2, west along y = 6.55, back to the start.
// Every waypoint keeps >= 0.95 m from all obstacles, segments <= 1 m.
std::vector<Vector2d> lapRoundMeetingTable()
{
  std::vector<Vector2d> wps = {{2.0, 3.0}, {2.0, 2.0}, {2.7, 1.45}};
  for (double x = 3.7; x <= 6.75; x += 1.0) wps.emplace_back(x, 1.45);
  for (double y = 2.4; y <= 6.45; y += 1.0) wps.emplace_back(7.2, y);
  wps.emplace_back(7.2, 6.55);
  for (double x = 6.2; x >= 2.15; x -= 1.0) wps.emplace_back(x, 6.55);
  wps.emplace_back(2.0, 5.7);
  wps.emplace_back(2.0, 4.8);
  wps.emplace_back(2.0, 4.0);
  return wps;
}

struct LapStats
{
  std::size_t reached = 0;
  double worst_error_m = 0, mean_error_m = 0, distance_m = 0, sim_time_s = 0, wall_time_s = 0;
  mrpt::poses::CPose2D final_pose;
};

LapStats driveLap(SimRig& rig, const std::vector<Vector2d>& wps)
{
  LapStats s;
  mrpt::system::CTicTac wall;
  for (const auto& wp : wps)
  {
    const auto r = rig.driver->driveTo(wp, std::nullopt);
    EXPECT_EQ(r.outcome, DriveOutcome::Reached)
        << "waypoint (" << wp.transpose() << "): " << r.message << " at " << r.final_pose;
    s.reached += r.reached();
    s.worst_error_m = std::max(s.worst_error_m, r.goal_distance_m);
    s.mean_error_m += r.goal_distance_m / static_cast<double>(wps.size());
    s.distance_m += r.distance_m;
    s.sim_time_s += r.sim_time_s;
  }
  s.wall_time_s = wall.Tac();
  s.final_pose = rig.sim->robot().groundTruth();
  return s;
}

void expectStandsStill(SimRig& rig)
{
  const auto before = rig.sim->robot().groundTruth();
  const auto v = rig.robot->velocity();
  EXPECT_EQ(v.vx, 0.0);
  EXPECT_EQ(v.vy, 0.0);
  EXPECT_EQ(v.omega, 0.0);
  for (int i = 0; i < 10; i++) rig.robot->step(0.1);
  const auto after = rig.sim->robot().groundTruth();
  EXPECT_EQ(before.x(), after.x());
  EXPECT_EQ(before.y(), after.y());
  EXPECT_EQ(before.phi(), after.phi());
}
}  // namespace

// ---------------------------------------------------------------------------
TEST(HoloRamp, BlendsMapFrameVelocityAndTurnsTowardsTheTravelDirection)
{
  // From standstill at yaw 0: 0.5 m/s towards +Y (dir_local = 90 deg), 1 s ramp.
  const mrpt::kinematics::CVehicleVelCmd_Holo cmd(0.5, M_PI / 2, 1.0, mrpt::DEG2RAD(40.0));
  const auto ramp = navigation::startHoloRamp(cmd, 10.0, 0.0, {0, 0, 0});
  EXPECT_NEAR(ramp.dir_rad, M_PI / 2, 1e-12);
  // Middle of [10.4, 10.6]: half the target velocity, still facing +X.
  const auto a = navigation::holoTwistAt(ramp, 10.4, 0.2, 0.0);
  EXPECT_NEAR(std::hypot(a.vx, a.vy), 0.25, 1e-9);
  EXPECT_GT(a.omega, 0.0);  // turning left towards +Y
  // After the ramp, facing +Y: all the velocity is "forward" in the robot frame.
  const auto b = navigation::holoTwistAt(ramp, 20.0, 0.1, M_PI / 2);
  EXPECT_NEAR(b.vx, 0.5, 1e-9);
  EXPECT_NEAR(b.vy, 0.0, 1e-9);
  EXPECT_EQ(b.omega, 0.0);  // aligned: no turn
  // 5 deg short of the direction with a 0.5 s step: the turn rate is cut to
  // reach it, never overshoot it.
  const auto c = navigation::holoTwistAt(ramp, 20.0, 0.5, M_PI / 2 - mrpt::DEG2RAD(5.0));
  EXPECT_NEAR(c.omega * 0.5, mrpt::DEG2RAD(5.0), 1e-9);
  // The stop ramp stands still.
  const auto d = navigation::holoTwistAt(navigation::stoppedHoloRamp(0.0), 1.0, 0.1, 0.3);
  EXPECT_EQ(d.vx, 0.0);
  EXPECT_EQ(d.vy, 0.0);
  EXPECT_EQ(d.omega, 0.0);
}

TEST(DriverParams, SaveLoadRoundTripAndBadValuesNameTheKey)
{
  DriverParams p = DriverParams::forFootprint(0.5, 0.36);
  p.max_v_mps = 0.3;
  p.max_w = mrpt::DEG2RAD(30.0);
  p.holonomic_method = "CHolonomicFullEval";
  mrpt::config::CConfigFileMemory m;
  p.saveToConfigFile(m, "navigation");
  DriverParams back;
  common::loadChecked(back, m, "navigation");
  mrpt::config::CConfigFileMemory m2;
  back.saveToConfigFile(m2, "navigation");
  EXPECT_EQ(m.getContent(), m2.getContent());
  EXPECT_NEAR(back.max_w, mrpt::DEG2RAD(30.0), 1e-12);

  auto errorOf = [](const std::string& text)
  {
    mrpt::config::CConfigFileMemory c(text);
    DriverParams q;
    try
    {
      common::loadChecked(q, c, "navigation");
    }
    catch (const std::exception& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(errorOf("[navigation]\nmax_v_mpss = 1\n").find("max_v_mpss"), std::string::npos);
  EXPECT_NE(errorOf("[navigation]\nholonomic_method = CHolonomicVFF\n").find("holonomic_method"),
            std::string::npos);
  EXPECT_NE(errorOf("[navigation]\nref_distance_m = 0.5\n").find("ref_distance_m"),
            std::string::npos);
  EXPECT_EQ(errorOf("[navigation]\nmax_v_mps = 0.8\n"), "");
}

TEST(DriverParams, MrptConfigHasEveryKeyMrptThrowsOn)
{
  mrpt::config::CConfigFileMemory c;
  DriverParams().writeMrptConfig(c);
  const std::vector<std::pair<std::string, std::string>> required = {
      {"CAbstractPTGBasedReactive", "holonomic_method"},
      {"CAbstractPTGBasedReactive", "motion_decider_method"},
      {"CAbstractPTGBasedReactive", "ref_distance"},
      {"CAbstractPTGBasedReactive", "robotMax_V_mps"},
      {"CAbstractPTGBasedReactive", "robotMax_W_degps"},
      {"CHolonomicND", "factorWeights"},
      {"CMultiObjMotionOpt_Scalarization", "scalar_score_formula"},
      {"CReactiveNavigationSystem", "min_obstacles_height"},
      {"CReactiveNavigationSystem", "max_obstacles_height"},
      {"CReactiveNavigationSystem", "PTG_COUNT"},
      {"CReactiveNavigationSystem", "PTG0_Type"},
      {"CReactiveNavigationSystem", "PTG0_num_paths"},
      {"CReactiveNavigationSystem", "PTG0_refDistance"},
      {"CReactiveNavigationSystem", "PTG0_T_ramp_max"},
      {"CReactiveNavigationSystem", "PTG0_v_max_mps"},
      {"CReactiveNavigationSystem", "PTG0_w_max_dps"},
      {"CReactiveNavigationSystem", "RobotModel_circular_shape_radius"}};
  for (const auto& [sec, key] : required) EXPECT_TRUE(c.keyExists(sec, key)) << sec << " " << key;
  EXPECT_NEAR(c.read_double("CReactiveNavigationSystem", "RobotModel_circular_shape_radius", 0),
              std::hypot(0.6, 0.356) + 0.05, 1e-6);
}

TEST(DriverParams, NavigationIniHoldsTheDefaults)
{
  const auto cfg = common::openIniFile(test::sourceDir() + "/config/navigation.ini");
  EXPECT_NO_THROW(common::assertKnownSections(*cfg, {"navigation"}));
  DriverParams loaded;
  common::loadChecked(loaded, *cfg, "navigation");
  mrpt::config::CConfigFileMemory a, b;
  loaded.saveToConfigFile(a, "navigation");
  DriverParams().saveToConfigFile(b, "navigation");
  EXPECT_EQ(a.getContent(), b.getContent());
}

// ---------------------------------------------------------------------------
TEST(StopAndScanDriver, IdealRobotReachesPointsInFreeSpaceAndTurnsToTheYaw)
{
  IdealRobot robot;
  DriverParams p;
  StopAndScanDriver driver(robot, p);
  const std::vector<std::pair<Vector2d, double>> goals = {
      {{1.0, 0.0}, 0.0}, {{1.0, 1.0}, M_PI / 2}, {{0.3, 1.7}, -2.5}, {{0.0, 0.0}, 0.0}};
  for (const auto& [g, yaw] : goals)
  {
    const auto r = driver.driveTo(g, yaw);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
    EXPECT_LE(r.goal_distance_m, p.goal_tolerance_m);
    EXPECT_LE(std::abs(mrpt::math::wrapToPi(r.final_pose.phi() - yaw)), p.yaw_tolerance);
    EXPECT_GT(r.distance_m, 0.5);
    EXPECT_GT(r.sim_time_s, 0.0);
  }
}

TEST(StopAndScanDriver, SensorFailureIsAnErrorAndStops)
{
  IdealRobot robot;
  StopAndScanDriver driver(robot, DriverParams());
  robot.sensors_ok = false;
  const auto r = driver.driveTo({2.0, 0.0}, std::nullopt);
  EXPECT_EQ(r.outcome, DriveOutcome::Error) << r.message;
  EXPECT_EQ(robot.velocity().vx, 0.0);
  EXPECT_EQ(robot.velocity().vy, 0.0);
}

TEST(StopAndScanDriver, BumperCollisionIsAnErrorAndStops)
{
  IdealRobot robot;
  robot.invisible_wall_x = 0.6;
  StopAndScanDriver driver(robot, DriverParams());
  const auto r = driver.driveTo({1.5, 0.0}, 0.5);
  EXPECT_EQ(r.outcome, DriveOutcome::Error) << r.message;
  EXPECT_NE(r.message.find("collision"), std::string::npos) << r.message;
  EXPECT_EQ(r.collisions, 1u);
  EXPECT_LE(r.final_pose.x(), 0.6);
  EXPECT_EQ(robot.velocity().vx, 0.0);
  EXPECT_EQ(robot.velocity().omega, 0.0);
}

TEST(StopAndScanDriver, ThrowsWhenTheRobotClockIsNotMrptsClock)
{
  IdealRobot robot;
  StopAndScanDriver driver(robot, DriverParams());
  robot.advance_mrpt_clock = false;
  for (int i = 0; i < 30; i++) robot.step(0.1);
  EXPECT_THROW(driver.driveTo({1.0, 0.0}, std::nullopt), std::runtime_error);
}

TEST(StopAndScanDriver, HardStepLimitEndsTheDrive)
{
  IdealRobot robot;
  DriverParams p;
  p.max_steps = 40;
  StopAndScanDriver driver(robot, p);
  const auto r = driver.driveTo({30.0, 0.0}, M_PI);
  EXPECT_EQ(r.outcome, DriveOutcome::Timeout) << r.message;
  EXPECT_EQ(r.steps, 40u);  // no rotation after a failed drive
  EXPECT_EQ(robot.velocity().vx, 0.0);
}

// ---------------------------------------------------------------------------
TEST(SimRobot, FanSeesTheWallsOwnsTheClockAndTakesAPoseSource)
{
  // 6 x 4 x 2.5 m box room, robot in the middle turned by 30 deg.
  const mrpt::poses::CPose2D start(3.0, 2.0, mrpt::DEG2RAD(30.0));
  const auto cfg = sim::SimConfig::defaults("omnirob");
  sim::Simulator sim(test::boxRoom(6, 4, 2.5, start), cfg.robot, cfg.cameras, cfg.sim);
  apps::SimObstacleSensor sensor;
  sensor.heights_m = {0.2, 0.4};
  sensor.rays_per_layer = 360;
  apps::SimRobot robot(sim, sensor);
  EXPECT_EQ(mrpt::Clock::getActiveClock(), mrpt::Clock::Simulated);
  EXPECT_EQ(mrpt::Clock::now(), sim.now());

  mrpt::maps::CSimplePointsMap pts;
  ASSERT_TRUE(robot.obstacles(pts));
  ASSERT_EQ(pts.size(), 720u);  // every ray hits a wall
  std::size_t off_layer = 0;
  double worst_m = 0;
  for (std::size_t i = 0; i < pts.size(); i++)
  {
    mrpt::math::TPoint3D p_robot;
    pts.getPoint(i, p_robot);
    off_layer += std::abs(p_robot.z - 0.2) > 1e-6 && std::abs(p_robot.z - 0.4) > 1e-6;
    double wx, wy;
    start.composePoint(p_robot.x, p_robot.y, wx, wy);  // robot frame -> world
    worst_m = std::max(worst_m, test::distanceToBoxRoom({wx, wy, p_robot.z}, 6, 4, 2.5));
  }
  EXPECT_EQ(off_layer, 0u);
  EXPECT_LT(worst_m, 1e-3);  // every point on a wall

  // step(): integrates the command, advances MRPT's clock; rejects odd dt.
  robot.setVelocity(0.2, 0.0, 0.0);
  robot.step(0.5);
  EXPECT_NEAR(sim.simTime(), 0.5, 1e-9);
  EXPECT_EQ(mrpt::Clock::now(), sim.now());
  EXPECT_GT(robot.odometry().x(), 0.05);
  EXPECT_THROW(robot.step(0.07), std::invalid_argument);

  // The pose source: ground truth by default, replaceable.
  EXPECT_EQ(robot.pose().x(), sim.robot().groundTruth().x());
  robot.setPoseSource([] { return mrpt::poses::CPose2D(1, 2, 3); });
  EXPECT_EQ(robot.pose().y(), 2.0);
  robot.setPoseSource({});
  EXPECT_EQ(robot.pose().y(), sim.robot().groundTruth().y());

  // Standing scans move the simulator's clock on, and MRPT's with it: 25 in
  // a row (drives that failed before their first step) left it 1.25 s
  // behind, and the driver's clock check ended the run.
  robot.stop();
  apps::SimScanSource scans(sim, &robot);
  const double before = sim.simTime();
  for (int i = 0; i < 25; ++i) scans.scan();
  EXPECT_GT(sim.simTime(), before + 1.0);
  EXPECT_EQ(mrpt::Clock::now(), sim.now());
}

TEST(StopAndScanDriver, OmnirobDrivesALapRoundTheMeetingTableWithoutCollision)
{
  SimRig rig("omnirob");
  const auto wps = lapRoundMeetingTable();
  const LapStats s = driveLap(rig, wps);
  EXPECT_EQ(s.reached, wps.size());
  EXPECT_LE(s.worst_error_m, rig.driver->params().goal_tolerance_m);
  EXPECT_EQ(rig.collisions(), 0u);
  EXPECT_GT(s.distance_m, 15.0);
  std::cout << "[ omnirob lap ] " << wps.size() << " waypoints, " << s.distance_m << " m in "
            << s.sim_time_s << " s simulated, " << s.wall_time_s << " s real ("
            << 1e3 * s.wall_time_s / s.distance_m << " ms real per simulated metre), reach error "
            << "mean " << s.mean_error_m << " m, worst " << s.worst_error_m << " m" << std::endl;
}

// scan_mode = continuous: the same lap through its waypoints without
// stopping (passBy), stopping at the last one only.
TEST(StopAndScanDriver, APassedLapKeepsMovingThroughItsWaypointsAndTakesLessTime)
{
  const auto wps = lapRoundMeetingTable();
  SimRig stopping("omnirob");
  const LapStats stop = driveLap(stopping, wps);
  SimRig passing("omnirob");
  const double tol = 0.15;
  double sim_time_s = 0, distance_m = 0;
  std::size_t passed = 0;
  for (std::size_t i = 0; i < wps.size(); i++)
  {
    const bool last = i + 1 == wps.size();
    const auto r = last ? passing.driver->driveTo(wps[i], std::nullopt)
                        : passing.driver->passBy(wps[i], tol);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached)
        << "waypoint " << i << " (" << wps[i].transpose() << "): " << r.message;
    sim_time_s += r.sim_time_s;
    distance_m += r.distance_m;
    const auto v = passing.robot->velocity();
    if (!last)
    {
      // Passed within the tolerance (and a step's travel: MRPT judges the
      // segment the robot moved), still moving.
      EXPECT_LE(r.goal_distance_m, tol + 0.5 * passing.driver->params().dt_s) << "waypoint " << i;
      passed += std::hypot(v.vx, v.vy) > 0.1;
    }
    else
    {
      EXPECT_LE(r.goal_distance_m, passing.driver->params().goal_tolerance_m);
      EXPECT_EQ(std::hypot(v.vx, v.vy), 0.0);
    }
  }
  EXPECT_EQ(passed, wps.size() - 1);
  EXPECT_EQ(passing.collisions(), 0u);
  EXPECT_GT(distance_m, 15.0);
  // Near full speed all the way (the last waypoint slows down), where
  // stopping at each waypoint costs a slow-down and a ramp-up each.
  EXPECT_LT(sim_time_s, 1.1 * distance_m / passing.driver->params().max_v_mps);
  EXPECT_LT(sim_time_s, 0.9 * stop.sim_time_s);
  std::cout << "[ omnirob lap ] stopping at every waypoint " << stop.sim_time_s << " s, "
            << stop.distance_m << " m; passing them " << sim_time_s << " s, " << distance_m
            << " m" << std::endl;
}

TEST(StopAndScanDriver, PassByRefusesAToleranceOfZero)
{
  IdealRobot robot;
  StopAndScanDriver driver(robot, DriverParams());
  EXPECT_THROW(driver.passBy({1.0, 0.0}, 0.0), std::invalid_argument);
}

TEST(StopAndScanDriver, SameRunTwiceGivesTheSamePoses)
{
  const std::vector<Vector2d> wps = {{2.0, 3.0}, {2.0, 2.0}, {2.7, 1.45}, {3.7, 1.45}};
  std::vector<mrpt::poses::CPose2D> finals;
  for (int run = 0; run < 2; run++)
  {
    SimRig rig("omnirob");
    finals.push_back(driveLap(rig, wps).final_pose);
  }
  EXPECT_EQ(finals[0].x(), finals[1].x());
  EXPECT_EQ(finals[0].y(), finals[1].y());
  EXPECT_EQ(finals[0].phi(), finals[1].phi());
}

TEST(StopAndScanDriver, FinalYawInTheRoom)
{
  SimRig rig("omnirob");
  const auto r = rig.driver->driveTo({2.0, 3.0}, -M_PI / 2);
  ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  EXPECT_LE(std::abs(mrpt::math::wrapToPi(rig.sim->robot().groundTruth().phi() + M_PI / 2)),
            rig.driver->params().yaw_tolerance);
  EXPECT_EQ(rig.collisions(), 0u);
}

// Continuous mode: a camera ring that a half turn maps onto itself sees the
// same from a yaw and its half turn; the last turn goes to the nearer.
TEST(StopAndScanDriver, AFinalYawWithAPeriodTurnsToTheNearestEquivalentYaw)
{
  const double want = mrpt::DEG2RAD(150.0);
  double t[2];
  for (const bool period : {false, true})
  {
    SimRig rig("omnirob");
    const auto r = rig.driver->driveTo({2.0, 3.0}, want, period ? M_PI : 0.0);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
    const double yaw = rig.sim->robot().groundTruth().phi();
    const double off = mrpt::math::wrapToPi(yaw - want);
    // Without: the yaw asked for; with: it or its half turn, whichever the
    // robot was nearer (it drove there at about its start yaw, 90 deg).
    EXPECT_LE(std::abs(period ? mrpt::math::wrapToPi(off - M_PI) : off), rig.driver->params().yaw_tolerance)
        << period << ": yaw " << mrpt::RAD2DEG(yaw);
    EXPECT_EQ(rig.collisions(), 0u);
    t[period] = r.sim_time_s;
  }
  EXPECT_LT(t[1], t[0]);
}

// Continuous mode with turns on the way: a reactive drive told a yaw to face
// turns the robot to it on the way (MRPT's own heading faces the way it
// goes): a pass arrives turned, moving, and a drive that stops there needs
// no turn at its end.
TEST(StopAndScanDriver, AReactiveDriveFacingAYawArrivesTurnedAndSooner)
{
  // From the start (2, 4) south to (2, 2): MRPT's heading turns to -90 deg.
  const double want = 0.0;
  {
    SimRig rig("omnirob");
    const auto r = rig.driver->passBy({2.0, 2.0}, 0.15, want);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
    const double yaw = rig.sim->robot().groundTruth().phi();
    EXPECT_LE(std::abs(mrpt::math::wrapToPi(yaw - want)), mrpt::DEG2RAD(2.0)) << mrpt::RAD2DEG(yaw);
    const auto v = rig.robot->velocity();
    EXPECT_GT(std::hypot(v.vx, v.vy), 0.1);
    EXPECT_EQ(rig.collisions(), 0u);
    // Facing no more once the drive is over: MRPT's own heading again.
    SimRig plain("omnirob");
    const auto q = plain.driver->passBy({2.0, 2.0}, 0.15);
    ASSERT_EQ(q.outcome, DriveOutcome::Reached) << q.message;
    EXPECT_GT(std::abs(mrpt::math::wrapToPi(plain.sim->robot().groundTruth().phi() - want)),
              mrpt::DEG2RAD(45.0));
  }
  double t[2];
  for (const bool face : {false, true})
  {
    SimRig rig("omnirob");
    const auto r = rig.driver->driveTo({2.0, 2.0}, want, 0.0,
                                       face ? std::optional<double>(want) : std::nullopt);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
    EXPECT_LE(std::abs(mrpt::math::wrapToPi(rig.sim->robot().groundTruth().phi() - want)),
              rig.driver->params().yaw_tolerance);
    EXPECT_LE(r.goal_distance_m, rig.driver->params().goal_tolerance_m);
    EXPECT_EQ(rig.collisions(), 0u);
    t[face] = r.sim_time_s;
  }
  std::cout << "[ facing ] to (2, 2), then 0 deg: " << t[0] << " s; facing 0 deg on the way: "
            << t[1] << " s" << std::endl;
  EXPECT_LT(t[1], t[0] - 1.0);
}

TEST(StopAndScanDriver, UnreachableWaypointsEndBlockedWithoutCollision)
{
  // Inside the cabinet against the south wall, and behind the south wall.
  for (const Vector2d& wp : {Vector2d(5.0, 0.25), Vector2d(2.0, -1.0)})
  {
    SCOPED_TRACE(wp.transpose());
    SimRig rig("omnirob");
    rig.driver->driveTo({2.0, 2.0}, std::nullopt);
    const auto r = rig.driver->driveTo(wp, std::nullopt);
    std::cout << "[ unreachable ] (" << wp.transpose() << "): " << toString(r.outcome) << " after "
              << r.sim_time_s << " s, " << r.goal_distance_m << " m short: " << r.message
              << std::endl;
    EXPECT_NE(r.outcome, DriveOutcome::Reached);
    EXPECT_LE(r.sim_time_s, rig.driver->params().timeout_s + 1.0);
    EXPECT_EQ(rig.collisions(), 0u);
    expectStandsStill(rig);
  }
}

TEST(StopAndScanDriver, CompactRobotDrivesTheLapAndCloseToTheWall)
{
  SimRig rig("compact");
  auto wps = lapRoundMeetingTable();
  // 0.5 m from the east wall: out of reach for the omniRob's 0.75 m circle.
  // Detour along the north passage past the desks, after (7.2, 6.55).
  wps.insert(wps.begin() + 13, {{7.9, 6.2},
                                {8.9, 6.3},
                                {9.9, 6.3},
                                {10.8, 6.0},
                                {11.5, 5.5},
                                {10.8, 6.0},
                                {9.9, 6.3},
                                {8.9, 6.3},
                                {7.9, 6.3},
                                {7.2, 6.55}});
  const LapStats s = driveLap(rig, wps);
  EXPECT_EQ(s.reached, wps.size());
  EXPECT_LE(s.worst_error_m, rig.driver->params().goal_tolerance_m);
  EXPECT_EQ(rig.collisions(), 0u);
  std::cout << "[ compact lap ] " << wps.size() << " waypoints, " << s.distance_m << " m in "
            << s.sim_time_s << " s simulated, " << s.wall_time_s << " s real ("
            << 1e3 * s.wall_time_s / s.distance_m << " ms real per simulated metre), reach error "
            << "mean " << s.mean_error_m << " m, worst " << s.worst_error_m << " m" << std::endl;
}

TEST(StopAndScanDriver, OmnirobReachesWaypointsAtThePlannersClearance)
{
  // The planner keeps r_coll + sqrt(2) l_res = 0.698 + 0.071 = 0.77 m from
  // obstacles; these waypoints are 0.77 m from the cabinet, the west wall and
  // the shelf (the navigator's circle: 0.748 m, stop gap 0.06 m, tolerance 0.05 m).
  SimRig rig("omnirob");
  const std::vector<Vector2d> wps = {{2.0, 3.0},  {2.5, 2.0}, {3.5, 1.27}, {4.5, 1.27}, {5.5, 1.27},
                                     {5.6, 2.0},  {4.6, 1.6}, {3.2, 2.3},  {2.2, 3.0},  {0.77, 3.0},
                                     {0.77, 5.0}, {1.5, 5.9}, {1.8, 6.73}};
  const LapStats s = driveLap(rig, wps);
  EXPECT_EQ(s.reached, wps.size());
  EXPECT_EQ(rig.collisions(), 0u);
}

// ---------------------------------------------------------------------------
// Two 4 x 4 m rooms joined by a 5 m corridor 1.1 m wide (walls 0.15 m thick):
// the passages of turtlebot3_house, where MRPT's CHolonomicND stalled.
std::string corridorWorld()
{
  const std::string path = test::tempPath("corridor_1m1.world");
  std::ofstream f(path);
  f << R"({"name": "corridor_1m1", "start": {"x": 2.0, "y": 2.0, "yaw_deg": 0},
  "elements": [
    {"type": "wall", "from": [0, 0], "to": [4, 0]}, {"type": "wall", "from": [0, 4], "to": [4, 4]},
    {"type": "wall", "from": [0, 0], "to": [0, 4]},
    {"type": "wall", "from": [4, 0], "to": [4, 1.375]}, {"type": "wall", "from": [4, 2.625], "to": [4, 4]},
    {"type": "wall", "from": [4, 1.375], "to": [9, 1.375]}, {"type": "wall", "from": [4, 2.625], "to": [9, 2.625]},
    {"type": "wall", "from": [9, 0], "to": [9, 1.375]}, {"type": "wall", "from": [9, 2.625], "to": [9, 4]},
    {"type": "wall", "from": [9, 0], "to": [13, 0]}, {"type": "wall", "from": [9, 4], "to": [13, 4]},
    {"type": "wall", "from": [13, 0], "to": [13, 4]}]})";
  return path;
}

TEST(StopAndScanDriver, CompactRobotDrivesThroughA1m1CorridorAndBack)
{
  // shape_margin_m 0 as in config/explore.ini: the navigator's circle is the
  // footprint's circumcircle (0.308 m); 0.095 m to each wall in the corridor.
  SimRig rig("compact", corridorWorld(), std::nullopt, 0.0);
  std::vector<Vector2d> wps;
  for (double x = 3.0; x <= 10.01; x += 1.0) wps.emplace_back(x, 2.0);
  for (double x = 9.0; x >= 2.99; x -= 1.0) wps.emplace_back(x, 2.0);
  const LapStats s = driveLap(rig, wps);
  EXPECT_EQ(s.reached, wps.size());
  EXPECT_EQ(rig.collisions(), 0u);
  EXPECT_NEAR(s.final_pose.x(), 3.0, 0.1);
}

TEST(StopAndScanDriver, StraightFallbackStopsBeforeAnObstacleOnTheWay)
{
  // The way east from (2, 0.8) runs into the room's east wall (x = 4 - 0.075):
  // the straight drive checks the whole way still to go and does not start.
  SimRig rig("compact", corridorWorld(), mrpt::poses::CPose2D(2.0, 0.8, 0.0), 0.0);
  const auto r = rig.driver->driveStraight({5.0, 0.8});
  EXPECT_EQ(r.outcome, DriveOutcome::Blocked) << r.message;
  EXPECT_NE(r.message.find("straight way"), std::string::npos) << r.message;
  EXPECT_NEAR(r.final_pose.x(), 2.0, 1e-9);
  EXPECT_LT(r.distance_m, 1e-9);
  EXPECT_EQ(rig.collisions(), 0u);
  // A free way is driven to the end.
  const auto back = rig.driver->driveStraight({2.0, 2.0});
  EXPECT_EQ(back.outcome, DriveOutcome::Reached) << back.message;
}

TEST(StopAndScanDriver, EscapeBacksOffFromAWallAtTheCircle)
{
  // 0.33 m from the west wall's face (x = 0.075): inside robotRadius() +
  // escape_clearance_m = 0.308 + 0.10 m.
  SimRig rig("compact", corridorWorld(), mrpt::poses::CPose2D(0.405, 2.0, 0.0), 0.0);
  const auto r = rig.driver->escape();
  EXPECT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  const auto p = rig.sim->robot().groundTruth();
  EXPECT_GT(p.x() - 0.075, 0.308 + 0.10 - 0.02) << "backed off east, away from the wall";
  EXPECT_NEAR(p.y(), 2.0, 0.05) << "straight away from it";
  EXPECT_EQ(rig.collisions(), 0u);
  // Already clear: nothing to do.
  const auto again = rig.driver->escape();
  EXPECT_EQ(again.outcome, DriveOutcome::Reached);
  EXPECT_LT(again.distance_m, 1e-9);
}

// ------------------------------------------- the footprint guard

TEST(FootprintGuard, ClearanceOfTheRotatedRectangleAndThePoseAfterATwist)
{
  using navigation::detail::poseAfter;
  using navigation::detail::rectangleClearance;
  using P = mrpt::poses::CPose2D;
  const double hl = 0.6, hw = 0.356;  // the omniRob
  EXPECT_NEAR(rectangleClearance({{1.0, 0.0}}, hl, hw, P()), 0.4, 1e-12);
  EXPECT_NEAR(rectangleClearance({{0.7, 0.456}}, hl, hw, P()), std::hypot(0.1, 0.1), 1e-12);
  EXPECT_EQ(rectangleClearance({{0.5, -0.3}, {3.0, 0.0}}, hl, hw, P()), 0.0);  // inside
  EXPECT_NEAR(rectangleClearance({{1.0, 0.0}}, hl, hw, P(0, 0, M_PI / 2)), 1.0 - hw, 1e-12);
  EXPECT_NEAR(rectangleClearance({{1.0, 0.0}, {0.0, -0.5}}, hl, hw, P(0.2, 0, 0)), 0.144, 1e-12);
  EXPECT_TRUE(std::isinf(rectangleClearance({}, hl, hw, P())));
  const P a = poseAfter(0.5, 0.0, 0.0, 0.4);
  EXPECT_NEAR(a.x(), 0.2, 1e-12);
  EXPECT_NEAR(a.y(), 0.0, 1e-12);
  const P b = poseAfter(0.0, 0.0, 0.5, 2.0);  // a turn in place stays in place
  EXPECT_NEAR(b.norm(), 0.0, 1e-12);
  EXPECT_NEAR(b.phi(), 1.0, 1e-12);
}

TEST(StopAndScanDriver, GuardHoldsTheFootprintItsMarginFromAWallTheWaypointIsTooCloseTo)
{
  // Compact robot (0.50 x 0.36 m) facing the room's east wall (face at
  // x = 3.925); the waypoint is 0.35 m from it, outside the navigator's
  // circle (0.308 m): MRPT drives there, the front then 0.10 m from the wall.
  // A guard margin of 0.20 m must stop the front 0.20 m from it, 0.10 m
  // short of the waypoint (the goal tolerance is 0.05 m).
  const mrpt::poses::CPose2D start(2.0, 0.8, 0.0);
  const Vector2d wp(3.925 - 0.35, 0.8);
  {
    SimRig free("compact", corridorWorld(), start, 0.0,
                [](DriverParams& p) { p.footprint_guard = false; });
    const auto r = free.driver->driveTo(wp, std::nullopt);
    EXPECT_EQ(r.outcome, DriveOutcome::Reached) << "control: the unguarded drive gets there; "
                                                << r.message;
  }
  SimRig rig("compact", corridorWorld(), start, 0.0,
             [](DriverParams& p) { p.guard_margin_m = 0.20; });
  const auto r = rig.driver->driveTo(wp, std::nullopt);
  std::cout << "[ guard ] " << toString(r.outcome) << ": " << r.message << std::endl;
  EXPECT_EQ(r.outcome, DriveOutcome::Blocked) << r.message;
  EXPECT_NE(r.message.find("footprint guard"), std::string::npos) << r.message;
  const auto p = rig.sim->robot().groundTruth();
  const double front = p.x() + 0.25 * std::abs(std::cos(p.phi())) + 0.18 * std::abs(std::sin(p.phi()));
  EXPECT_GE(3.925 - front, 0.20 - 0.005) << "the footprint kept the margin";
  EXPECT_LE(3.925 - front, 0.30) << "and got close to it (slowed, not stopped early)";
  EXPECT_EQ(rig.collisions(), 0u);
  EXPECT_GT(rig.driver->guardHeldCommands(), 0u);
  expectStandsStill(rig);
}

// The compact robot driven at full speed straight at the corridor world's
// east wall (face x = 3.925) through the guard alone, on a base that brakes
// at 0.5 m/s^2: the front's least distance to the wall, and the collisions.
std::pair<double, std::size_t> fullSpeedAtTheWall(double guard_knows_accel_mps2)
{
  auto cfg = sim::SimConfig::defaults("compact");
  cfg.robot.max_accel_mps2 = 0.5;
  cfg.robot.max_angular_accel = mrpt::DEG2RAD(90.0);
  sim::Simulator sim(sim::loadWorld(corridorWorld(), mrpt::poses::CPose2D(1.0, 0.8, 0.0)),
                     cfg.robot, cfg.cameras, cfg.sim);
  apps::SimRobot robot(sim);
  navigation::detail::GuardParams g;
  g.length_m = cfg.robot.length_m;
  g.width_m = cfg.robot.width_m;
  g.max_accel_mps2 = guard_knows_accel_mps2;
  g.max_angular_accel = guard_knows_accel_mps2 > 0 ? cfg.robot.max_angular_accel : 0.0;
  navigation::detail::FootprintGuard guard(robot, g);
  double least = 1e9;
  for (int k = 0; k < 100; k++)
  {
    guard.setVelocity(0.5, 0.0, 0.0);
    guard.step(0.1);
    least = std::min(least, 3.925 - (sim.robot().groundTruth().x() + 0.5 * cfg.robot.length_m));
  }
  return {least, sim.robot().collisions()};
}

TEST(FootprintGuard, OnABaseWithAccelerationLimitsItKeepsTheMarginWhileBraking)
{
  // Told the limits, the guard slows the base while it can still brake
  // within its margin (0.03 m) of the wall; a guard that assumes commands
  // are executed at once holds them too late (horizon 0.3 s = 0.15 m at
  // 0.5 m/s, the braking distance 0.25 m) and the base runs on.
  const auto [aware, aware_hits] = fullSpeedAtTheWall(0.5);
  const auto [unaware, unaware_hits] = fullSpeedAtTheWall(0.0);
  std::cout << "[ accel guard ] least front clearance: aware " << aware << " m, unaware "
            << unaware << " m (" << unaware_hits << " refused steps)" << std::endl;
  EXPECT_EQ(aware_hits, 0u);
  EXPECT_GE(aware, 0.03 - 0.005);
  EXPECT_LE(aware, 0.10) << "and it got there (slowed, not stopped early)";
  EXPECT_LT(unaware, 0.02) << "control: without the limits the margin is lost";
}

TEST(StopAndScanDriver, GuardRefusesATurnTheCorridorIsTooNarrowFor)
{
  // The omniRob (1.2 x 0.712 m) lengthwise in the 1.1 m corridor: turning
  // 90 degrees would put its 1.2 m across it. Unguarded, the simulator
  // refuses a step (a collision); guarded, the turn stops at the margin.
  const mrpt::poses::CPose2D start(6.5, 2.0, 0.0);
  {
    SimRig free("omnirob", corridorWorld(), start, 0.0,
                [](DriverParams& p) { p.footprint_guard = false; });
    const auto r = free.driver->rotateTo(M_PI / 2);
    EXPECT_EQ(r.outcome, DriveOutcome::Error) << "control: the unguarded turn hits; " << r.message;
    EXPECT_GT(free.collisions(), 0u);
  }
  SimRig rig("omnirob", corridorWorld(), start, 0.0);
  const auto r = rig.driver->rotateTo(M_PI / 2);
  EXPECT_EQ(r.outcome, DriveOutcome::Blocked) << r.message;
  EXPECT_EQ(rig.collisions(), 0u);
  const double yaw = std::abs(rig.sim->robot().groundTruth().phi());
  const double half_extent_y = 0.6 * std::sin(yaw) + 0.356 * std::cos(yaw);
  EXPECT_GT(yaw, mrpt::DEG2RAD(5.0)) << "it turned as far as the corridor lets it";
  EXPECT_LE(half_extent_y, 0.55 - rig.driver->params().guard_margin_m + 0.005);
  expectStandsStill(rig);
}

TEST(StopAndScanDriver, AWaypointReachedWhereTheFinalTurnIsHeldCountsAsReached)
{
  // The omniRob at its waypoint, centre 0.71 m from the room's south wall
  // (face y = 0.075) and facing it: outside its circumcircle (0.698 m), but
  // a quarter turn sweeps its corners within the guard's 0.03 m. The turn
  // stops at the margin and the drive is no failure (the stop's scan is
  // taken in the yaw it got to).
  const Vector2d wp(2.0, 0.075 + 0.71);
  SimRig rig("omnirob", corridorWorld(), mrpt::poses::CPose2D(wp.x(), wp.y(), -M_PI / 2), 0.0);
  const auto r = rig.driver->driveTo(wp, 0.0);
  std::cout << "[ held turn ] " << toString(r.outcome) << ": " << r.message << std::endl;
  EXPECT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  EXPECT_NE(r.message.find("footprint guard"), std::string::npos) << r.message;
  EXPECT_LE(r.goal_distance_m, rig.driver->params().goal_tolerance_m);
  const double yaw = rig.sim->robot().groundTruth().phi();
  EXPECT_GT(yaw, -M_PI / 2 + mrpt::DEG2RAD(5.0)) << "it turned part of the way";
  const double extent = 0.6 * std::abs(std::sin(yaw)) + 0.356 * std::abs(std::cos(yaw));
  EXPECT_GE(rig.sim->robot().groundTruth().y() - extent - 0.075, 0.03 - 0.005);
  EXPECT_EQ(rig.collisions(), 0u);
  expectStandsStill(rig);
}

// --------------------------------------- the footprint drive (issue 13)

namespace
{
/// Two 4 x 4 m rooms side by side; the wall between them (x = 4, 0.15 m
/// thick) has a door of `door_m` centred on y = 2.
std::string twoRoomsWorld(double door_m)
{
  const std::string path = test::tempPath(mrpt::format("two_rooms_door_%.2f.world", door_m));
  const double lo = 2.0 - 0.5 * door_m, hi = 2.0 + 0.5 * door_m;
  std::ofstream f(path);
  f << mrpt::format(R"({"name": "two_rooms", "start": {"x": 2.0, "y": 2.0, "yaw_deg": 90},
  "elements": [
    {"type": "wall", "from": [0, 0], "to": [8, 0]}, {"type": "wall", "from": [0, 4], "to": [8, 4]},
    {"type": "wall", "from": [0, 0], "to": [0, 4]}, {"type": "wall", "from": [8, 0], "to": [8, 4]},
    {"type": "wall", "from": [4, 0], "to": [4, %.3f]}, {"type": "wall", "from": [4, %.3f], "to": [4, 4]}]})",
                    lo, hi);
  return path;
}

/// A RobotInterface between the driver and the simulated robot that, after
/// every step, records whether the footprint grown by `margin_m` on each
/// side touched the world (the real robot's clearance fell below it).
class ClearanceProbe : public navigation::RobotInterface
{
 public:
  ClearanceProbe(apps::SimRobot& robot, const sim::Simulator& sim, double margin_m)
      : robot_(robot), sim_(sim), margin_m_(margin_m)
  {
  }
  void setVelocity(double vx, double vy, double w) override { robot_.setVelocity(vx, vy, w); }
  void stop() override { robot_.stop(); }
  mrpt::poses::CPose2D pose() const override { return robot_.pose(); }
  mrpt::poses::CPose2D odometry() const override { return robot_.odometry(); }
  mrpt::math::TTwist2D velocity() const override { return robot_.velocity(); }
  bool obstacles(mrpt::maps::CSimplePointsMap& out) override { return robot_.obstacles(out); }
  mrpt::Clock::time_point now() const override { return robot_.now(); }
  std::optional<std::size_t> collisionCount() const override { return robot_.collisionCount(); }
  void step(double dt_s) override
  {
    robot_.step(dt_s);
    const auto& r = sim_.robot();
    const sim::Footprint grown{r.params().length_m + 2 * margin_m_,
                               r.params().width_m + 2 * margin_m_};
    if (sim_.checker().collides(r.groundTruth(), grown)) ++too_close_;
  }
  std::size_t tooClose() const { return too_close_; }

 private:
  apps::SimRobot& robot_;
  const sim::Simulator& sim_;
  double margin_m_;
  std::size_t too_close_ = 0;
};

/// The omniRob in `world` (at `start`, or the world's start) driven through
/// a ClearanceProbe of 2 cm: sim, robot, probe and driver, in that order.
struct ProbedOmniRob
{
  sim::SimConfig cfg = sim::SimConfig::defaults("omnirob");
  sim::Simulator simulator;
  apps::SimRobot robot;
  ClearanceProbe probe;
  StopAndScanDriver driver;

  ProbedOmniRob(const std::string& world, const std::optional<mrpt::poses::CPose2D>& start)
      : simulator(sim::loadWorld(world, start), cfg.robot, cfg.cameras, cfg.sim),
        robot(simulator),
        probe(robot, simulator, 0.02),
        driver(probe, params(cfg))
  {
  }
  static DriverParams params(const sim::SimConfig& c)
  {
    auto p = DriverParams::forFootprint(c.robot.length_m, c.robot.width_m);
    p.max_v_mps = c.robot.max_v_mps;
    p.max_w = c.robot.max_w;
    return p;
  }
};
}  // namespace

// [path] turn_on_the_way_deg (issue 15): a footprint drive whose turn the
// planner checked along the way turns while it translates, in proportion
// to the way made: it reaches the same pose sooner than turning in place
// first, and keeps 2 cm from the world.
TEST(StopAndScanDriver, AFootprintDriveTurnsOnTheWayAndArrivesSooner)
{
  const mrpt::poses::CPose2D start(1.5, 1.5, 0.0);
  const Vector2d wp(3.0, 2.5);
  const double yaw = mrpt::DEG2RAD(60.0);
  double t[2];
  for (const bool on_way : {false, true})
  {
    ProbedOmniRob rig(twoRoomsWorld(0.90), start);
    const auto r = rig.driver.driveFootprint(wp, yaw, std::nullopt, on_way);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << on_way << ": " << r.message;
    const auto gt = rig.simulator.robot().groundTruth();
    EXPECT_LE(std::hypot(gt.x() - wp.x(), gt.y() - wp.y()), rig.driver.params().goal_tolerance_m + 0.02);
    EXPECT_LE(std::abs(mrpt::math::wrapToPi(gt.phi() - yaw)), rig.driver.params().yaw_tolerance + mrpt::DEG2RAD(1.0))
        << on_way;
    EXPECT_EQ(rig.simulator.robot().collisions(), 0u);
    EXPECT_EQ(rig.probe.tooClose(), 0u);
    t[on_way] = r.sim_time_s;
  }
  std::cout << "[ turn on the way ] turning in place first " << t[0] << " s, on the way " << t[1]
            << " s" << std::endl;
  EXPECT_LT(t[1], t[0] - 0.5);
}

// A corner between two footprint drives (scan_mode = continuous, issue 15):
// passed on the waypoint itself at the corner speed, not stopped at and not
// cut (a pass within a tolerance would leave the next drive a way beside the
// planned one).
TEST(StopAndScanDriver, AFootprintPassLandsOnACornerAndGoesOnSooner)
{
  const mrpt::poses::CPose2D start(1.5, 1.5, 0.0);
  const Vector2d corner(2.5, 1.5), end(3.2, 2.2);  // a 45 deg corner: full speed
  constexpr double kTolerance_m = 0.005;
  double t[2];
  for (const bool pass : {false, true})
  {
    ProbedOmniRob rig(twoRoomsWorld(0.90), start);
    auto& driver = rig.driver;
    const auto a = pass ? driver.passFootprint(corner, 0.0, kTolerance_m, false, 0.5)
                        : driver.driveFootprint(corner, 0.0);
    ASSERT_EQ(a.outcome, DriveOutcome::Reached) << pass << ": " << a.message;
    const double off = std::hypot(a.final_pose.x() - corner.x(), a.final_pose.y() - corner.y());
    EXPECT_LE(off, pass ? kTolerance_m : driver.params().goal_tolerance_m) << pass;
    const auto b = driver.driveFootprint(end, 0.0);
    ASSERT_EQ(b.outcome, DriveOutcome::Reached) << pass << ": " << b.message;
    EXPECT_EQ(rig.simulator.robot().collisions(), 0u);
    EXPECT_EQ(rig.probe.tooClose(), 0u);
    t[pass] = a.sim_time_s + b.sim_time_s;
  }
  std::cout << "[ corner ] stopping at it " << t[0] << " s, passing on it " << t[1] << " s"
            << std::endl;
  EXPECT_LT(t[1], t[0] - 0.3);
}

TEST(StopAndScanDriver, TheOmniRobPassesANinetyCentimetreDoorTurnedLengthwise)
{
  // The omniRob starts across the door's axis (yaw 90 deg). The planner's
  // footprint path turns it lengthwise in the room, then drives straight
  // through the 0.9 m door: 9.4 cm to each jamb. The thesis' circle
  // (MRPT's navigator) cannot pass: it is the control.
  const std::string world = twoRoomsWorld(0.90);
  {
    SimRig circle("omnirob", world, std::nullopt, 0.0);
    const auto r = circle.driver->driveTo({6.0, 2.0}, std::nullopt);
    std::cout << "[ circle at a 0.9 m door ] " << toString(r.outcome) << ": " << r.message
              << std::endl;
    EXPECT_NE(r.outcome, DriveOutcome::Reached) << "control: " << r.message;
    EXPECT_LT(circle.sim->robot().groundTruth().x(), 3.5);
    EXPECT_EQ(circle.collisions(), 0u);
  }
  ProbedOmniRob rig(world, std::nullopt);
  auto& driver = rig.driver;
  auto& simulator = rig.simulator;
  auto& probe = rig.probe;
  // The waypoints of the footprint path: turn, then 1 m pieces lengthwise.
  for (const double x : {3.0, 4.0, 5.0, 6.0})
  {
    const auto r = driver.driveFootprint({x, 2.0}, 0.0);
    ASSERT_EQ(r.outcome, DriveOutcome::Reached) << "to x = " << x << ": " << r.message;
  }
  const auto gt = simulator.robot().groundTruth();
  EXPECT_NEAR(gt.x(), 6.0, 0.1);
  EXPECT_LT(std::abs(mrpt::math::wrapToPi(gt.phi())), mrpt::DEG2RAD(3.0));
  EXPECT_EQ(simulator.robot().collisions(), 0u);
  EXPECT_EQ(probe.tooClose(), 0u) << "the footprint came within 2 cm of the world";
}

TEST(StopAndScanDriver, TheFootprintDriveStopsBeforeASeventyCentimetreDoor)
{
  // Sent through a 0.7 m door anyway (the planner refuses it): the drive
  // stops short without touching, the guard or the waypoint check ends it.
  SimRig rig("omnirob", twoRoomsWorld(0.70), mrpt::poses::CPose2D(3.0, 2.0, 0.0), 0.0);
  const auto r = rig.driver->driveFootprint({5.0, 2.0}, 0.0);
  std::cout << "[ 0.7 m door ] " << toString(r.outcome) << ": " << r.message << std::endl;
  EXPECT_EQ(r.outcome, DriveOutcome::Blocked) << r.message;
  EXPECT_EQ(rig.collisions(), 0u);
  EXPECT_LT(rig.sim->robot().groundTruth().x() + 0.6, 4.0 - 0.075) << "its nose stays in the room";
  expectStandsStill(rig);
  EXPECT_TRUE(r.blocking_points.empty()) << "the guard ended it, not the waypoint check";
}

TEST(StopAndScanDriver, AFootprintDriveBlockedAtItsWaypointSaysByWhichPoints)
{
  // A waypoint 0.5 m short of the 0.7 m door: the rectangle there reaches
  // the door posts (its half width 0.356 m, the posts 0.35 m off its axis).
  // The waypoint check ends the drive at once, and says which sensed points
  // were in the way (map frame) for the planner: at the posts, inside the
  // rectangle at the waypoint.
  SimRig rig("omnirob", twoRoomsWorld(0.70), mrpt::poses::CPose2D(3.0, 2.0, 0.0), 0.0);
  const auto r = rig.driver->driveFootprint({3.5, 2.0}, 0.0);
  ASSERT_EQ(r.outcome, DriveOutcome::Blocked) << r.message;
  ASSERT_NE(r.message.find("inside the footprint at the waypoint"), std::string::npos) << r.message;
  EXPECT_EQ(rig.collisions(), 0u);
  ASSERT_FALSE(r.blocking_points.empty());
  for (const auto& q : r.blocking_points)
  {
    EXPECT_LE(std::abs(q.x() - 3.5), 0.6 + 1e-6) << q.transpose();
    EXPECT_LE(std::abs(q.y() - 2.0), 0.356 + 1e-6) << q.transpose();
    EXPECT_GE(q.x(), 3.9) << "not at a door post: " << q.transpose();  // the wall's face: 3.925
    EXPECT_GE(std::abs(q.y() - 2.0), 0.34) << "not at a door post: " << q.transpose();
  }
}

TEST(StopAndScanDriver, AFootprintWaypointOffTheDoorsMiddleIsCentredOnTheSensedJambs)
{
  // b13, omniRob, nbv: in a door with a few centimetres a side, the plan's
  // waypoint lay 5 cm towards a jamb (the map and the swept path registered
  // before a correction): the rectangle there held a jamb point, and every
  // plan was blocked at its first waypoint. Here the waypoint is in a 0.85 m
  // door, 8 cm off its middle (the body's top side 1.1 cm into the upper
  // jamb, y 2.425). The drive moves it sideways onto what the sensors see,
  // 3 cm or more from both jambs, and passes; without centring it is
  // blocked by the jamb points.
  const Vector2d wp(4.075, 2.08);
  {
    SimRig off("omnirob", twoRoomsWorld(0.85), mrpt::poses::CPose2D(3.0, 2.0, 0.0), 0.0,
               [](DriverParams& p) { p.footprint_centring_m = 0; });
    const auto r = off.driver->driveFootprint(wp, 0.0);
    ASSERT_EQ(r.outcome, DriveOutcome::Blocked) << "control: " << r.message;
    ASSERT_NE(r.message.find("inside the footprint at the waypoint"), std::string::npos) << r.message;
    EXPECT_FALSE(r.blocking_points.empty());
    EXPECT_EQ(off.collisions(), 0u);
  }
  ProbedOmniRob rig(twoRoomsWorld(0.85), mrpt::poses::CPose2D(3.0, 2.0, 0.0));
  auto& driver = rig.driver;
  auto& simulator = rig.simulator;
  auto& probe = rig.probe;
  const auto r = driver.driveFootprint(wp, 0.0);
  std::cout << "[ centred waypoint ] " << toString(r.outcome) << ": " << r.message << std::endl;
  ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  EXPECT_NE(r.message.find("waypoint centred by"), std::string::npos) << r.message;
  EXPECT_TRUE(r.blocking_points.empty());
  const auto gt = simulator.robot().groundTruth();
  EXPECT_NEAR(gt.x(), wp.x(), 0.1);
  EXPECT_LE(gt.y() + 0.356, 2.425 - 0.03 + 0.005) << "3 cm from the upper jamb";
  EXPECT_GE(gt.y() - 0.356, 1.575 + 0.03 - 0.005) << "3 cm from the lower jamb";
  EXPECT_EQ(simulator.robot().collisions(), 0u);
  EXPECT_EQ(probe.tooClose(), 0u) << "the footprint came within 2 cm of the world";
}

TEST(StopAndScanDriver, AFootprintDriveHeldByTheGuardOnTheWayTakesAParallelLane)
{
  // b1, omniRob, nbv: the plan's line through a 0.87 m door ran a few
  // centimetres off its middle (the planner's states lie on cell centres);
  // the guard held the body 3 cm from a post on the way, every drive was
  // blocked and the room behind blacklisted. The waypoint itself is in the
  // next room, free, so the waypoint's centring does not apply. Here the
  // line through a 0.85 m door is 6 cm off its middle (the body's top side
  // 0.9 cm from the upper jamb, y 2.425). The drive moves sideways onto the
  // parallel line that keeps the guard's margin from what the sensors see
  // and passes; without it, the guard holds it before the door.
  const mrpt::poses::CPose2D start(3.0, 2.06, 0.0);
  const Vector2d wp(5.0, 2.06);
  {
    SimRig off("omnirob", twoRoomsWorld(0.85), start, 0.0,
               [](DriverParams& p) { p.footprint_centring_m = 0; });
    const auto r = off.driver->driveFootprint(wp, 0.0);
    ASSERT_EQ(r.outcome, DriveOutcome::Blocked) << "control: " << r.message;
    EXPECT_TRUE(r.guard_held) << r.message;
    EXPECT_LT(off.sim->robot().groundTruth().x() + 0.6, 4.0) << "held before the door";
    EXPECT_EQ(off.collisions(), 0u);
  }
  ProbedOmniRob rig(twoRoomsWorld(0.85), start);
  const auto r = rig.driver.driveFootprint(wp, 0.0);
  std::cout << "[ parallel lane ] " << toString(r.outcome) << ": " << r.message << std::endl;
  ASSERT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  EXPECT_NE(r.message.find("lane moved"), std::string::npos) << r.message;
  const auto gt = rig.simulator.robot().groundTruth();
  EXPECT_NEAR(gt.x(), wp.x(), 0.05);
  EXPECT_LE(gt.y() + 0.356, 2.425 - 0.03 + 0.005) << "on a line 3 cm from the upper jamb";
  EXPECT_GE(gt.y(), wp.y() - 0.06 - 0.005) << "moved at most footprint_centring_m";
  EXPECT_EQ(rig.simulator.robot().collisions(), 0u);
  EXPECT_EQ(rig.probe.tooClose(), 0u) << "the footprint came within 2 cm of the world";
}

TEST(StopAndScanDriver, AFootprintDriveStartingAtTheGuardsMarginBacksOffFirst)
{
  // The omniRob lengthwise in the 1.1 m corridor, its side 2.5 cm from the
  // south wall's face (y = 1.45): closer than the guard's 3 cm, as a stop
  // after a held approach leaves it. A 2.5 degree turn swings its rear
  // corner 2.6 cm towards the wall: held at once ...
  const mrpt::poses::CPose2D start(6.5, 1.45 + 0.356 + 0.025, 0.0);
  const double yaw = mrpt::DEG2RAD(2.5);
  {
    SimRig held("omnirob", corridorWorld(), start, 0.0,
                [](DriverParams& p) { p.footprint_backoff_m = 0; });
    const auto r = held.driver->driveFootprint({7.3, 1.9}, yaw);
    EXPECT_EQ(r.outcome, DriveOutcome::Blocked) << "control: without the back-off; " << r.message;
    EXPECT_EQ(held.collisions(), 0u);
  }
  // ... unless the drive first backs the rectangle off to 3 + 3 cm.
  SimRig rig("omnirob", corridorWorld(), start, 0.0);
  const auto r = rig.driver->driveFootprint({7.3, 1.9}, yaw);
  EXPECT_EQ(r.outcome, DriveOutcome::Reached) << r.message;
  EXPECT_NE(r.message.find("back-off"), std::string::npos) << r.message;
  EXPECT_EQ(rig.collisions(), 0u);
  EXPECT_NEAR(rig.sim->robot().groundTruth().x(), 7.3, 0.06);
  // Already clear: the back-off does nothing.
  const auto again = rig.driver->backOffFootprint();
  EXPECT_EQ(again.outcome, DriveOutcome::Reached);
  EXPECT_EQ(again.steps, 0u);
}

// ------------------------------------------- navigation logs (issue 14)

namespace
{
/// Reads a .reactivenavlog the way navlog-viewer does: CSerializable objects
/// from a gzip stream until EOF, keeping the CLogFileRecord ones.
std::vector<mrpt::nav::CLogFileRecord::Ptr> readNavlog(const std::string& path)
{
  std::vector<mrpt::nav::CLogFileRecord::Ptr> out;
  mrpt::io::CFileGZInputStream f(path);
  auto arch = mrpt::serialization::archiveFrom(f);
  for (;;)
  {
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
      obj = arch.ReadObject();
    }
    catch (const mrpt::serialization::CExceptionEOF&)
    {
      break;
    }
    if (auto rec = std::dynamic_pointer_cast<mrpt::nav::CLogFileRecord>(obj)) out.push_back(rec);
  }
  return out;
}

double distanceToSegment(const mrpt::math::TPose2D& p, const Vector2d& a, const Vector2d& b)
{
  const Vector2d q(p.x, p.y), ab = b - a;
  const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (q - (a + t * ab)).norm();
}
}  // namespace

TEST(StopAndScanDriver, NavlogDirWritesOneReadableReactivenavlogPerDrive)
{
  namespace fs = std::filesystem;
  const auto dir = test::tempPath("navlogs");
  fs::remove_all(dir);
  SimRig rig("omnirob");
  auto p = rig.driver->params();
  p.navlog_dir = dir + "/sub";  // created by the driver
  rig.driver = std::make_unique<StopAndScanDriver>(*rig.robot, p);
  const std::vector<Vector2d> legs = {{2.0, 4.0}, {2.0, 3.0}, {2.6, 2.2}};  // start, 2 drives
  for (std::size_t i = 1; i < legs.size(); i++)
    ASSERT_EQ(rig.driver->driveTo(legs[i], std::nullopt).outcome, DriveOutcome::Reached);
  // A second driver (a new run) into the same directory does not overwrite.
  rig.driver = std::make_unique<StopAndScanDriver>(*rig.robot, p);
  ASSERT_EQ(rig.driver->driveTo(legs[1], std::nullopt).outcome, DriveOutcome::Reached);
  rig.driver.reset();

  const std::vector<std::pair<Vector2d, Vector2d>> drives = {
      {legs[0], legs[1]}, {legs[1], legs[2]}, {legs[2], legs[1]}};
  for (std::size_t i = 0; i < drives.size(); i++)
  {
    const std::string file = mrpt::format("%s/sub/log_%03u.reactivenavlog", dir.c_str(),
                                          static_cast<unsigned>(i));  // MRPT counts from 000
    ASSERT_TRUE(fs::exists(file)) << file;
    const auto recs = readNavlog(file);
    ASSERT_GT(recs.size(), 5u) << file;
    // The first record carries the PTG (navlog-viewer rebuilds the paths from it).
    ASSERT_FALSE(recs.front()->infoPerPTG.empty());
    ASSERT_TRUE(recs.front()->infoPerPTG[0].ptg) << file;
    EXPECT_EQ(recs.front()->infoPerPTG[0].ptg->GetRuntimeClass()->className,
              std::string("mrpt::nav::CPTG_Holo_Blend"));
    const auto& [from, to] = drives[i];
    double worst = 0;
    for (const auto& r : recs)
      worst = std::max(worst, distanceToSegment(r->robotPoseLocalization, from, to));
    EXPECT_LT(worst, 0.3) << file << ": logged poses off the drive's path";
    const auto& a = recs.front()->robotPoseLocalization;
    const auto& b = recs.back()->robotPoseLocalization;
    EXPECT_LT(std::hypot(a.x - from.x(), a.y - from.y()), 0.1) << file;
    EXPECT_LT(std::hypot(b.x - to.x(), b.y - to.y()), 0.2) << file;
    EXPECT_GT(recs.front()->WS_Obstacles.size(), 0u) << "no obstacles logged";
    EXPECT_NEAR(recs.front()->robotShape_radius, p.robotRadius(), 1e-6);
    std::cout << "[ navlog ] " << file << ": " << recs.size() << " records, " << fs::file_size(file)
              << " bytes, worst distance to the path " << worst << " m" << std::endl;
  }
  EXPECT_FALSE(fs::exists(dir + "/sub/log_003.reactivenavlog"));
}

TEST(StopAndScanDriver, NavlogDirThatCannotBeCreatedNamesTheKey)
{
  IdealRobot robot;
  DriverParams p;
  p.navlog_dir = "/proc/voxplore_no_navlogs_here";
  try
  {
    StopAndScanDriver driver(robot, p);
    ADD_FAILURE() << "expected an error";
  }
  catch (const std::exception& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("navlog_dir"), std::string::npos) << msg;
    EXPECT_NE(msg.find("/proc/voxplore_no_navlogs_here"), std::string::npos) << msg;
  }
  // A file where the directory should be is a configuration error naming the key.
  const auto file = test::tempPath("navlog_is_a_file");
  std::ofstream(file) << "x";
  mrpt::config::CConfigFileMemory c("[navigation]\nnavlog_dir = " + file + "\n");
  DriverParams q;
  try
  {
    common::loadChecked(q, c, "navigation");
    ADD_FAILURE() << "expected an error";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("navlog_dir"), std::string::npos) << e.what();
  }
}
