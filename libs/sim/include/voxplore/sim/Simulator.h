/* voxplore — the simulator: a world, an omnidirectional robot and its depth cameras. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/Robot.h>
#include <voxplore/sim/World.h>

#include <deque>
#include <memory>
#include <optional>
#include <random>

namespace voxplore::sim
{
/// @brief Simulation settings. ini section [simulator].
struct SimulatorParams : public mrpt::config::CLoadableOptions
{
  double dt_s = 0.05;               ///< integration step [s]
  double scan_every_m = 0.5;        ///< stop and scan after this much travel along a segment [m]
  double goal_tolerance_m = 0.01;   ///< a stop point is reached within this distance [m]
  double goal_tolerance_yaw = mrpt::DEG2RAD(1.0);  ///< ... and this yaw error [rad] (ini: deg)
  double floor_clearance_m = 0.03;  ///< geometry below this height is floor (drivable) [m]
  double segment_timeout_s = 120.0; ///< give up a stop point after this long [s]
  bool sensor_noise = true;         ///< Gaussian range noise on the depth images
  /// A scan taken while the robot moves (Simulator::scan(true)): the cameras
  /// are exposed one after another, camera c of N this long before camera
  /// c + 1, the last one when the scan is delivered; each image is rendered
  /// from the robot's true pose at its own exposure and timestamped then. The
  /// default puts the eight O3D100 exposures one after another into one
  /// 20 Hz period (overlapping ToF cameras must not expose at once). A
  /// standing scan exposes all at once. 0 = all at once [s].
  double camera_stagger_s = 0.05 / 8;
  double start_time_s = 1.7e9;      ///< simulated clock at start (UNIX seconds)
  int seed = 1;                     ///< seeds every random draw (motion, odometry, sensor noise)

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Everything the robot delivers at one stop.
struct ScanStop
{
  std::size_t index = 0;                         ///< 0-based stop counter
  mrpt::Clock::time_point timestamp;             ///< simulated time of the scan
  mrpt::poses::CPose2D T_world_robot_gt;         ///< ground truth
  mrpt::poses::CPose2D odometry;                 ///< accumulated noisy odometry
  mrpt::obs::CActionCollection::Ptr actions;     ///< odometry increment since the previous stop
  mrpt::obs::CSensoryFrame::Ptr observations;    ///< N x CObservation3DRangeScan + CObservationOdometry
};

/// @brief Result of driving to a point.
enum class DriveOutcome
{
  Reached,  ///< within tolerance
  Blocked,  ///< the next step would collide; the robot stopped in front of it
  Timeout   ///< segment_timeout_s elapsed
};

const char* toString(DriveOutcome o);

/// @brief Owns the world geometry (ray caster, collision checker), the robot
///        and the camera rig; advances a simulated clock. Deterministic for
///        SimulatorParams::seed.
class Simulator
{
 public:
  /// @throws std::runtime_error naming the world file when the start pose
  ///         collides or lies inside an obstacle.
  Simulator(
      World world, const RobotParams& robot, const CameraRigParams& cameras,
      const SimulatorParams& sim);
  // The collision checker points into world_: not copyable, not movable.
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;
  Simulator(Simulator&&) = delete;
  Simulator& operator=(Simulator&&) = delete;

  /// @brief One velocity step of dt_s (robot frame).
  OmniRobot::StepResult step(double vx_mps, double vy_mps, double w_radps);

  /// @brief Drives in a straight line to (x, y), turning to `yaw` on the way
  ///        when given, and stops there (P-controller on the true pose).
  DriveOutcome driveTo(double x, double y, std::optional<double> yaw_rad);

  /// @brief Stops and scans: reads odometry, renders every camera.
  ///        `moving` = false (stop-and-scan): the robot stands one sensor
  ///        period (0.05 s) and every camera sees it from its pose now.
  ///        `moving` = true (scanning while driving): no time passes, camera c
  ///        sees the world from the robot's true pose at its exposure
  ///        (SimulatorParams::camera_stagger_s), and the odometry observation
  ///        carries the robot's velocity (CObservationOdometry::velocityLocal,
  ///        the motion executed over the last simulator step) for deskewing.
  ScanStop scan(bool moving = false);

  const World& world() const { return world_; }
  const RayCaster& caster() const { return *caster_; }
  const CollisionChecker& checker() const { return *checker_; }
  const OmniRobot& robot() const { return robot_; }
  const DepthCameraRig& rig() const { return rig_; }
  const SimulatorParams& params() const { return params_; }
  mrpt::Clock::time_point now() const;
  double simTime() const { return sim_time_s_; }
  std::size_t numStops() const { return stops_; }

 private:
  World world_;
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<CollisionChecker> checker_;
  SimulatorParams params_;
  OmniRobot robot_;
  DepthCameraRig rig_;
  std::mt19937_64 rng_motion_, rng_odo_, rng_sensor_;
  double sim_time_s_ = 0;
  std::size_t stops_ = 0;
  mrpt::poses::CPose2D odo_at_last_stop_;
  /// (sim time, true pose) after each step of the last second or so.
  std::deque<std::pair<double, mrpt::poses::CPose2D>> history_;
  /// The true pose at sim time t (linear between the steps of history_;
  /// the oldest kept, or the pose now, outside it).
  mrpt::poses::CPose2D trueposeAt(double t) const;
};

}  // namespace voxplore::sim
