/* voxplore — the simulator behind navigation::RobotInterface. */
#pragma once

#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/RobotInterface.h>
#include <voxplore/sim/Simulator.h>

#include <functional>
#include <vector>

namespace voxplore::apps
{
/// @brief The obstacle sensor of SimRobot: a 360 deg fan of horizontal rays
///        from the robot centre at each of several heights, cast against the
///        world mesh (a multi-layer 2D lidar).
///
/// Why not the depth cameras: the thesis' ring sees nothing within about
/// 1 m of the robot (cameras at 0.6 m pitched down 15 deg) and rendering 8
/// cameras per 0.1 s step would cost far more than these few thousand rays.
/// A reactive navigator without memory needs the near field, which a real
/// omniRob gets from its safety laser scanners; this fan stands in for them.
/// The heights span the robot body (0.645 m): chair seats and table legs are
/// seen, table tops (0.71 m and up) pass over the robot.
struct SimObstacleSensor
{
  /// Ray heights above the floor [m]: every 0.1 m from just above the floor
  /// clearance to just below the robots' top (0.645 / 0.65 m), so that a
  /// table top or shelf anywhere in the robot's slab is seen (with layers at
  /// 0.10/0.30/0.50 only, the compact robot drove into a table top at ~0.6 m
  /// in turtlebot3_house).
  std::vector<double> heights_m = {0.05, 0.15, 0.25, 0.35, 0.45, 0.55, 0.62};
  int rays_per_layer = 720;  ///< rays per 360 deg (0.5 deg apart: 4 cm legs seen to 4.5 m)
  double max_range_m = 6.0;  ///< farther hits are dropped [m]
};

/// @brief navigation::RobotInterface over a sim::Simulator.
///
/// Clock: the constructor makes MRPT's clock simulated
/// (mrpt::Clock::setActiveClock(mrpt::Clock::Simulated)) and sets it to
/// Simulator::now(); every step() advances the Simulator and sets MRPT's
/// clock to its time again, so now() == mrpt::Clock::now() always. This is
/// process-wide state: the destructor restores the previous clock source.
/// Use one SimRobot at a time.
class SimRobot : public navigation::RobotInterface
{
 public:
  /// @brief Where pose() comes from; empty = the simulator's ground truth.
  using PoseSource = std::function<mrpt::poses::CPose2D()>;

  explicit SimRobot(sim::Simulator& sim, const SimObstacleSensor& sensor = {});
  ~SimRobot() override;
  SimRobot(const SimRobot&) = delete;
  SimRobot& operator=(const SimRobot&) = delete;

  /// @brief Replaces the pose estimate (e.g. the SLAM pose in the explore
  ///        app); an empty function restores the ground truth.
  void setPoseSource(PoseSource source) { pose_source_ = std::move(source); }

  /// @brief Stores the command; the Simulator clamps it to RobotParams' limits.
  void setVelocity(double vx_mps, double vy_mps, double w_radps) override;
  void stop() override;
  mrpt::poses::CPose2D pose() const override;
  /// @brief Noise-free odometry: the ground truth relative to the pose at
  ///        construction (the Simulator draws noisy odometry only when scanning).
  mrpt::poses::CPose2D odometry() const override;
  /// @brief The commanded velocity (the simulator executes it up to motion
  ///        noise, or not at all when the step would collide); with
  ///        acceleration limits ([robot] max_accel_mps2, max_angular_accel)
  ///        the velocity the base holds, which reaches the command over time.
  mrpt::math::TTwist2D velocity() const override;
  /// @brief Casts the SimObstacleSensor fan at the true pose.
  bool obstacles(mrpt::maps::CSimplePointsMap& out_robot_frame) override;
  mrpt::Clock::time_point now() const override { return sim_.now(); }
  /// @brief Runs dt_s / SimulatorParams::dt_s simulator steps.
  /// @throws std::invalid_argument when dt_s is not a positive multiple of
  ///         the simulator's dt_s.
  void step(double dt_s) override;
  /// @brief sim::OmniRobot::collisions(): steps refused because they would collide.
  std::optional<std::size_t> collisionCount() const override { return sim_.robot().collisions(); }

  sim::Simulator& simulator() { return sim_; }
  const SimObstacleSensor& sensor() const { return sensor_; }

 private:
  sim::Simulator& sim_;
  SimObstacleSensor sensor_;
  PoseSource pose_source_;
  mrpt::math::TTwist2D cmd_{0, 0, 0};
  mrpt::poses::CPose2D odometry_origin_;
  mrpt::Clock::Source previous_clock_;
  std::vector<Eigen::Vector3f> dirs_robot_;  ///< per ray, robot frame (unit, z = 0)
};

/// @brief mission::ScanSource over a sim::Simulator: Simulator::scan(),
///        keeping the last stop (its ground-truth pose, for the evaluation).
class SimScanSource : public mission::ScanSource
{
 public:
  /// @param robot when given, a scan while its commanded velocity is not
  ///        zero is a moving one (Simulator::scan(true)).
  explicit SimScanSource(sim::Simulator& sim, const navigation::RobotInterface* robot = nullptr)
      : sim_(sim), robot_(robot)
  {
  }
  mission::Scan scan() override;
  /// @brief The last stop scan() delivered (index, ground truth, ...).
  const sim::ScanStop& last() const { return last_; }

 private:
  sim::Simulator& sim_;
  const navigation::RobotInterface* robot_;
  sim::ScanStop last_;
};

/// @brief mission::Clock of a sim::Simulator: its simulated time.
class SimClock : public mission::Clock
{
 public:
  explicit SimClock(const sim::Simulator& sim) : sim_(sim) {}
  mrpt::Clock::time_point now() const override { return sim_.now(); }

 private:
  const sim::Simulator& sim_;
};

}  // namespace voxplore::apps
