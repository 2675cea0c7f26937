/* voxplore — the simulated omnidirectional robot: kinematics, motion and odometry noise. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/math/TTwist2D.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/CollisionChecker.h>

#include <random>
#include <string>
#include <vector>

namespace voxplore::sim
{
/// @brief Body, speed limits and noise of the robot. ini section [robot].
///
/// Odometry noise is MRPT's Gaussian motion model
/// (CActionRobotMovement2D::TMotionModelOptions::gaussianModel), drawn once
/// per odometry reading on the increment since the previous reading.
struct RobotParams : public mrpt::config::CLoadableOptions
{
  std::string profile = "omnirob";  ///< informative: omnirob | compact | custom
  double length_m = 1.200;  ///< footprint along +X (KUKA omniRob) [m]
  double width_m = 0.712;   ///< footprint along +Y [m]
  double height_m = 0.645;  ///< body height: geometry above it cannot be hit [m]
  double camera_height_m = 0.60;  ///< height of the camera ring [m]
  double max_v_mps = 0.5;   ///< translation speed limit used by the simulator [m/s]
  double max_w = mrpt::DEG2RAD(45.0);  ///< rotation speed limit [rad/s] (ini: deg/s)
  /// Translation acceleration limit (the body-frame velocity vector changes by
  /// at most this per second, braking too); 0 = a command is executed at once [m/s^2]
  double max_accel_mps2 = 0;
  /// Rotation acceleration limit; 0 = at once [rad/s^2] (ini: deg/s^2)
  double max_angular_accel = 0;
  double motion_noise_rel = 0.02;  ///< executed vs commanded velocity, relative 1-sigma
  double odo_a1 = 0.01;    ///< odometry xy std per metre travelled [m/m]
  double odo_a2 = mrpt::RAD2DEG(0.001);  ///< odometry xy std per radian turned [m/rad]
  double odo_a3 = mrpt::DEG2RAD(1.0);    ///< odometry yaw std per metre travelled [rad/m]
  double odo_a4 = 0.02;    ///< odometry yaw std per radian turned [rad/rad]
  double odo_min_std_xy_m = 0.002;  ///< odometry xy std floor per reading [m]
  double odo_min_std_phi = mrpt::DEG2RAD(0.1);  ///< odometry yaw std floor per reading [rad] (ini: deg)
  bool odometry_noise = true;  ///< false: odometry equals ground truth motion

  /// @brief The KUKA omniRob (thesis 4.1.1): 1.2 x 0.712 x 0.645 m.
  static RobotParams omnirob();
  /// @brief A smaller profile for houses with narrow doors: 0.50 x 0.36 x 0.65 m.
  static RobotParams compact();
  /// @brief omnirob() or compact() by name.
  /// @throws std::runtime_error for another name.
  static RobotParams byName(const std::string& name);

  Footprint footprint() const { return {length_m, width_m}; }
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions motionModel() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Omnidirectional (mecanum) kinematics with a ground-truth pose, a
///        noisy odometry, and a collision stop.
class OmniRobot
{
 public:
  OmniRobot(const RobotParams& params, const mrpt::poses::CPose2D& start);

  /// @brief Result of one integration step.
  struct StepResult
  {
    bool collided = false;  ///< the step was refused: the footprint would hit the world
  };

  /// @brief Integrates a robot-frame velocity command (clamped to the limits,
  ///        reached at the acceleration limits, perturbed by motion noise) for
  ///        `dt_s`. When `checker` says the new pose collides, the robot stays
  ///        where it is, stands still, and the step counts as a collision.
  StepResult step(
      double vx_mps, double vy_mps, double w_radps, double dt_s, std::mt19937_64& rng,
      const CollisionChecker* checker);

  /// @brief Reads the odometry: draws MRPT-model noise on the ground-truth
  ///        increment since the previous reading and accumulates it. The
  ///        odometry frame starts at (0,0,0) where the robot starts.
  /// @return the accumulated odometry pose
  mrpt::poses::CPose2D readOdometry(std::mt19937_64& rng);

  /// @brief Covariance MRPT's Gaussian model gives for an odometry increment.
  mrpt::math::CMatrixDouble33 odometryCovariance(const mrpt::poses::CPose2D& increment) const;

  const mrpt::poses::CPose2D& groundTruth() const { return gt_; }
  /// @brief The robot-frame velocity the base holds now (the last command
  ///        ramped at the acceleration limits, common::rampedVelocity();
  ///        without motion noise).
  const mrpt::math::TTwist2D& velocity() const { return vel_; }
  const mrpt::poses::CPose2D& lastOdometry() const { return odo_; }
  const RobotParams& params() const { return params_; }
  std::size_t collisions() const { return collision_poses_.size(); }
  /// @brief World pose the robot stood at for each refused step, in order.
  const std::vector<mrpt::poses::CPose2D>& collisionPoses() const { return collision_poses_; }
  double distanceTravelled() const { return travelled_m_; }

 private:
  RobotParams params_;
  mrpt::poses::CPose2D gt_;
  mrpt::poses::CPose2D gt_at_last_read_;
  mrpt::poses::CPose2D odo_;
  mrpt::math::TTwist2D vel_{0, 0, 0};
  std::vector<mrpt::poses::CPose2D> collision_poses_;  // one per refused step
  double travelled_m_ = 0;
};

}  // namespace voxplore::sim
