/* voxplore — settings of the stop-and-scan driver and of MRPT's reactive navigator. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>

#include <string>
#include <vector>

namespace voxplore::navigation
{
/// @brief Driver and navigator settings. ini section [navigation].
///
/// MRPT's CReactiveNavigationSystem is configured from these fields only
/// (see writeMrptConfig()): a holonomic PTG (CPTG_Holo_Blend) with the
/// CHolonomicND method, the robot as the circle round its footprint. Every
/// key MRPT 2.5.8 throws on when missing gets its value here.
struct DriverParams : public mrpt::config::CLoadableOptions
{
  // --- robot ---
  double footprint_length_m = 1.200;  ///< robot footprint along +X (KUKA omniRob) [m]
  double footprint_width_m = 0.712;   ///< robot footprint along +Y [m]
  double shape_margin_m = 0.05;  ///< added to the footprint's circumradius for the navigator [m]
  double max_v_mps = 0.5;        ///< translation speed limit of the navigator [m/s]
  double max_w = mrpt::DEG2RAD(45.0);   ///< rotation speed limit [rad/s] (ini: deg/s)
  double max_accel_mps2 = 0;      ///< the base's translation acceleration limit; 0 = none [m/s^2]
  double max_angular_accel = 0;   ///< ... rotation [rad/s^2] (ini: deg/s^2); 0 = none
  double min_obstacle_height_m = 0.05;  ///< obstacle points below this are floor [m]
  double max_obstacle_height_m = 0.70;  ///< points above this pass over the robot [m]
  double obstacle_cell_m = 0.05;  ///< keep one obstacle point per XY cell this big (0: all) [m]

  // --- driving loop ---
  double dt_s = 0.1;                ///< navigation period: one navigationStep() per dt [s]
  double goal_tolerance_m = 0.05;   ///< a waypoint is reached within this distance [m]
  double timeout_s = 120.0;         ///< give up a waypoint after this much robot time [s]
  double blocked_timeout_s = 15.0;  ///< Blocked after this long without progress [s]
  double progress_min_m = 0.05;  ///< progress = the best distance to the goal shrank this much [m]
  int max_steps = 3000;          ///< hard limit of navigation steps per waypoint (never hangs)

  bool straight_fallback = true;     ///< when MRPT's navigator stalls, drive straight if the way is free (driveStraight)

  // --- recovery when pinned (no progress with obstacles at the robot's circle) ---
  double escape_clearance_m = 0.10;  ///< back off until the nearest obstacle is this far past robotRadius() [m]; 0 = no recovery
  double escape_speed_mps = 0.10;    ///< back-off speed [m/s]
  double escape_timeout_s = 4.0;     ///< longest back-off [s]

  // --- footprint guard (our own safety layer under every command) ---
  bool footprint_guard = true;    ///< scale every velocity command so the footprint rectangle keeps guard_margin_m from the sensed obstacle points
  double guard_margin_m = 0.03;   ///< clearance the guard keeps between the footprint and sensed obstacles [m]
  double guard_horizon_s = 0.3;   ///< a command must keep the margin when held this long [s]
  double guard_hold_s = 1.0;      ///< a drive the guard holds still this long ends Blocked [s]
  double footprint_backoff_m = 0.03;  ///< a drive starting within guard_margin_m + half this of a sensed point first backs the rectangle off to guard_margin_m + this (backOffFootprint) [m]; 0 = off
  double footprint_centring_m = 0.06;  ///< a footprint drive blocked by sensed points inside the rectangle at its waypoint tries once more to the waypoint moved sideways (across the held yaw) by the least amount up to this that keeps guard_margin_m from every sensed point [m]; 0 = off
  // --- final rotation to the requested yaw (P-controller) ---
  double yaw_tolerance = mrpt::DEG2RAD(2.0);  ///< final yaw error accepted [rad] (ini: deg)
  double yaw_gain = 2.0;                      ///< turn rate per radian of yaw error [1/s]
  double rotate_timeout_s = 20.0;             ///< give up the final rotation after this long [s]

  // --- MRPT reactive navigator (CAbstractPTGBasedReactive, CPTG_Holo_Blend, CHolonomicND) ---
  std::string holonomic_method = "CHolonomicND";  ///< CHolonomicND | CHolonomicFullEval
  double ref_distance_m = 3.0;    ///< look-ahead: obstacles and PTG paths up to this distance [m]
  int num_paths = 61;             ///< PTG path count (directions)
  double t_ramp_max_s = 0.5;      ///< PTG velocity blending time [s]
  double target_slowdown = 0.15;  ///< ND TARGET_SLOW_APPROACHING_DISTANCE (of ref_distance_m)
  double too_close_obstacle = 0.15;     ///< ND TOO_CLOSE_OBSTACLE (of ref_distance_m)
  double secure_distance_start = 0.02;  ///< stop at this free distance (of ref_distance_m)
  double secure_distance_end = 0.10;    ///< full speed from this free distance (of ref_distance_m)
  bool verbose = false;                 ///< MRPT navigator log messages on the console

  // --- inspection ---
  /// Directory for MRPT's navigation logs (navlog-viewer): every driveTo()
  /// writes one gzipped `log_NNN.reactivenavlog` (MRPT's name, NNN the first
  /// free number from 000, so files of earlier drives and runs are never
  /// overwritten) with one mrpt::nav::CLogFileRecord per navigator step.
  /// Created when missing; relative to the working directory. Empty: off.
  std::string navlog_dir;

  /// @brief The section names this struct reads.
  static std::vector<std::string> sections() { return {"navigation"}; }

  /// @brief Defaults with the robot footprint of a sim::RobotParams profile
  ///        (omnirob: 1.2 x 0.712 m; compact: 0.50 x 0.36 m).
  static DriverParams forFootprint(double length_m, double width_m);

  /// @brief Radius of the circle the navigator keeps free of obstacles:
  ///        sqrt((l/2)^2 + (w/2)^2) + shape_margin_m [m].
  double robotRadius() const;

  /// @brief Writes the complete MRPT 2.5.8 configuration of
  ///        mrpt::nav::CReactiveNavigationSystem for these settings into
  ///        `out` (sections [CAbstractNavigator], [CWaypointsNavigator],
  ///        [CAbstractPTGBasedReactive], [CHolonomicND], [CHolonomicFullEval],
  ///        [CMultiObjectiveMotionOptimizerBase],
  ///        [CMultiObjMotionOpt_Scalarization], [CReactiveNavigationSystem]).
  void writeMrptConfig(mrpt::config::CConfigFileBase& out) const;

  /// @throws std::runtime_error naming file, section and key for a bad value.
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace voxplore::navigation
