// mission::ExplorationLoop on a second, minimal robot that has nothing to do
// with libs/sim (this test links voxplore::mission only): a circular
// holonomic robot in a room of axis-aligned boxes, with 8 depth cameras
// ray-cast analytically here, a 3-layer obstacle fan for the navigator and
// MRPT's simulated clock. It is what a user writes to plug in a robot
// (README "Plugging in a robot"), cut down to the geometry of one room.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <voxplore/common/camera_mounts.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/stages.h>
#include <voxplore/mission/ExplorationLoop.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <vector>

#include "expect_error.h"

namespace
{
using namespace voxplore;

/// An axis-aligned solid box [m].
struct Box
{
  Eigen::Vector3d lo, hi;
};

/// The world: a 10 x 4 m room split by a wall at x = 5 with a 1.2 m gap at
/// the top (y 2.8..4), and a 0.6 m cube in the right half.
std::vector<Box> twoRooms()
{
  const double h = 2.2;
  return {
      {{-0.2, -0.2, 0}, {0.0, 4.2, h}},    // west wall
      {{10.0, -0.2, 0}, {10.2, 4.2, h}},   // east wall
      {{-0.2, -0.2, 0}, {10.2, 0.0, h}},   // south wall
      {{-0.2, 4.0, 0}, {10.2, 4.2, h}},    // north wall
      {{4.9, 0.0, 0}, {5.1, 2.8, h}},      // partition, gap y 2.8..4
      {{7.0, 1.0, 0}, {7.6, 1.6, 0.6}},    // a crate
  };
}

/// Ray parameter of the first hit of o + t d (t >= 0) with the boxes and the
/// floor z = 0; infinity when nothing is hit.
double castRay(const std::vector<Box>& boxes, const Eigen::Vector3d& o, const Eigen::Vector3d& d)
{
  double best = std::numeric_limits<double>::infinity();
  if (d.z() < 0) best = -o.z() / d.z();
  for (const auto& b : boxes)
  {
    double t0 = 0, t1 = best;
    bool hit = true;
    for (int k = 0; k < 3 && hit; k++)
    {
      if (std::abs(d[k]) < 1e-12)
      {
        hit = o[k] >= b.lo[k] && o[k] <= b.hi[k];
        continue;
      }
      double ta = (b.lo[k] - o[k]) / d[k], tb = (b.hi[k] - o[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      hit = t0 <= t1;
    }
    if (hit) best = std::min(best, t0);
  }
  return best;
}

/// Distance from a point to a box in the plane (0 inside).
double planarDistance(const Box& b, double x, double y)
{
  const double dx = std::max({b.lo.x() - x, 0.0, x - b.hi.x()});
  const double dy = std::max({b.lo.y() - y, 0.0, y - b.hi.y()});
  return std::hypot(dx, dy);
}

/// A holonomic disc robot with perfect odometry (own frame = the world),
/// driving on MRPT's simulated clock. Refuses (and counts) a step that would
/// bring the disc closer than its radius to a box.
class DiscRobot : public navigation::RobotInterface, public mission::Clock
{
 public:
  DiscRobot(std::vector<Box> world, mrpt::poses::CPose2D start, double radius_m)
      : world_(std::move(world)),
        pose_(start),
        radius_m_(radius_m),
        previous_clock_(mrpt::Clock::getActiveClock())
  {
    mrpt::Clock::setSimulatedTime(now_);
    mrpt::Clock::setActiveClock(mrpt::Clock::Simulated);
  }
  ~DiscRobot() override { mrpt::Clock::setActiveClock(previous_clock_); }

  void setVelocity(double vx, double vy, double w) override
  {
    const double v = std::hypot(vx, vy);
    const double s = v > kMaxV ? kMaxV / v : 1.0;
    cmd_ = {vx * s, vy * s, std::clamp(w, -kMaxW, kMaxW)};
  }
  void stop() override { cmd_ = {0, 0, 0}; }
  mrpt::poses::CPose2D pose() const override
  {
    ADD_FAILURE() << "the loop must drive by its own estimate, not RobotInterface::pose()";
    return pose_;
  }
  mrpt::poses::CPose2D odometry() const override { return pose_; }
  mrpt::math::TTwist2D velocity() const override { return cmd_; }
  bool obstacles(mrpt::maps::CSimplePointsMap& out) override
  {
    out.clear();
    for (const double z : {0.1, 0.3, 0.5})
      for (int i = 0; i < 720; i++)
      {
        const double a = i * M_PI / 360.0;
        const Eigen::Vector3d d(std::cos(pose_.phi() + a), std::sin(pose_.phi() + a), 0);
        const double t = castRay(world_, {pose_.x(), pose_.y(), z}, d);
        if (t <= 6.0) out.insertPoint(t * std::cos(a), t * std::sin(a), z);
      }
    return true;
  }
  mrpt::Clock::time_point now() const override { return now_; }
  void step(double dt_s) override
  {
    const int n = std::max(1, static_cast<int>(std::lround(dt_s / 0.01)));
    for (int k = 0; k < n; k++)
    {
      const double h = dt_s / n;
      const double c = std::cos(pose_.phi()), s = std::sin(pose_.phi());
      const mrpt::poses::CPose2D next(pose_.x() + (c * cmd_.vx - s * cmd_.vy) * h,
                                      pose_.y() + (s * cmd_.vx + c * cmd_.vy) * h,
                                      pose_.phi() + cmd_.omega * h);
      if (clearance(next.x(), next.y()) < radius_m_)
        collisions_++;
      else
        pose_ = next;
      min_clearance_m_ = std::min(min_clearance_m_, clearance(pose_.x(), pose_.y()) - radius_m_);
      max_x_ = std::max(max_x_, pose_.x());
    }
    now_ += std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::duration<double>(dt_s));
    mrpt::Clock::setSimulatedTime(now_);
  }
  std::optional<std::size_t> collisionCount() const override { return collisions_; }

  const mrpt::poses::CPose2D& truePose() const { return pose_; }
  const std::vector<Box>& world() const { return world_; }
  double minClearance() const { return min_clearance_m_; }
  double maxX() const { return max_x_; }
  /// Scans take a sensor period of standing still.
  void advance(double dt_s)
  {
    now_ += std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::duration<double>(dt_s));
    mrpt::Clock::setSimulatedTime(now_);
  }

 private:
  double clearance(double x, double y) const
  {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& b : world_) d = std::min(d, planarDistance(b, x, y));
    return d;
  }
  static constexpr double kMaxV = 0.5, kMaxW = M_PI / 4;
  std::vector<Box> world_;
  mrpt::poses::CPose2D pose_;
  double radius_m_;
  mrpt::math::TTwist2D cmd_{0, 0, 0};
  mrpt::Clock::time_point now_ = mrpt::Clock::fromDouble(1.7e9);
  mrpt::Clock::Source previous_clock_;
  std::size_t collisions_ = 0;
  double min_clearance_m_ = std::numeric_limits<double>::infinity();
  double max_x_ = -std::numeric_limits<double>::infinity();
};

/// 8 noise-free 64 x 48 depth cameras (40 x 30 deg) on the thesis' ring,
/// rendered by castRay at the robot's true pose.
class BoxCameras : public mission::ScanSource
{
 public:
  BoxCameras(DiscRobot& robot, std::vector<mrpt::poses::CPose3D> mounts)
      : robot_(robot), mounts_(std::move(mounts))
  {
    cam_.ncols = kW;
    cam_.nrows = kH;
    const double fx = 0.5 * kW / std::tan(0.5 * mrpt::DEG2RAD(40.0));
    const double fy = 0.5 * kH / std::tan(0.5 * mrpt::DEG2RAD(30.0));
    cam_.setIntrinsicParamsFromValues(fx, fy, 0.5 * (kW - 1), 0.5 * (kH - 1));
  }

  mission::Scan scan() override
  {
    if (fail_at_scan_ && scans_ == *fail_at_scan_)
      throw std::runtime_error("BoxCameras: camera bus timeout at scan " + std::to_string(scans_));
    scans_++;
    robot_.advance(0.05);
    mission::Scan s;
    s.timestamp = robot_.now();
    s.odometry = robot_.odometry();
    s.observations = mrpt::obs::CSensoryFrame::Create();
    const mrpt::poses::CPose3D T_world_robot(robot_.truePose());
    for (std::size_t c = 0; c < mounts_.size(); c++)
    {
      auto obs = mrpt::obs::CObservation3DRangeScan::Create();
      obs->sensorLabel = "CAM" + std::to_string(c);
      obs->timestamp = s.timestamp;
      obs->hasRangeImage = true;
      obs->range_is_depth = true;
      obs->rangeUnits = 0.001f;
      obs->rangeImage_setSize(kH, kW);
      obs->cameraParams = cam_;
      obs->cameraParamsIntensity = cam_;
      obs->maxRange = 7.0f;
      obs->stdError = 0.01f;
      obs->sensorPose = mounts_[c];
      const mrpt::poses::CPose3D T_world_cam = T_world_robot + mounts_[c];
      const auto R = T_world_cam.getRotationMatrix().asEigen();
      const Eigen::Vector3d o(T_world_cam.x(), T_world_cam.y(), T_world_cam.z());
      for (int v = 0; v < kH; v++)
        for (int u = 0; u < kW; u++)
        {
          // MRPT's camera frame: +X depth, +Y left, +Z up; x = 1 makes t the depth.
          const Eigen::Vector3d d_cam(1.0, (cam_.cx() - u) / cam_.fx(), (cam_.cy() - v) / cam_.fy());
          const double depth = castRay(robot_.world(), o, R * d_cam);
          const double range = depth * d_cam.norm();
          obs->rangeImage(v, u) = range >= 0.12 && range <= 7.0
                                      ? static_cast<uint16_t>(std::lround(depth / 0.001))
                                      : uint16_t(0);
        }
      s.observations->insert(obs);
    }
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->sensorLabel = "ODOMETRY";
    odo->timestamp = s.timestamp;
    odo->odometry = s.odometry;
    s.observations->insert(odo);
    return s;
  }

  std::optional<std::size_t> fail_at_scan_;  ///< throw instead of scanning (0-based)

 private:
  static constexpr int kW = 64, kH = 48;
  DiscRobot& robot_;
  std::vector<mrpt::poses::CPose3D> mounts_;
  mrpt::img::TCamera cam_;
  std::size_t scans_ = 0;
};

/// Counts events; stops the run after `stop_after_robot_steps` robot steps.
struct CountingListener : mission::Listener
{
  std::size_t scans = 0, stops = 0, plans = 0, robot_steps = 0;
  std::vector<double> plan_paths;  ///< path_length_m at each plan [m]
  /// the largest Frontier::unknown_m2 of each plan's frontiers (-1: none) [m^2]
  std::vector<double> plan_pockets;
  std::optional<std::size_t> stop_after_robot_steps;
  void onScan(const mission::Scan&) override { scans++; }
  void onStop(const mission::Scan&, const mapping::StopReport&) override { stops++; }
  void onPlan(const exploration::PlanResult& plan, double,
              const mission::ExplorationStatus& status) override
  {
    plans++;
    plan_paths.push_back(status.path_length_m);
    double largest = -1;
    if (plan.frontiers)
      for (const auto& f : plan.frontiers->frontiers) largest = std::max(largest, f.unknown_m2);
    plan_pockets.push_back(largest);
  }
  void onRobotStep() override { robot_steps++; }
  std::string stopReason() override
  {
    return stop_after_robot_steps && robot_steps >= *stop_after_robot_steps ? "interrupted"
                                                                           : std::string();
  }
};

/// The compact robot's parameters from config/explore.ini, as voxplore-explore loads them.
struct RobotSetup
{
  static constexpr double kLength = 0.50, kWidth = 0.36;
  mapping::SlamIcpParams slam;
  exploration::PlannerParams planner;
  navigation::DriverParams driver;
  mission::ExplorationLoopParams loop;
  std::vector<mrpt::poses::CPose3D> mounts;
  double radius_m = 0;

  RobotSetup()
  {
    // common::openIniFile, as the apps: MRPT's own reader takes the comment
    // of a key left empty for its value (navlog_dir).
    const auto file = common::openIniFile(std::string(VOXPLORE_SOURCE_DIR) + "/config/explore.ini");
    const mrpt::config::CConfigFileBase& ini = *file;
    mounts = common::cameraRing(kLength, kWidth, 0.60, mrpt::DEG2RAD(30.0));
    radius_m = std::hypot(kLength / 2, kWidth / 2);
    slam.load(ini);
    planner.collision.r_coll_m = radius_m;
    planner.load(ini);
    // This robot is a disc (its collisions are its circle's): the thesis'
    // model, not the rectangle config/explore.ini plans with.
    planner.collision.model = exploration::CollisionParams::Model::Circle;
    planner.rating.mounts = mounts;
    driver = navigation::DriverParams::forFootprint(kLength, kWidth);
    common::loadChecked(driver, ini, "navigation");
    loop.loadFromConfigFile(ini, "explore");  // [explore] also holds the simulator's keys
    loop.max_steps = 40;
  }
};

/// A run of the disc robot in twoRooms() from (2, 2) with `setup`.
mission::ExplorationStatus exploreTwoRooms(const RobotSetup& setup,
                                           mission::Listener* listener = nullptr,
                                           std::vector<Box> world = twoRooms(),
                                           std::size_t* collisions = nullptr)
{
  DiscRobot robot(std::move(world), mrpt::poses::CPose2D(2.0, 2.0, 0.0), setup.radius_m);
  BoxCameras cameras(robot, setup.mounts);
  mission::ExplorationLoop loop(robot, cameras, robot, setup.slam, setup.planner, setup.driver,
                                setup.loop, listener);
  const auto status = loop.run();
  if (collisions) *collisions = robot.collisionCount().value();
  return status;
}

TEST(ExplorationLoop, ExploresTwoRoomsWithARobotOutsideTheSimulator)
{
  RobotSetup setup;
  DiscRobot robot(twoRooms(), mrpt::poses::CPose2D(2.0, 2.0, 0.0), setup.radius_m);
  BoxCameras cameras(robot, setup.mounts);
  CountingListener events;
  mission::ExplorationLoop loop(robot, cameras, robot, setup.slam, setup.planner, setup.driver,
                                setup.loop, &events);
  const auto& status = loop.run();

  // It ends by itself, having driven through the gap into the right room.
  EXPECT_TRUE(status.termination_reason == "no frontier" ||
              status.termination_reason == "no reachable frontier")
      << status.termination_reason;
  EXPECT_GE(status.steps, 2u);
  EXPECT_GT(robot.maxX(), 5.5) << "never entered the right room";
  EXPECT_EQ(robot.collisionCount().value(), 0u);
  EXPECT_GE(robot.minClearance(), 0.02);
  EXPECT_EQ(events.plans, status.steps);
  EXPECT_EQ(events.stops, loop.slam().numStops());
  EXPECT_EQ(events.scans, events.stops);
  EXPECT_GT(events.robot_steps, 0u);
  EXPECT_GT(status.path_length_m, 3.0);

  // SLAM (map frame = the start pose) agrees with the true pose at the end.
  const mrpt::poses::CPose2D start(2.0, 2.0, 0.0);
  const auto truth = robot.truePose() - start;
  const auto est = loop.slam().currentPose();
  EXPECT_LT(std::hypot(est.x() - truth.x(), est.y() - truth.y()), 0.05);
  EXPECT_LT(std::abs(mrpt::math::wrapToPi(est.phi() - truth.phi())), mrpt::DEG2RAD(1.0));

  // The 2D grid knows both rooms' floor (cells 0.4 m clear of any wall) as free.
  const auto ground = exploration::projectToGround(loop.slam().octomap().tree(), est,
                                                   setup.planner.projection, loop.sweptPath());
  std::size_t floor = 0, free = 0;
  for (double x = 0.2; x < 10.0; x += 0.1)
    for (double y = 0.2; y < 4.0; y += 0.1)
    {
      bool clear = true;
      for (const auto& b : robot.world()) clear = clear && planarDistance(b, x, y) >= 0.4;
      if (!clear) continue;
      floor++;
      double mx = 0, my = 0;
      (-start).composePoint(x, y, mx, my);
      exploration::Cell c;
      free += exploration::cellOf(ground.state, {mx, my}, c) &&
              *ground.state.cellByIndex(c.cx, c.cy) == exploration::GroundState::Free;
    }
  EXPECT_GT(static_cast<double>(free) / floor, 0.95) << free << " of " << floor << " floor cells";
  std::cout << "explored: " << status.termination_reason << " after " << status.steps
            << " steps, " << loop.slam().numStops() << " stops, path " << status.path_length_m
            << " m, floor known free " << static_cast<double>(free) / floor
            << ", min clearance " << robot.minClearance() << " m, final pose error "
            << std::hypot(est.x() - truth.x(), est.y() - truth.y()) << " m" << std::endl;
}

TEST(ExplorationLoop, AListenerStopsTheRunMidDriveWithTheRobotStanding)
{
  RobotSetup setup;
  DiscRobot robot(twoRooms(), mrpt::poses::CPose2D(2.0, 2.0, 0.0), setup.radius_m);
  BoxCameras cameras(robot, setup.mounts);
  CountingListener events;
  events.stop_after_robot_steps = 15;
  mission::ExplorationLoop loop(robot, cameras, robot, setup.slam, setup.planner, setup.driver,
                                setup.loop, &events);
  const auto& status = loop.run();
  EXPECT_EQ(status.termination_reason, "interrupted");
  EXPECT_EQ(events.robot_steps, 15u);
  const auto v = robot.velocity();
  EXPECT_EQ(std::hypot(v.vx, v.vy) + std::abs(v.omega), 0.0) << "the robot was left moving";
}

TEST(ExplorationLoop, TheTimeLimitHoldsOnTheGivenClock)
{
  RobotSetup setup;
  setup.loop.max_sim_time_s = 20.0;
  const auto status = exploreTwoRooms(setup);
  EXPECT_EQ(status.termination_reason, "max_sim_time");
  EXPECT_GE(status.elapsed_s, 20.0);
  EXPECT_LT(status.elapsed_s, 20.5);  // within a robot step or a scan of the limit
}

TEST(ExplorationLoop, AScanSourceErrorPropagatesAndTheStopsSoFarStay)
{
  RobotSetup setup;
  DiscRobot robot(twoRooms(), mrpt::poses::CPose2D(2.0, 2.0, 0.0), setup.radius_m);
  BoxCameras cameras(robot, setup.mounts);
  cameras.fail_at_scan_ = 2;
  mission::ExplorationLoop loop(robot, cameras, robot, setup.slam, setup.planner, setup.driver,
                                setup.loop);
  try
  {
    loop.run();
    FAIL() << "expected the scan source's error";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("camera bus timeout at scan 2"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(loop.slam().numStops(), 2u);
}

/// A 1.5 m path window asking a gain no drive reaches (the rule fires as
/// soon as the window is driven), up to 30 steps.
RobotSetup pathWindowSetup()
{
  RobotSetup setup;
  setup.loop.stagnation_path_m = 1.5;
  setup.loop.stagnation_path_min_gain_m2 = 1000.0;
  setup.loop.max_steps = 30;
  return setup;
}

}  // namespace

TEST(ExplorationLoop, ARunThatFindsNoNewFloorEndsWithStagnation)
{
  // The stagnation rule over steps: with a gain no step can reach (1,000 m^2
  // over 2 steps) the run ends at the third planning step, by itself, the
  // robot standing, the frontiers left reported. (Off by default: 20 steps
  // cut a building run short; ExploresTwoRoomsWithARobotOutsideTheSimulator
  // ends by "no frontier".)
  RobotSetup setup;
  setup.loop.stagnation_steps = 2;
  setup.loop.stagnation_min_gain_m2 = 1000.0;
  const auto status = exploreTwoRooms(setup);
  EXPECT_EQ(status.termination_reason, "stagnation");
  EXPECT_EQ(status.steps, 3u);
  EXPECT_GT(status.known_floor_m2, 1.0);
  EXPECT_FALSE(status.frontiers_left.empty());
  // Off (0): the same run goes on past the third step.
  setup.loop.stagnation_steps = 0;
  setup.loop.max_steps = 4;
  EXPECT_NE(exploreTwoRooms(setup).termination_reason, "stagnation");
}

TEST(ExplorationLoop, StagnationOverThePathWaitsForTheWindowToBeDriven)
{
  // The path window: with a gain no drive can reach, the run ends
  // "stagnation" at the first planning step after the robot has driven the
  // window (not before: a robot standing at a door fills no window), with
  // the frontiers left reported.
  RobotSetup setup = pathWindowSetup();
  CountingListener events;
  const auto status = exploreTwoRooms(setup, &events);
  const auto& paths = events.plan_paths;
  ASSERT_EQ(status.termination_reason, "stagnation");
  ASSERT_GE(paths.size(), 2u);
  EXPECT_GE(paths.back(), 1.5);  // the window was driven ...
  EXPECT_LT(paths[paths.size() - 2], 1.5);  // ... and the step before had not
  EXPECT_FALSE(status.frontiers_left.empty());
  // A window longer than the run never fills: the rule does not fire,
  // whatever gain it asks for.
  setup.loop.stagnation_path_m = 1000.0;
  setup.loop.max_steps = 4;
  EXPECT_NE(exploreTwoRooms(setup).termination_reason, "stagnation");
}

TEST(ExplorationLoop, TheTailRuleWaitsWhileAFrontierFacesOpenUnknown)
{
  // The tail rule with a gain no drive reaches over a 1.5 m window and any
  // closed pocket counted small: while a frontier faces open unknown (a room
  // not entered, unknown out to the grid's border) the run goes on, the
  // window driven; it ends by itself when nothing is left to reach.
  RobotSetup setup;
  setup.loop.stagnation_path_m = 0;
  setup.loop.tail_path_m = 1.5;
  setup.loop.tail_min_gain_m2 = 1000.0;
  setup.loop.tail_pocket_m2 = std::numeric_limits<double>::infinity();
  setup.loop.max_steps = 40;
  CountingListener events;
  const auto status = exploreTwoRooms(setup, &events);
  std::size_t open_after_window = 0;
  for (std::size_t i = 0; i < events.plan_pockets.size(); ++i)
  {
    std::cout << "[ tail ] step " << i << ": " << events.plan_paths[i] << " m, largest pocket "
              << events.plan_pockets[i] << " m^2\n";
    open_after_window += events.plan_paths[i] >= 1.5 && std::isinf(events.plan_pockets[i]);
  }
  std::cout << "[ tail ] " << status.termination_reason << " after " << status.steps << " steps\n";
  EXPECT_GE(open_after_window, 2u) << "steps the rule had to wait through";
  EXPECT_NE(status.termination_reason, "only small pockets left");
  EXPECT_NE(status.termination_reason, "max_steps");
}

TEST(ExplorationLoop, OnlySmallPocketsNeedsEveryFrontierOnASmallClosedPocket)
{
  const auto frontier = [](double unknown_m2)
  {
    exploration::Frontier f;
    f.unknown_m2 = unknown_m2;
    return f;
  };
  using L = mission::ExplorationLoop;
  EXPECT_TRUE(L::onlySmallPockets({frontier(0.4), frontier(3.9)}, 4.0));
  EXPECT_FALSE(L::onlySmallPockets({frontier(0.4), frontier(4.0)}, 4.0)) << "a room's worth";
  EXPECT_FALSE(L::onlySmallPockets({frontier(0.4), frontier(std::numeric_limits<double>::infinity())},
                                   std::numeric_limits<double>::infinity()))
      << "open unknown is never small";
  EXPECT_FALSE(L::onlySmallPockets({}, 4.0)) << "no frontier: the planner's end, not the tail's";
  EXPECT_FALSE(mission::ExplorationLoopParams{}.tail_path_m <= 0) << "on by default";
}

TEST(ExplorationLoop, AKnownFloorFallenByHalfIsAMapThatShutTheRobotIn)
{
  using L = mission::ExplorationLoop;
  // willowgarage compact nbv's last steps: 1,057 m^2 known, then 72.
  EXPECT_TRUE(L::floorCollapsed({12, 900, 1047.7, 1057.3, 72.0}));
  EXPECT_TRUE(L::floorCollapsed({400, 199}));
  // A rebuild after a loop closure or a door drawn 2 cm narrower loses a
  // little; a run still growing or standing still loses nothing.
  EXPECT_FALSE(L::floorCollapsed({400, 380}));
  EXPECT_FALSE(L::floorCollapsed({400, 200}));
  EXPECT_FALSE(L::floorCollapsed({10, 20, 30}));
  EXPECT_FALSE(L::floorCollapsed({50}));
  EXPECT_FALSE(L::floorCollapsed({}));
  // The floor still in G, cut off from the robot: b7 compact nbv (seed 2)
  // stood between two tables' legs with 145.5 of 146 m^2 cut off.
  EXPECT_TRUE(L::cutOffShutsIn(145.5, 146.1));
  EXPECT_TRUE(L::cutOffShutsIn(60, 100));
  EXPECT_FALSE(L::cutOffShutsIn(50, 100));
  EXPECT_FALSE(L::cutOffShutsIn(3, 400)) << "floor beside furniture legs";
  EXPECT_FALSE(L::cutOffShutsIn(4, 5)) << "under 5 m^2";
}

TEST(ExplorationLoop, ALowObstacleSeenOnTheWayEndsTheDrive)
{
  // A 5 cm plate the robot's obstacle fan (0.1 m and up) never senses and
  // the cameras see only from afar (no floor within ~0.9 m of their rim).
  auto world = twoRooms();
  // Just past the gap: planned over from the left room, seen only on the way.
  world.push_back({{6.0, 2.9, 0.0}, {6.5, 3.4, 0.05}});
  RobotSetup setup;
  // The plate lies on the course the thesis' frontier tiers take (one tier
  // goes to the left room's short frontiers first and plans past it later).
  setup.planner.frontier_tiers = true;
  // ... and drives its plans to their ends (replan_at_stops ends the drive
  // that passes it at a stop before, whose scan saw the plan's frontier).
  setup.loop.replan_at_stops = mission::ExplorationLoopParams::Switch::Off;
  setup.loop.max_steps = 30;
  setup.loop.low_obstacle_replan = mission::ExplorationLoopParams::Switch::On;
  std::size_t hits_on = 0, hits_off = 0;
  const auto on = exploreTwoRooms(setup, nullptr, world, &hits_on);
  setup.loop.low_obstacle_replan = mission::ExplorationLoopParams::Switch::Off;
  const auto off = exploreTwoRooms(setup, nullptr, world, &hits_off);
  std::cout << "on: " << hits_on << " collisions, " << on.low_obstacle_replans << " replans, "
            << on.termination_reason << "; off: " << hits_off << " collisions, "
            << off.low_obstacle_replans << " replans, " << off.termination_reason << std::endl;
  EXPECT_EQ(hits_on, 0u);
  EXPECT_GT(on.low_obstacle_replans, 0u);
  EXPECT_NE(on.termination_reason, "max_steps");
  EXPECT_EQ(off.low_obstacle_replans, 0u);
  EXPECT_GT(hits_off, 0u) << "the plate is not on a path planned before it was seen";
}

TEST(ExplorationLoop, LowObstacleReplanAutoIsOnWithExactFootprintMargins)
{
  // "auto": on where the planner plans with the footprint and exact margins
  // (the compact robot), off with trimmed margins (the omniRob) or the circle.
  using Switch = mission::ExplorationLoopParams::Switch;
  mission::ExplorationLoopParams p;
  ASSERT_EQ(p.low_obstacle_replan, Switch::Auto);
  exploration::CollisionParams compact;
  compact.model = exploration::CollisionParams::Model::Footprint;
  compact.footprint_length_m = 0.50;
  compact.footprint_width_m = 0.36;
  EXPECT_TRUE(p.lowObstacleReplanInForce(compact, 0.05));
  exploration::CollisionParams omni;  // the omniRob's rectangle: trimmed
  omni.model = exploration::CollisionParams::Model::Footprint;
  EXPECT_FALSE(p.lowObstacleReplanInForce(omni, 0.05));
  compact.model = exploration::CollisionParams::Model::Circle;
  EXPECT_FALSE(p.lowObstacleReplanInForce(compact, 0.05));
  p.low_obstacle_replan = Switch::On;
  EXPECT_TRUE(p.lowObstacleReplanInForce(omni, 0.05));
  // The ini: auto / true / false round-trip; anything else names the key.
  mrpt::config::CConfigFileMemory m;
  m.write("explore", "low_obstacle_replan", "false");
  p.loadFromConfigFile(m, "explore");
  EXPECT_EQ(p.low_obstacle_replan, Switch::Off);
  m.write("explore", "low_obstacle_replan", "auto");
  p.loadFromConfigFile(m, "explore");
  EXPECT_EQ(p.low_obstacle_replan, Switch::Auto);
  EXPECT_EQ(test::savedText(p, "explore", "low_obstacle_replan"), "auto");
  m.write("explore", "low_obstacle_replan", "sometimes");
  test::expectErrorNaming([&] { p.loadFromConfigFile(m, "explore"); }, "low_obstacle_replan",
                          "'sometimes'");
}

// [explore] replan_at_stops (issue 12): a stop-and-scan drive whose frontier
// the scan at an intermediate stop has seen ends at that stop, and the loop
// plans from there; the rooms are explored as fully, as safely, on a shorter
// path. Off, every plan is driven to its end.
TEST(ExplorationLoop, AStopThatSawThePlansFrontierEndsTheDrive)
{
  RobotSetup setup;
  ASSERT_EQ(setup.loop.scan_mode, mission::ExplorationLoopParams::ScanMode::StopAndScan);
  using Switch = mission::ExplorationLoopParams::Switch;
  setup.loop.replan_at_stops = Switch::Off;
  std::size_t hits_off = 0, hits_on = 0;
  const auto off = exploreTwoRooms(setup, nullptr, twoRooms(), &hits_off);
  setup.loop.replan_at_stops = Switch::On;
  const auto on = exploreTwoRooms(setup, nullptr, twoRooms(), &hits_on);
  std::cout << "off: " << off.termination_reason << ", " << off.steps << " steps, path "
            << off.path_length_m << " m; on: " << on.termination_reason << ", " << on.steps
            << " steps, path " << on.path_length_m << " m, " << on.targets_seen_on_the_way
            << " drives ended at a stop" << std::endl;
  EXPECT_EQ(off.targets_seen_on_the_way, 0u);
  EXPECT_GT(on.targets_seen_on_the_way, 0u);
  for (const auto* s : {&off, &on})
    EXPECT_TRUE(s->termination_reason == "no frontier" ||
                s->termination_reason == "no reachable frontier")
        << s->termination_reason;
  EXPECT_EQ(hits_off, 0u);
  EXPECT_EQ(hits_on, 0u);
  EXPECT_LT(on.path_length_m, off.path_length_m);
  // Auto: the nbv strategy only; the nearest baseline drives to the end.
  setup.loop.replan_at_stops = Switch::Auto;
  setup.planner.strategy = exploration::Strategy::NearestFrontier;
  const auto nearest = exploreTwoRooms(setup);
  EXPECT_EQ(nearest.targets_seen_on_the_way, 0u);
  EXPECT_TRUE(setup.loop.replanAtStopsInForce(true));
  EXPECT_FALSE(setup.loop.replanAtStopsInForce(false));
  // The ini: auto / true / false round-trip; anything else names the key.
  mission::ExplorationLoopParams p;
  mrpt::config::CConfigFileMemory m;
  m.write("explore", "replan_at_stops", "true");
  p.loadFromConfigFile(m, "explore");
  EXPECT_EQ(p.replan_at_stops, Switch::On);
  m.write("explore", "replan_at_stops", "auto");
  p.loadFromConfigFile(m, "explore");
  EXPECT_EQ(p.replan_at_stops, Switch::Auto);
  EXPECT_EQ(test::savedText(p, "explore", "replan_at_stops"), "auto");
  m.write("explore", "replan_at_stops", "often");
  test::expectErrorNaming([&] { p.loadFromConfigFile(m, "explore"); }, "replan_at_stops",
                          "'often'");
}

// [explore] seen_gate: the check of replan_at_stops first looks at the
// ground projection alone; while most of the plan's frontier cells still
// border unknown, the frontier is there and the frontiers are not computed
// again. verify computes both and lets the full check decide: its run is the
// run without the gate, and it counts the gate's wrong answers.
TEST(ExplorationLoop, TheSeenGateAnswersChecksFromTheProjectionAndVerifyKeepsTheRun)
{
  RobotSetup setup;
  setup.loop.replan_at_stops = mission::ExplorationLoopParams::Switch::On;
  setup.loop.seen_gate_fraction = 0.5;  // this small world's frontiers are seen at once
  setup.loop.seen_gate = false;
  const auto off = exploreTwoRooms(setup);
  setup.loop.seen_gate_verify = true;
  const auto verify = exploreTwoRooms(setup);
  setup.loop.seen_gate_verify = false;
  setup.loop.seen_gate = true;
  std::size_t hits = 0;
  const auto on = exploreTwoRooms(setup, nullptr, twoRooms(), &hits);
  std::cout << "off: " << off.seen_checks << " checks, path " << off.path_length_m
            << " m; verify: " << verify.seen_gate_misses << " misses; on: " << on.seen_checks
            << " checks, " << on.seen_gated << " gated, path " << on.path_length_m << " m, "
            << on.termination_reason << std::endl;
  EXPECT_GT(off.seen_checks, 0u);
  EXPECT_EQ(off.seen_gated, 0u);
  EXPECT_EQ(verify.seen_gated, 0u);
  EXPECT_EQ(verify.steps, off.steps);
  EXPECT_EQ(verify.seen_checks, off.seen_checks);
  EXPECT_EQ(verify.targets_seen_on_the_way, off.targets_seen_on_the_way);
  EXPECT_DOUBLE_EQ(verify.path_length_m, off.path_length_m);
  EXPECT_LE(verify.seen_gate_misses, verify.seen_checks);
  EXPECT_GT(on.seen_gated, 0u);
  EXPECT_GT(on.targets_seen_on_the_way, 0u);
  EXPECT_TRUE(on.termination_reason == "no frontier" ||
              on.termination_reason == "no reachable frontier")
      << on.termination_reason;
  EXPECT_EQ(hits, 0u);
  // The ini: a fraction outside (0, 1] names the key.
  mission::ExplorationLoopParams p;
  mrpt::config::CConfigFileMemory m;
  m.write("explore", "seen_gate_fraction", "1");
  p.loadFromConfigFile(m, "explore");
  EXPECT_EQ(p.seen_gate_fraction, 1.0);
  m.write("explore", "seen_gate_fraction", "0");
  test::expectErrorNaming([&] { p.loadFromConfigFile(m, "explore"); }, "seen_gate_fraction",
                          "seen_gate_fraction = 0");
}

TEST(ExplorationLoop, StagnationWaitsWhileAFrontierWasNeverPlanned)
{
  // The guard: a window that says stop does not end the run while a
  // frontier left lies away from every frontier planned so far (a room
  // never targeted); when the run does end by stagnation, none is new.
  RobotSetup setup = pathWindowSetup();
  // The thesis' drives to the plan's end: the course on which the window
  // closes while a room is still new (with replan_at_stops the window closes
  // with no new frontier left, and the guard has nothing to hold).
  setup.loop.replan_at_stops = mission::ExplorationLoopParams::Switch::Off;
  CountingListener plain;
  const auto without = exploreTwoRooms(setup, &plain);
  ASSERT_EQ(without.termination_reason, "stagnation");
  ASSERT_GT(without.new_frontiers, 0u) << "the test needs a new frontier at the window's end";
  setup.loop.stagnation_new_frontier_guard = true;
  CountingListener guarded;
  const auto with = exploreTwoRooms(setup, &guarded);
  EXPECT_GT(guarded.plans, plain.plans);
  if (with.termination_reason == "stagnation")
  {
    EXPECT_EQ(with.new_frontiers, 0u);
  }
  // Off by default.
  EXPECT_FALSE(mission::ExplorationLoopParams{}.stagnation_new_frontier_guard);
}

// [path] turn_on_the_way_deg = auto (issue 15): what the loop and voxplore-plan
// plan with: on (150 deg, under a half turn) when scanning while driving,
// off for stop-and-scan; a configured value as it is.
TEST(ExplorationLoopParams, TurnOnTheWayAutoFollowsTheScanMode)
{
  using mission::ExplorationLoopParams;
  using M = ExplorationLoopParams::ScanMode;
  EXPECT_EQ(ExplorationLoopParams::turnOnTheWayDegInForce(-1, M::Continuous), 150.0);
  EXPECT_EQ(ExplorationLoopParams::turnOnTheWayDegInForce(-1, M::StopAndScan), 0.0);
  EXPECT_EQ(ExplorationLoopParams::turnOnTheWayDegInForce(20, M::StopAndScan), 20.0);
  EXPECT_EQ(ExplorationLoopParams::turnOnTheWayDegInForce(0, M::Continuous), 0.0);
}
