/* voxplore — the robot the navigation drives: velocity commands in, pose and obstacles out.
 *
 * No simulator types here: the simulator (voxplore::apps::SimRobot), a rawlog
 * replay or a real platform implement this interface, and
 * navigation::StopAndScanDriver only ever talks to it.
 *
 * Who owns the clock: the implementation. now() is the robot's time, and the
 * navigation (MRPT's reactive navigator included) reads time only through
 * now() and mrpt::Clock::now(). A simulator must therefore switch MRPT to
 * its simulated clock (mrpt::Clock::setActiveClock(mrpt::Clock::Simulated))
 * and advance it inside step(), so that mrpt::Clock::now() == now() after
 * every step; a real robot keeps MRPT's real-time clock and sleeps in step(). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/math/TTwist2D.h>
#include <mrpt/poses/CPose2D.h>

#include <cstddef>
#include <optional>

namespace voxplore::navigation
{
/// @brief An omnidirectional planar robot as the navigation sees it.
///
/// Frames: the map frame is the world frame of pose(); the robot frame is
/// +X forward, +Y left, +Z up with the floor at z = 0. Units: m, rad, s.
class RobotInterface
{
 public:
  virtual ~RobotInterface() = default;

  /// @brief Commands a robot-frame velocity, held until the next
  ///        setVelocity() or stop() (the platform clamps it to its limits).
  /// @param vx_mps forward speed [m/s]
  /// @param vy_mps leftward speed [m/s]
  /// @param w_radps turn rate, counter-clockwise positive [rad/s]
  virtual void setVelocity(double vx_mps, double vy_mps, double w_radps) = 0;

  /// @brief Commands zero velocity now (the robot stands still from the
  ///        next step() on).
  virtual void stop() = 0;

  /// @brief Best pose estimate of the robot in the map frame (ground truth
  ///        in a simulator by default, the SLAM pose in the explore app).
  virtual mrpt::poses::CPose2D pose() const = 0;

  /// @brief Raw odometry pose (own frame, may drift; locally smooth).
  virtual mrpt::poses::CPose2D odometry() const = 0;

  /// @brief Current velocity in the robot frame (vx, vy [m/s], omega [rad/s]).
  virtual mrpt::math::TTwist2D velocity() const = 0;

  /// @brief The latest obstacle points in the robot frame, floor removed
  ///        (z is the height above the floor; the navigator keeps only the
  ///        points in its own height band).
  /// @param out_robot_frame cleared and filled
  /// @return false when the sensors failed (the navigation then stops with
  ///         an error); true otherwise, also when no obstacle is in view.
  virtual bool obstacles(mrpt::maps::CSimplePointsMap& out_robot_frame) = 0;

  /// @brief The robot's clock (see the file comment: equal to
  ///        mrpt::Clock::now() after every step()).
  virtual mrpt::Clock::time_point now() const = 0;

  /// @brief Lets `dt_s` seconds pass while executing the last command: a
  ///        real robot sleeps, a simulator integrates and advances its clock.
  virtual void step(double dt_s) = 0;

  /// @brief Number of collisions (bumper hits) since the robot was created.
  /// @return std::nullopt when the platform cannot detect collisions.
  virtual std::optional<std::size_t> collisionCount() const { return std::nullopt; }
};

/// @brief The robot's velocity() is not zero: a pass left it moving
///        (scanning while driving), where stop-and-scan always stands.
inline bool isMoving(const RobotInterface& robot)
{
  const auto v = robot.velocity();
  return v.vx != 0 || v.vy != 0 || v.omega != 0;
}

}  // namespace voxplore::navigation
