#include <mrpt/core/exceptions.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDF.h>
#include <voxplore/common/config.h>
#include <voxplore/common/velocity_ramp.h>
#include <voxplore/sim/Robot.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace voxplore::sim
{
using mrpt::poses::CPose2D;

RobotParams RobotParams::omnirob() { return RobotParams{}; }

RobotParams RobotParams::compact()
{
  RobotParams p;
  p.profile = "compact";
  p.length_m = 0.50;
  p.width_m = 0.36;
  p.height_m = 0.65;
  p.camera_height_m = 0.60;
  return p;
}

RobotParams RobotParams::byName(const std::string& name)
{
  if (name == "omnirob") return omnirob();
  if (name == "compact") return compact();
  throw std::runtime_error("unknown robot profile '" + name + "' (known: omnirob, compact)");
}

mrpt::obs::CActionRobotMovement2D::TMotionModelOptions RobotParams::motionModel() const
{
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions m;
  m.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
  m.gaussianModel = {odo_a1, odo_a2, odo_a3, odo_a4, odo_min_std_xy_m, odo_min_std_phi};
  return m;
}

void RobotParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(profile, string, c, s);
  MRPT_LOAD_CONFIG_VAR(length_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_v_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_w, c, s);
  MRPT_LOAD_CONFIG_VAR(max_accel_mps2, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_angular_accel, c, s);
  MRPT_LOAD_CONFIG_VAR(motion_noise_rel, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odo_a1, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odo_a2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odo_a3, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odo_a4, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odo_min_std_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(odo_min_std_phi, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_noise, bool, c, s);
  using common::requireValid;
  requireValid(length_m > 0 && width_m > 0 && height_m > 0, c, s, "length_m",
               "robot dimensions must be positive");
  requireValid(camera_height_m > 0, c, s, "camera_height_m", "must be positive");
  requireValid(max_v_mps > 0, c, s, "max_v_mps", "must be positive");
  requireValid(max_w > 0, c, s, "max_w", "must be positive");
  requireValid(max_accel_mps2 >= 0, c, s, "max_accel_mps2", "must be >= 0 (0 = no limit)");
  requireValid(max_angular_accel >= 0, c, s, "max_angular_accel", "must be >= 0 (0 = no limit)");
  requireValid(motion_noise_rel >= 0, c, s, "motion_noise_rel", "must be >= 0");
  requireValid(odo_a1 >= 0 && odo_a2 >= 0 && odo_a3 >= 0 && odo_a4 >= 0, c, s, "odo_a1",
               "odometry model coefficients must be >= 0");
  requireValid(odo_min_std_xy_m >= 0 && odo_min_std_phi >= 0, c, s, "odo_min_std_xy_m",
               "must be >= 0");
}

void RobotParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(profile, c, s);
  MRPT_SAVE_CONFIG_VAR(length_m, c, s);
  MRPT_SAVE_CONFIG_VAR(width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_v_mps, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_w, c, s);
  MRPT_SAVE_CONFIG_VAR(max_accel_mps2, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_angular_accel, c, s);
  MRPT_SAVE_CONFIG_VAR(motion_noise_rel, c, s);
  MRPT_SAVE_CONFIG_VAR(odo_a1, c, s);
  MRPT_SAVE_CONFIG_VAR(odo_a2, c, s);
  MRPT_SAVE_CONFIG_VAR(odo_a3, c, s);
  MRPT_SAVE_CONFIG_VAR(odo_a4, c, s);
  MRPT_SAVE_CONFIG_VAR(odo_min_std_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(odo_min_std_phi, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_noise, c, s);
}

OmniRobot::OmniRobot(const RobotParams& params, const CPose2D& start)
    : params_(params), gt_(start), gt_at_last_read_(start)
{
}

OmniRobot::StepResult OmniRobot::step(
    double vx_mps, double vy_mps, double w_radps, double dt_s, std::mt19937_64& rng,
    const CollisionChecker* checker)
{
  // Clamp to the limits (translation as a vector: omnidirectional base).
  const double v = std::hypot(vx_mps, vy_mps);
  if (v > params_.max_v_mps)
  {
    vx_mps *= params_.max_v_mps / v;
    vy_mps *= params_.max_v_mps / v;
  }
  w_radps = std::clamp(w_radps, -params_.max_w, params_.max_w);
  vel_ = common::rampedVelocity(vel_, {vx_mps, vy_mps, w_radps}, params_.max_accel_mps2,
                                params_.max_angular_accel, dt_s);
  vx_mps = vel_.vx;
  vy_mps = vel_.vy;
  w_radps = vel_.omega;

  // Executed velocity = commanded x (1 + relative Gaussian error).
  std::normal_distribution<double> gauss(0.0, params_.motion_noise_rel);
  vx_mps *= 1.0 + gauss(rng);
  vy_mps *= 1.0 + gauss(rng);
  w_radps *= 1.0 + gauss(rng);

  // Exact for constant body velocities over short dt: translate along the
  // heading at the middle of the step.
  const double mid_yaw = gt_.phi() + 0.5 * w_radps * dt_s;
  const double c = std::cos(mid_yaw), s = std::sin(mid_yaw);
  const double dx = (c * vx_mps - s * vy_mps) * dt_s;
  const double dy = (s * vx_mps + c * vy_mps) * dt_s;
  const CPose2D next(gt_.x() + dx, gt_.y() + dy, mrpt::math::wrapToPi(gt_.phi() + w_radps * dt_s));

  StepResult r;
  if (checker && checker->collides(next, params_.footprint()))
  {
    collision_poses_.push_back(gt_);
    vel_ = {0, 0, 0};  // the bumper stops the base
    r.collided = true;
    return r;
  }
  travelled_m_ += std::hypot(dx, dy);
  gt_ = next;
  return r;
}

mrpt::math::CMatrixDouble33 OmniRobot::odometryCovariance(const CPose2D& increment) const
{
  mrpt::obs::CActionRobotMovement2D act;
  act.computeFromOdometry(increment, params_.motionModel());
  mrpt::math::CMatrixDouble33 cov;
  act.poseChange->getCovariance(cov);
  return cov;
}

CPose2D OmniRobot::readOdometry(std::mt19937_64& rng)
{
  const CPose2D inc = gt_ - gt_at_last_read_;  // increment in the previous robot frame
  gt_at_last_read_ = gt_;
  const bool moved =
      std::abs(inc.x()) > 1e-9 || std::abs(inc.y()) > 1e-9 || std::abs(inc.phi()) > 1e-9;
  CPose2D noisy = inc;
  if (params_.odometry_noise && moved)
  {
    // Draw from MRPT's Gaussian motion model of this increment with our own
    // seeded generator (MRPT's drawSingleSample uses a global RNG).
    const Eigen::Matrix3d cov = odometryCovariance(inc).asEigen();
    const Eigen::Matrix3d L = cov.llt().matrixL();
    std::normal_distribution<double> gauss(0.0, 1.0);
    const Eigen::Vector3d z(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Vector3d e = L * z;
    noisy = CPose2D(inc.x() + e[0], inc.y() + e[1], mrpt::math::wrapToPi(inc.phi() + e[2]));
  }
  odo_ = odo_ + noisy;
  return odo_;
}

}  // namespace voxplore::sim
