/* voxplore — a safety layer between the driving and the robot: no velocity
 * command may bring the footprint rectangle nearer than a margin to a sensed
 * obstacle point.
 *
 * Our own, forced by a measured weakness: MRPT's CPTG_Holo_Blend sees the
 * robot as its circumcircle (polygonal shapes exist only for the
 * differential-drive PTGs), CHolonomicND lets that circle graze obstacles
 * (secure_distance_start), and our straight and back-off recoveries test a
 * circle too. In the buildings campaign (9fffcc7) the footprint came within
 * 4-8 mm of a wall in 6 runs and hit one in 2 (compact robot, nearest). */
#pragma once
#include <mrpt/maps/CSimplePointsMap.h>
#include <voxplore/navigation/RobotInterface.h>

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

namespace voxplore::navigation::detail
{
/// @brief Distance from the rectangle (half extents hl along +X, hw along +Y)
///        placed at `pose` to the nearest of `points` (same frame as pose);
///        0 when a point is inside; +infinity without points.
double rectangleClearance(const std::vector<Eigen::Vector2d>& points, double hl, double hw,
                          const mrpt::poses::CPose2D& pose);

/// @brief The robot pose after holding the robot-frame twist for t seconds,
///        relative to the pose at t = 0 (translation along the heading at
///        mid-time, as the simulator integrates).
mrpt::poses::CPose2D poseAfter(double vx, double vy, double w, double t);

/// @brief Settings of the guard (from DriverParams).
struct GuardParams
{
  double length_m = 1.2;     ///< footprint along +X [m]
  double width_m = 0.712;    ///< footprint along +Y [m]
  double margin_m = 0.03;    ///< clearance the guard keeps [m]
  double horizon_s = 0.3;    ///< a command must keep the margin over this long [s]
  /// The base's acceleration limits (0 = commands are executed at once): a
  /// command must keep the margin while the base ramps towards it for
  /// horizon_s and then brakes to a stand [m/s^2], [rad/s^2].
  double max_accel_mps2 = 0;
  double max_angular_accel = 0;
  double z_min_m = 0.05;     ///< obstacle points below this are floor [m]
  double z_max_m = 0.70;     ///< points above this pass over the robot [m]
};

/// @brief A RobotInterface that forwards to another one and scales every
///        velocity command down (keeping its direction and curvature) until
///        holding it for horizon_s (with acceleration limits: ramping towards
///        it from the velocity the base holds, then braking to a stand)
///        keeps the footprint at least margin_m from
///        every obstacle point the robot senses, or does not bring it closer
///        when it already is nearer than that (so the robot can always back
///        away). The obstacle points are read once per robot time step.
class FootprintGuard : public RobotInterface
{
 public:
  FootprintGuard(RobotInterface& inner, const GuardParams& params);

  void setVelocity(double vx_mps, double vy_mps, double w_radps) override;
  void stop() override;
  mrpt::poses::CPose2D pose() const override { return inner_.pose(); }
  mrpt::poses::CPose2D odometry() const override { return inner_.odometry(); }
  mrpt::math::TTwist2D velocity() const override { return inner_.velocity(); }
  bool obstacles(mrpt::maps::CSimplePointsMap& out_robot_frame) override;
  mrpt::Clock::time_point now() const override { return inner_.now(); }
  void step(double dt_s) override;
  std::optional<std::size_t> collisionCount() const override { return inner_.collisionCount(); }

  /// @brief Robot time the guard has held the robot (scale below 5 % of a
  ///        non-zero command) without a break [s].
  double heldFor_s() const { return held_s_; }
  /// @brief The footprint's clearance to the sensed points at the last
  ///        command [m] (+infinity when none was in reach).
  double lastClearance_m() const { return last_clearance_m_; }
  /// @brief Commands scaled down so far, and commands held (scale < 5 %).
  std::size_t scaledCommands() const { return scaled_; }
  std::size_t heldCommands() const { return held_; }

 private:
  bool refreshPoints();
  double commandClearance(double vx, double vy, double w) const;
  double rampedClearance(double vx, double vy, double w) const;
  bool accelerationLimited() const
  {
    return params_.max_accel_mps2 > 0 || params_.max_angular_accel > 0;
  }

  RobotInterface& inner_;
  GuardParams params_;
  mrpt::maps::CSimplePointsMap raw_;
  std::optional<mrpt::Clock::time_point> raw_time_;  // when raw_ was sensed
  bool raw_ok_ = false;
  std::vector<Eigen::Vector2d> near_;      // points in the height band within reach
  std::vector<Eigen::Vector2d> relevant_;  // ... that the current command can come near
  bool held_now_ = false;
  double held_s_ = 0, last_clearance_m_ = 0;
  std::size_t scaled_ = 0, held_ = 0;
};

}  // namespace voxplore::navigation::detail
