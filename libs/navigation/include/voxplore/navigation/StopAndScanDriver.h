/* voxplore — stop-and-scan driving: one waypoint at a time with MRPT's reactive navigator. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/navigation/DriverParams.h>
#include <voxplore/navigation/RobotInterface.h>

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace voxplore::navigation
{
namespace detail
{
class FootprintGuard;
struct DriveLog;
}
/// @brief How a drive to one waypoint ended.
enum class DriveOutcome
{
  Reached,  ///< within goal_tolerance_m (and yaw_tolerance when a yaw was asked, unless the
            ///< footprint guard held the final turn: the message then says how far it got)
  Blocked,  ///< no progress for blocked_timeout_s, or an obstacle seen at the waypoint
  Timeout,  ///< timeout_s / max_steps / rotate_timeout_s ran out while still progressing
  Error     ///< a collision, a sensor failure or a navigator error (see message)
};

const char* toString(DriveOutcome o);

/// @brief Result of StopAndScanDriver::driveTo(). The robot stands still in every case.
struct DriveResult
{
  DriveOutcome outcome = DriveOutcome::Error;
  mrpt::poses::CPose2D final_pose;  ///< RobotInterface::pose() at the end (map frame)
  double goal_distance_m = 0;       ///< final distance to the waypoint [m]
  double distance_m = 0;            ///< path length driven, from pose() [m]
  double sim_time_s = 0;            ///< robot time spent (RobotInterface::now()) [s]
  std::size_t steps = 0;            ///< RobotInterface::step() calls
  std::size_t collisions = 0;       ///< new collisions the robot reported (0 without a bumper)
  std::string message;              ///< why it ended, for the user
  bool guard_held = false;          ///< the footprint guard held the robot and so ended it (Blocked)
  /// driveFootprint() Blocked because sensed points lay inside the rectangle
  /// at the waypoint: those points (map frame, the pose() frame). The map may
  /// not hold them (below the projection's z_min, or a pose error): the
  /// exploration loop marks them occupied for the planner.
  std::vector<Eigen::Vector2d> blocking_points;

  bool reached() const { return outcome == DriveOutcome::Reached; }
};

/// @brief Drives a RobotInterface to waypoints with
///        mrpt::nav::CReactiveNavigationSystem (CPTG_Holo_Blend + CHolonomicND,
///        the robot as the circle round its footprint), stopping at each one:
///        MRPT does not stop at intermediate waypoints, so each driveTo()
///        sends a single target and waits for the navigator to go idle.
///
/// Time is the robot's (RobotInterface::now(), equal to mrpt::Clock::now());
/// with a simulated robot every run is deterministic.
class StopAndScanDriver
{
 public:
  /// @throws std::runtime_error when MRPT rejects the configuration.
  StopAndScanDriver(RobotInterface& robot, const DriverParams& params);
  ~StopAndScanDriver();
  StopAndScanDriver(const StopAndScanDriver&) = delete;
  StopAndScanDriver& operator=(const StopAndScanDriver&) = delete;

  /// @brief Drives to `waypoint` (map frame), stops, then turns in place to
  ///        `final_yaw_rad` when given and the waypoint was reached. Runs
  ///        navigationStep() then RobotInterface::step(dt_s) until the
  ///        navigator reports the target reached or an error, a sensed
  ///        obstacle lies within the footprint's circumradius of the
  ///        waypoint (3 steps in a row), timeout_s, blocked_timeout_s without
  ///        progress, a collision, a sensor failure, or max_steps.
  /// @return the outcome; never hangs (at most max_steps steps for the
  ///         drive plus rotate_timeout_s / dt_s steps for the rotation).
  /// @throws std::runtime_error when RobotInterface::now() and
  ///         mrpt::Clock::now() disagree (a simulator that did not switch
  ///         MRPT to its simulated clock).
  /// @param final_yaw_period_rad > 0: final_yaw_rad plus any multiple of it
  ///        gives the same view (a camera ring that a half turn maps onto
  ///        itself: pi); the turn goes to the nearest of them.
  /// @param face_yaw_rad set: on the way the robot turns to this yaw (map
  ///        frame, at up to max_w) instead of to its direction of travel,
  ///        MRPT's own heading (the circle MRPT plans for holds the
  ///        rectangle at any yaw): it arrives turned for the footprint
  ///        drive or the view after it.
  DriveResult driveTo(const Eigen::Vector2d& waypoint, std::optional<double> final_yaw_rad,
                      double final_yaw_period_rad = 0,
                      std::optional<double> face_yaw_rad = std::nullopt);

  /// @brief Scanning while driving ([explore] scan_mode = continuous): drives
  ///        at an intermediate waypoint as driveTo() does, but without
  ///        slowing down (desired speed at the target 1), and returns
  ///        Reached once within `tolerance_m`
  ///        with the robot still moving, so that the next drive goes on from
  ///        there. A robot that is moving already (a pass before) is not
  ///        backed off first. Any other ending stops the robot and runs the
  ///        fallbacks of driveTo() (straight drive, escape).
  ///        face_yaw_rad: as driveTo()'s.
  DriveResult passBy(const Eigen::Vector2d& waypoint, double tolerance_m,
                     std::optional<double> face_yaw_rad = std::nullopt);

  /// @brief Turns in place to `yaw_rad` (P-controller on the yaw error).
  /// @return Reached within yaw_tolerance, Timeout after rotate_timeout_s,
  ///         Error on a collision.
  DriveResult rotateTo(double yaw_rad);

  /// @brief Fallback when MRPT's navigator stalls (our own: CHolonomicND
  ///        commands zero velocity in 1.1 m corridors and doorways with a
  ///        free circle around the robot; measured in turtlebot3_house):
  ///        drives straight at the waypoint (holonomic, no turning) while
  ///        no sensed obstacle point in the height band lies within
  ///        robotRadius() of the straight segment still to go, slowing down
  ///        over the last 0.3 m.
  /// @return Reached within goal_tolerance_m; Blocked when the segment is
  ///         not free or no progress for blocked_timeout_s; Timeout after
  ///         timeout_s; Error on a sensor failure or a collision.
  DriveResult driveStraight(const Eigen::Vector2d& waypoint);

  /// @brief The footprint drive, for passages the circle MRPT's PTGs see
  ///        does not fit through ([collision] model = footprint): turns in place
  ///        to `yaw_rad` (rotateTo), then translates straight at the waypoint
  ///        (holonomic) holding that yaw, slowing down over the last 0.3 m,
  ///        with the footprint guard under every command. The planner checked
  ///        the turn and the way against the map; the drive checks the
  ///        rectangle at the waypoint against the sensed points.
  /// @return Reached within goal_tolerance_m; Blocked when a sensed point lies
  ///         inside the rectangle at the waypoint (3 steps in a row), the
  ///         guard held the robot for guard_hold_s, or no progress for
  ///         blocked_timeout_s; Timeout / Error as driveTo(); a turn that did
  ///         not reach the yaw ends the drive with its outcome. With
  ///         `final_yaw_rad`, a reached waypoint is followed by the turn to it
  ///         as in driveTo().
  /// @param turn_on_way The planner checked the turn along the way
  ///        (exploration::Path::turn_on_way): no turn in place first; the yaw
  ///        goes to `yaw_rad` as the robot translates, in proportion to the
  ///        way made.
  DriveResult driveFootprint(const Eigen::Vector2d& waypoint, double yaw_rad,
                             std::optional<double> final_yaw_rad = std::nullopt,
                             bool turn_on_way = false);

  /// @brief driveFootprint() through an intermediate waypoint
  ///        ([explore] scan_mode = continuous): the turn to `yaw_rad`, when
  ///        one is needed, is made standing (the planner checked it at the
  ///        pose before); the translation does not slow down, and the drive
  ///        returns Reached within `tolerance_m` with the robot still moving
  ///        (no back-off first while it moves). Any other ending is
  ///        driveFootprint()'s, standing. `turn_on_way` as driveFootprint().
  /// @param corner_speed_mps >= 0: a corner; the robot slows down to this
  ///        speed (at most) over the last 0.3 m and lands on the waypoint
  ///        (its last step no longer than the way left) instead of ending
  ///        the drive before it, so the next drive does not cut the corner.
  DriveResult passFootprint(const Eigen::Vector2d& waypoint, double yaw_rad, double tolerance_m,
                            bool turn_on_way = false, double corner_speed_mps = -1);

  /// @brief Recovery of a pinned robot (our own: MRPT's reactive navigator
  ///        stands still for ever once an obstacle point is at its circle):
  ///        backs off at escape_speed_mps along the sum of the repulsions of
  ///        the sensed obstacle points within robotRadius() +
  ///        escape_clearance_m, until none is that close, the repulsions
  ///        cancel out (pinched from both sides), escape_timeout_s, or a
  ///        collision. Does nothing when escape_clearance_m is 0.
  /// @return Reached when clear (also when already clear), Blocked when it
  ///         could not get clear, Error on a sensor failure or collision.
  DriveResult escape();

  /// @brief The footprint's back-off (our own, like escape(), for the
  ///        rectangle): when the rectangle is within guard_margin_m +
  ///        footprint_backoff_m / 2 of a sensed obstacle point, translates
  ///        without turning at escape_speed_mps along the sum of the
  ///        points' pushes (each away from its nearest point of the
  ///        rectangle, weighted by how much nearer than guard_margin_m +
  ///        footprint_backoff_m it is), until the clearance is that, the
  ///        pushes cancel out, escape_timeout_s, or a collision. A stop left
  ///        3 cm from a wall (the guard's margin) held every first command
  ///        of the next drive (b3, omniRob, nbv: 9 replans in place). Does
  ///        nothing with the guard or footprint_backoff_m off.
  /// @return Reached when clear (also when already clear), Blocked when it
  ///         could not get clear, Error on a sensor failure or collision.
  DriveResult backOffFootprint();
  /// @brief The waypoint moved sideways (across yaw_rad) by the least
  ///        multiple of 5 mm up to footprint_centring_m at which the
  ///        rectangle in yaw_rad keeps guard_margin_m from every sensed
  ///        obstacle point; nullopt when none does (or the sensors fail).
  std::optional<Eigen::Vector2d> centredWaypoint(const Eigen::Vector2d& waypoint, double yaw_rad);
  /// @brief The least sideways move (across yaw_rad, a multiple of 5 mm up
  ///        to footprint_centring_m) after which the straight line to the
  ///        waypoint moved as far keeps guard_margin_m from every sensed
  ///        obstacle point, for the rectangle at yaw_rad and at the robot's
  ///        yaw, on the move sideways and on the line; nullopt when none
  ///        does (or the sensors fail).
  std::optional<double> laneOffset(const Eigen::Vector2d& waypoint, double yaw_rad);

  const DriverParams& params() const { return params_; }

  /// @brief Velocity commands the footprint guard ([navigation]
  ///        footprint_guard) scaled down so far, and of those the ones it
  ///        held still (0 with the guard off).
  std::size_t guardScaledCommands() const;
  std::size_t guardHeldCommands() const;

 private:
  struct Impl;
  /// driveTo() (pass_tolerance_m < 0) and passBy() (the tolerance).
  DriveResult reactiveDrive(const Eigen::Vector2d& waypoint, std::optional<double> final_yaw_rad,
                            double pass_tolerance_m, double final_yaw_period_rad = 0,
                            std::optional<double> face_yaw_rad = std::nullopt);
  /// The footprint guard has held the robot for guard_hold_s.
  bool guardHolding() const;
  /// Blocked when guardHolding().
  std::optional<std::pair<DriveOutcome, std::string>> guardEnding() const;
  /// Why the straight way is not free, from the sensed points in the
  /// navigator's height band and the waypoint (tx, ty), both in the frame of
  /// the robot at `pose`; empty while it is free.
  using WayCheck = std::function<std::optional<std::pair<DriveOutcome, std::string>>(
      const std::vector<Eigen::Vector2d>& points, double tx, double ty,
      const mrpt::poses::CPose2D& pose)>;
  /// The straight holonomic drive of driveStraight() and driveFootprint():
  /// at the waypoint, slowing down over the last 0.3 m, holding `hold_yaw`
  /// when given (else not turning), until goal_tolerance_m (or
  /// tolerance_m when >= 0), `way` says stop, or checkAfterStep / the guard
  /// ends it.
  /// `pass`: no slowing down, and Reached leaves the robot moving.
  /// `turn_on_way`: turn from the yaw at the start to `hold_yaw` in
  /// proportion to the way made (no faster than 0.8 max_w allows).
  /// `corner_speed_mps` >= 0 (a pass): passFootprint()'s corner.
  DriveResult straightDrive(const Eigen::Vector2d& waypoint, std::optional<double> hold_yaw,
                            const WayCheck& way, double tolerance_m = -1, bool pass = false,
                            bool turn_on_way = false, double corner_speed_mps = -1);
  /// driveFootprint() (pass_tolerance_m < 0) and passFootprint().
  DriveResult footprintDrive(const Eigen::Vector2d& waypoint, double yaw_rad,
                             std::optional<double> final_yaw_rad, double pass_tolerance_m,
                             bool turn_on_way, double corner_speed_mps = -1);
  /// The turn to `final_yaw_rad` at a reached waypoint (driveTo(),
  /// driveFootprint()), appended to `res`.
  void turnAtWaypoint(DriveResult& res, std::optional<double> final_yaw_rad,
                      double final_yaw_period_rad = 0);
  /// A reactive drive that ended Blocked: driveStraight() when
  /// straight_fallback, then escape() when escape_clearance_m > 0, appended
  /// to `res` (its outcome theirs).
  void recoverBlocked(DriveResult& res, const Eigen::Vector2d& waypoint);
  /// Stops the robot; the result of a drive that ended with `end`.
  DriveResult finishDrive(const detail::DriveLog& log,
                          const std::pair<DriveOutcome, std::string>& end);

  DriverParams params_;
  std::unique_ptr<detail::FootprintGuard> guard_;  // between the driving and the robot; null when off
  RobotInterface& robot_;                          // the guard when on, else the robot
  std::unique_ptr<Impl> impl_;
};

}  // namespace voxplore::navigation
