// The simulated omnidirectional robot: kinematics, collision stop, odometry noise model.
#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/Robot.h>

#include <cmath>

#include "test_worlds.h"

using namespace voxplore;
using mrpt::poses::CPose2D;

namespace
{
sim::RobotParams noiseless()
{
  auto p = sim::RobotParams::omnirob();
  p.motion_noise_rel = 0;
  p.odometry_noise = false;
  return p;
}
}  // namespace

TEST(OmniRobot, OmnidirectionalKinematics)
{
  sim::OmniRobot r(noiseless(), CPose2D(1, 2, M_PI / 2));
  std::mt19937_64 rng(1);
  for (int i = 0; i < 40; i++) r.step(0.0, 0.5, 0.0, 0.05, rng, nullptr);  // 1 m to the left
  EXPECT_NEAR(r.groundTruth().x(), 0.0, 1e-9);
  EXPECT_NEAR(r.groundTruth().y(), 2.0, 1e-9);
  EXPECT_NEAR(r.groundTruth().phi(), M_PI / 2, 1e-12);
  EXPECT_NEAR(r.distanceTravelled(), 1.0, 1e-9);
  // Speed limit: a 10 m/s command moves at max_v_mps.
  const double x0 = r.groundTruth().x(), y0 = r.groundTruth().y();
  r.step(10.0, 0.0, 0.0, 1.0, rng, nullptr);
  EXPECT_NEAR(std::hypot(r.groundTruth().x() - x0, r.groundTruth().y() - y0), 0.5, 1e-9);
  // Rotation limit
  const double phi0 = r.groundTruth().phi();
  r.step(0.0, 0.0, 10.0, 0.5, rng, nullptr);
  EXPECT_NEAR(mrpt::math::wrapToPi(r.groundTruth().phi() - phi0), mrpt::DEG2RAD(45.0) * 0.5, 1e-9);
}

TEST(OmniRobot, AccelerationLimitsRampTheVelocityUpAndDownAndABumpStopsIt)
{
  auto p = noiseless();
  p.max_accel_mps2 = 1.0;
  p.max_angular_accel = mrpt::DEG2RAD(90.0);
  sim::OmniRobot r(p, CPose2D(0, 0, 0));
  std::mt19937_64 rng(1);
  r.step(0.5, 0.0, 0.0, 0.05, rng, nullptr);
  EXPECT_NEAR(r.velocity().vx, 0.05, 1e-12) << "1 m/s^2 for 50 ms";
  for (int i = 1; i < 20; i++) r.step(0.5, 0.0, 0.0, 0.05, rng, nullptr);
  EXPECT_NEAR(r.velocity().vx, 0.5, 1e-12);
  // 0.5 s ramping (0.05 s x 0.05 x (1 + ... + 10) = 0.1375 m), 0.5 s at 0.5 m/s.
  EXPECT_NEAR(r.groundTruth().x(), 0.1375 + 0.25, 1e-9);
  // A turn commanded at once while translating: the translation brakes
  // (the vector moves towards zero) and the rotation ramps at 90 deg/s^2.
  r.step(0.0, 0.0, mrpt::DEG2RAD(45.0), 0.05, rng, nullptr);
  EXPECT_NEAR(r.velocity().vx, 0.45, 1e-12);
  EXPECT_NEAR(r.velocity().omega, mrpt::DEG2RAD(4.5), 1e-12);
  const double x0 = r.groundTruth().x();
  for (int i = 0; i < 20; i++) r.step(0.0, 0.0, 0.0, 0.05, rng, nullptr);
  EXPECT_EQ(r.velocity().vx, 0.0);
  EXPECT_EQ(r.velocity().omega, 0.0);
  EXPECT_NEAR(r.groundTruth().x() - x0, 0.05 * (0.40 + 0.35 + 0.30 + 0.25 + 0.20 + 0.15 + 0.10 + 0.05),
              1e-6) << "braking from 0.45 m/s at 1 m/s^2";
  // A bump stops the base: the next step starts from rest.
  const sim::World room = test::boxRoom(4, 4, 2.5, CPose2D(2, 2, 0));
  sim::CollisionChecker checker(room, 0.03, 0.645);
  sim::OmniRobot b(p, CPose2D(3.39, 2.0, 0));  // front 0.01 m from the wall at x = 4
  for (int i = 0; i < 5; i++) b.step(0.5, 0.0, 0.0, 0.05, rng, &checker);
  EXPECT_GT(b.collisions(), 0u);
  EXPECT_EQ(b.velocity().vx, 0.0);
}

TEST(OmniRobot, FirstOdometryIsOriginAndMatchesMotionWithoutNoise)
{
  sim::OmniRobot r(noiseless(), CPose2D(5, -3, 1.0));
  std::mt19937_64 rng(1);
  EXPECT_EQ(r.readOdometry(rng), CPose2D(0, 0, 0));
  for (int i = 0; i < 20; i++) r.step(0.4, 0.1, 0.2, 0.05, rng, nullptr);
  const CPose2D odo = r.readOdometry(rng);
  const CPose2D gt_rel = r.groundTruth() - CPose2D(5, -3, 1.0);
  EXPECT_NEAR(odo.x(), gt_rel.x(), 1e-9);
  EXPECT_NEAR(odo.y(), gt_rel.y(), 1e-9);
  EXPECT_NEAR(odo.phi(), gt_rel.phi(), 1e-9);
}

TEST(OmniRobot, OdometryErrorStatisticsMatchTheModel)
{
  auto p = noiseless();
  p.odometry_noise = true;
  const CPose2D inc(0.5, 0.1, mrpt::DEG2RAD(10.0));
  constexpr int kTrials = 20000;
  std::mt19937_64 rng(123);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d model = Eigen::Matrix3d::Zero();
  for (int k = 0; k < kTrials; k++)
  {
    sim::OmniRobot r(p, CPose2D());
    // Move exactly by `inc` (noise-free motion): rotate in place after translating.
    const int steps = 20;  // 0.25 m/s, below max_v_mps
    for (int i = 0; i < steps; i++) r.step(inc.x() / (0.1 * steps), inc.y() / (0.1 * steps), 0, 0.1, rng, nullptr);
    for (int i = 0; i < steps; i++) r.step(0, 0, inc.phi() / (0.1 * steps), 0.1, rng, nullptr);
    ASSERT_NEAR((r.groundTruth() - inc).norm(), 0.0, 1e-9);
    if (k == 0) model = r.odometryCovariance(inc).asEigen();
    const CPose2D odo = r.readOdometry(rng);
    const Eigen::Vector3d e(odo.x() - inc.x(), odo.y() - inc.y(),
                            mrpt::math::wrapToPi(odo.phi() - inc.phi()));
    sum += e;
    sum2 += e * e.transpose();
  }
  const Eigen::Vector3d mean = sum / kTrials;
  const Eigen::Matrix3d cov = sum2 / kTrials - mean * mean.transpose();
  for (int i = 0; i < 3; i++)
  {
    const double sd = std::sqrt(model(i, i));
    ASSERT_GT(sd, 0.0);
    EXPECT_NEAR(mean[i], 0.0, 4 * sd / std::sqrt(double(kTrials))) << "axis " << i;
    // Sample variance of 20,000 draws: relative standard error 1 %.
    EXPECT_NEAR(cov(i, i) / model(i, i), 1.0, 0.05) << "axis " << i;
  }
}

TEST(OmniRobot, CollisionStopsTheRobotInFrontOfAWall)
{
  // A wall at x in [3, 3.2]; drive towards it with many headings: the robot
  // stops, counts a collision and never passes into the wall.
  sim::World w = test::boxRoom(20, 20, 2.5, CPose2D(1, 10, 0));
  w.mesh.addBox({3.1f, 10.0f, 1.0f}, {0.2f, 20.0f, 2.0f});
  sim::CollisionChecker checker(w, 0.03, 0.645);
  for (int deg = 0; deg < 360; deg += 15)
  {
    const double yaw = mrpt::DEG2RAD(double(deg));
    sim::OmniRobot r(noiseless(), CPose2D(1.0, 10.0, yaw));
    std::mt19937_64 rng(1);
    // world +X velocity expressed in the robot frame
    const double vx = std::cos(yaw) * 0.5, vy = -std::sin(yaw) * 0.5;
    bool stopped = false;
    for (int i = 0; i < 200 && !stopped; i++) stopped = r.step(vx, vy, 0, 0.05, rng, &checker).collided;
    EXPECT_TRUE(stopped) << deg;
    EXPECT_EQ(r.collisions(), 1u);
    ASSERT_EQ(r.collisionPoses().size(), 1u);  // logged where the robot stood
    EXPECT_NEAR(r.collisionPoses()[0].x(), r.groundTruth().x(), 1e-12);
    const double half_extent = std::abs(0.6 * std::cos(yaw)) + std::abs(0.356 * std::sin(yaw));
    EXPECT_LT(r.groundTruth().x() + half_extent, 3.0) << deg;          // never inside the wall
    EXPECT_GT(r.groundTruth().x() + half_extent, 3.0 - 0.026) << deg;  // stopped within one step
  }
}

TEST(RobotParams, ProfilesAndConfigRoundTrip)
{
  EXPECT_NEAR(sim::RobotParams::omnirob().footprint().circumradius(), 0.698, 1e-3);
  EXPECT_LT(sim::RobotParams::compact().footprint().circumradius(), 0.35);
  EXPECT_THROW(sim::RobotParams::byName("tank"), std::runtime_error);
}
