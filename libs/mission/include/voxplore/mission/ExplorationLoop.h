/* voxplore — the exploration loop behind three interfaces: a robot, a scan source, a clock.
 *
 * The loop of thesis fig. 4.4 with stop-and-scan driving (thesis 4.6):
 * scan -> SlamIcp -> plan -> drive one waypoint at a time with MRPT's
 * reactive navigator, stop and scan at each; a failed drive scans and
 * replans, a frontier that fails max_failures_per_target times is
 * blacklisted (as explore_lite does).
 *
 * Nothing here knows the simulator. To explore with a real robot implement
 *   - navigation::RobotInterface: velocity commands in; odometry, obstacle
 *     points and the robot's time out (the loop composes the pose estimate
 *     itself from the SLAM pose at the last stop and the odometry since, so
 *     the robot's own pose() is never read);
 *   - ScanSource: the depth images of every camera on demand, taken while
 *     the robot stands still;
 *   - Clock: the time the run's limit (max_sim_time_s) is measured in
 *     (SystemClock for a real robot);
 * then construct an ExplorationLoop and call run(). README "Plugging in a
 * robot" walks through it; apps::ExploreRun runs it on mrpt-sim. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/plan_inputs.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/mission/ExplorationLoopParams.h>
#include <voxplore/navigation/DriverParams.h>
#include <voxplore/navigation/RobotInterface.h>

#include <Eigen/Core>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace voxplore::navigation
{
class StopAndScanDriver;
struct DriveResult;
}

namespace voxplore::mission
{
/// @brief What the robot delivers at one stop.
struct Scan
{
  mrpt::Clock::time_point timestamp;  ///< when the images were taken
  /// Accumulated odometry at the scan (own frame, may drift): the SLAM's
  /// motion prior between stops.
  mrpt::poses::CPose2D odometry;
  /// One mrpt::obs::CObservation3DRangeScan per camera (depth image,
  /// intrinsics, sensorPose on the robot; see DESIGN.md) and optionally a
  /// CObservationOdometry. Must not be null.
  mrpt::obs::CSensoryFrame::Ptr observations;
  /// Optional: the odometry increment since the previous stop as a
  /// CActionRobotMovement2D (for a .rawlog of the run); may be null.
  mrpt::obs::CActionCollection::Ptr actions;
};

/// @brief A source of depth scans on demand.
class ScanSource
{
 public:
  virtual ~ScanSource() = default;
  /// @brief Takes one scan with every camera. Called only while the robot
  ///        stands still (after RobotInterface::stop() and a drive's end).
  /// @throws std::runtime_error when the sensors cannot deliver (ends the run
  ///         with that error; the maps so far stay in ExplorationLoop::slam()).
  virtual Scan scan() = 0;
};

/// @brief The time a run is measured in.
class Clock
{
 public:
  virtual ~Clock() = default;
  virtual mrpt::Clock::time_point now() const = 0;
};

/// @brief Clock of a real robot: MRPT's active clock (mrpt::Clock::now()).
class SystemClock : public Clock
{
 public:
  mrpt::Clock::time_point now() const override { return mrpt::Clock::now(); }
};

/// @brief The loop's state after each step, and its end.
struct ExplorationStatus
{
  /// Empty while running; then the planner's done reason ("no frontier",
  /// ...), "stagnation", "the map shut the robot in" (the stagnation rule
  /// fired on a known floor fallen under half of its largest: drift drew a
  /// wall across the way the robot came), "only small pockets left",
  /// "max_steps", "max_sim_time", or what Listener::stopReason() said
  std::string termination_reason;
  std::size_t steps = 0;          ///< planning steps
  std::size_t failed_drives = 0;  ///< waypoints not reached (Blocked / Timeout / Error)
  std::size_t blacklisted = 0;    ///< targets given up
  std::size_t guard_scaled = 0;   ///< velocity commands the driver's footprint guard slowed down
  std::size_t guard_held = 0;     ///< ... of those, the ones it held still
  std::size_t low_obstacle_replans = 0;  ///< drives ended by a low obstacle seen on the way (low_obstacle_replan)
  std::size_t scans_moving = 0;  ///< scans taken while driving (scan_mode = continuous)
  std::size_t targets_seen_on_the_way = 0;  ///< drives ended because their frontier was seen (replan_on_the_way, replan_at_stops)
  std::size_t seen_checks = 0;  ///< frontiers computed again on the way to see whether the plan's is gone
  double seen_check_s = 0;      ///< wall time of those checks [s]
  std::size_t seen_gated = 0;        ///< of seen_checks, answered by [explore] seen_gate alone
  std::size_t seen_gate_misses = 0;  ///< seen_gate = verify: checks the gate would have answered wrongly
  double path_length_m = 0;       ///< travelled by the pose estimate between stops [m]
  double time_translating_s = 0;  ///< robot time translating (any speed) [s]
  double time_turning_s = 0;      ///< ... turning in place; the rest it stood (scans, stops) [s]
  double compute_s = 0;           ///< wall time of SLAM + planning [s]
  double slam_ms_step = 0;        ///< SLAM time of the current step so far [ms]
  double elapsed_s = 0;           ///< Clock time since run() started [s]
  double known_floor_m2 = 0;      ///< free floor known in G at the last planning step [m^2]
  /// Frontiers of the last planning step farther than blacklist_radius_m
  /// from every frontier planned before it (stagnation_new_frontier_guard)
  std::size_t new_frontiers = 0;
  /// At the end (the planner found nothing to do): the known free floor the
  /// robot cannot get to (exploration::cutOffFloorM2) [m^2]
  double known_floor_cut_off_m2 = 0;
  /// The frontiers of the last planning step border only closed pockets of
  /// open unknown, each under ExplorationLoopParams::tail_pocket_m2 (false
  /// without frontiers)
  bool small_pockets_only = false;
  /// Open unknown of the last planning step that the stops looked at and
  /// left unknown, no frontier source ([sampling] retire_looks) [m^2]
  double unobservable_m2 = 0;
  /// The frontiers of the last planning step (map frame): centre and length
  /// [m]; what is left unexplored when the run ends.
  std::vector<std::pair<Eigen::Vector2d, double>> frontiers_left;
};

/// @brief Hooks for whoever runs the loop (logging, evaluation, a GUI).
///        Every method has a default; they are called on the loop's thread.
class Listener
{
 public:
  virtual ~Listener() = default;
  /// @brief A scan as the source delivered it, before SlamIcp sees it (record
  ///        it here: a stop that makes SLAM throw is then in the log too).
  virtual void onScan(const Scan& /*scan*/) {}
  /// @brief After SlamIcp processed a stop (`scan` as the source delivered it).
  virtual void onStop(const Scan& /*scan*/, const mapping::StopReport& /*report*/) {}
  /// @brief After each planning step, before its waypoints are driven.
  virtual void onPlan(const exploration::PlanResult& /*plan*/, double /*plan_ms*/,
                      const ExplorationStatus& /*status*/)
  {
  }
  /// @brief Before each planning step: exactly what the planner is given
  ///        besides its parameters (exploration::writePlanInputs saves it).
  virtual void onPlanInputs(const exploration::PlanInputs& /*inputs*/,
                            const octomap::OcTree& /*V*/)
  {
  }
  /// @brief After every RobotInterface::step() of a drive.
  virtual void onRobotStep() {}
  /// @brief A line for the user (failed waypoints, blacklisted targets, loop closures).
  virtual void onMessage(const std::string& /*line*/) {}
  /// @brief Polled before each planning step and after each robot step; a
  ///        non-empty reason ends the run there (e.g. "interrupted" on SIGINT).
  virtual std::string stopReason() { return {}; }
};

/// @brief The exploration loop over RobotInterface, ScanSource and Clock.
///        One run per instance; owns the SLAM, the driver and the targets'
///        bookkeeping.
class ExplorationLoop
{
 public:
  /// @param robot velocity commands, odometry, obstacle points, robot time
  ///        (navigation::StopAndScanDriver drives it; its pose() is not read)
  /// @param listener optional; must outlive the loop
  /// @throws std::runtime_error when MRPT rejects the driver configuration.
  ExplorationLoop(
      navigation::RobotInterface& robot, ScanSource& scans, const Clock& clock,
      const mapping::SlamIcpParams& slam, const exploration::PlannerParams& planner,
      const navigation::DriverParams& driver, const ExplorationLoopParams& params,
      Listener* listener = nullptr);
  ~ExplorationLoop();
  ExplorationLoop(const ExplorationLoop&) = delete;
  ExplorationLoop& operator=(const ExplorationLoop&) = delete;

  /// @brief Scans, then plans and drives until the planner is done or a
  ///        limit holds; the robot stands still at the end.
  /// @return the status, termination_reason set
  /// @throws whatever the robot, the scan source or SLAM throw; slam() then
  ///         holds the stops so far (save them with SlamIcp::saveOutputs()).
  const ExplorationStatus& run();

  const ExplorationStatus& status() const { return status_; }
  const mapping::SlamIcp& slam() const { return slam_; }
  mapping::SlamIcp& slam() { return slam_; }
  /// @brief The estimated poses of the robot (map frame, 5 cm apart): the
  ///        planner's swept floor.
  const exploration::SweptPath& sweptPath() const { return swept_; }
  /// @brief Frontier centres given up (map frame).
  const std::vector<Eigen::Vector2d>& blacklist() const { return blacklist_; }
  /// @brief The pose the navigator drives by: the SLAM pose at the last
  ///        stop composed with the odometry increment since (map frame).
  mrpt::poses::CPose2D poseEstimate() const;

  /// @brief Whether `frontiers` is not empty and each borders only closed pockets
  /// of open unknown under `max_m2` in all (Frontier::unknown_m2).
  static bool onlySmallPockets(const std::vector<exploration::Frontier>& frontiers, double max_m2);
  /// @brief Whether the last of the known floors (m^2 at each planning step)
  ///        is under half of the largest before it: G lost its floor, the
  ///        map (not the building) shut the robot in.
  static bool floorCollapsed(const std::vector<double>& known_floor);
  /// @brief Whether `cut_off_m2` of the `known_floor_m2` of known free floor
  ///        cut off from the robot (an end with nothing to plan) is more
  ///        than half of it and at least 5 m^2: the map shut the robot in,
  ///        whatever the planner's reason says.
  static bool cutOffShutsIn(double cut_off_m2, double known_floor_m2);

 private:
  class PosedRobot;
  void loop();
  /// Takes a scan; SlamIcp integrates it at once, or (`beside`, with
  /// scan_latency_s > 0) on a worker thread, its result taken by settleScan().
  void scanAndIntegrate(bool beside = false);
  /// Brings a robot still moving after its drive's stop() to a stand.
  void standStill();
  /// The result of the scan being integrated beside the driving, if any,
  /// waited for and taken into the loop (pose, swept path, looks, listener).
  void settleScan();
  void applyScan(const Scan& scan, const mapping::StopReport& rep, double compute_s,
                 const mrpt::poses::CPose2D& odometry);
  /// The scan integrated beside the driving is due (scan_latency_s after it).
  bool pendingDue() const;
  struct PendingScan;
  enum class Drive
  {
    Reached,      ///< every waypoint
    Failed,       ///< a waypoint not reached (counted against the target)
    Interrupted,  ///< a low obstacle seen on the way (low_obstacle_replan)
    TargetSeen,   ///< the plan's frontier seen on the way (replan_on_the_way: the robot moves;
                  ///< replan_at_stops: it stands at the stop)
  };
  /// The caller replans unless Reached. Lead-ins made on the way change
  /// the plan's waypoints (leadInOnTheWay).
  Drive driveWaypoints(exploration::PlanResult& plan);
  /// scan_mode = continuous with turns on the way: a circle waypoint i
  /// before a footprint one (after turns in place or not), where the
  /// rectangle keeps the turn margin at every yaw from the robot's to the
  /// footprint drive's all along the way there, is driven as a lead-in
  /// (the planner's lead-ins, Path::kTurnFromAnyYaw, hold every yaw; this
  /// one the robot's, known only now); the turns in place are erased.
  void leadInOnTheWay(exploration::PlanResult& plan, std::size_t i) const;
  /// scan_mode = continuous with turns on the way: a footprint waypoint i
  /// whose drive would turn in place first (the robot stands after a circle
  /// drive, or a plan starts in another yaw) turns on the first 0.6, 0.3,
  /// 0.15 or 0.1 m of its way instead (longest first, at most half of it), where the
  /// turn layer holds the turn in proportion there and the translation layer
  /// the drive's yaw on from there: a waypoint is inserted at i.
  void turnFirstOnTheWay(exploration::PlanResult& plan, std::size_t i) const;
  /// scan_mode = continuous with turns on the way: the yaw a circle
  /// waypoint i's drive turns the robot to on its way (MRPT's reactive drive
  /// would face the way it goes): the yaw the next footprint drive starts
  /// in, or the view's when none follows; empty otherwise.
  std::optional<double> faceYaw(const exploration::PlanResult& plan, std::size_t i) const;
  /// low_obstacle_replan: whether a low obstacle cell not in low_at_plan_
  /// lies within reach of the path from waypoint `from` on.
  bool lowObstacleAhead(const exploration::PlanResult& plan, std::size_t from) const;
  /// How waypoint i of a plan is passed without stopping (scan_mode =
  /// continuous): within tolerance_m, or, at a corner (corner_speed_mps >=
  /// 0), on the waypoint itself at no more than that speed.
  struct Pass
  {
    double tolerance_m = 0;
    double corner_speed_mps = -1;
  };
  /// Empty when the robot must stop there (the last one, unless a
  /// footprint one reached in the view's yaw: passed at half speed, landing
  /// on it; a circle waypoint
  /// before a footprint one, unless a lead-in; a footprint one whose next
  /// needs a turn in place, or bends the way into a circle one by more than
  /// kPassBendDeg, which a pass would cut). A footprint one turned on its
  /// way whose pass would leave more than yaw_tolerance of the turn undone
  /// (tolerance / way of it) is landed on (a short piece, a large turn).
  std::optional<Pass> passTolerance(const exploration::PlanResult& plan, std::size_t i) const;
  /// Waypoint i of the plan driven by the drive its kind takes: the
  /// rectangle's (narrow) or MRPT's circle, passed (`pass`) or stopped at.
  navigation::DriveResult driveWaypoint(const exploration::PlanResult& plan, std::size_t i,
                                        const std::optional<Pass>& pass);
  /// A drive to waypoint i that failed: its blocking points kept, counted
  /// against the plan's target, said.
  void noteFailedDrive(const exploration::PlanResult& plan, std::size_t i,
                       const navigation::DriveResult& r);
  /// low_obstacle_replan: a low obstacle seen on the rest of the plan after
  /// waypoint i (not twice without the robot moving in between); the
  /// robot stops (continuous) and the caller replans.
  bool lowObstacleInterrupts(const exploration::PlanResult& plan, std::size_t i, bool continuous);
  /// The pose the planner plans from.
  mrpt::poses::CPose2D planPose() const;
  /// replan_on_the_way: the plan's frontier is gone from a plan made now.
  bool targetSeen(const exploration::PlanResult& plan);
  /// exploration::plan() from planPose() with the loop's inputs (`step`
  /// seeds the sampler, `low`: the map's low obstacles).
  exploration::PlanResult planNow(std::size_t step, const std::vector<Eigen::Vector2d>& approach,
                                  const std::vector<Eigen::Vector2d>& low);
  /// The low obstacle cells (keys) the current plan was made with.
  void setLowAtPlan(const std::vector<Eigen::Vector2d>& low);
  /// Frontier centre -> count, one entry per blacklist_radius_m.
  using TargetCounts = std::vector<std::pair<Eigen::Vector2d, int>>;
  /// The entry of `counts` within blacklist_radius_m of `target` (added at 0).
  TargetCounts::iterator countFor(TargetCounts& counts, const Eigen::Vector2d& target);
  void registerFailure(const Eigen::Vector2d& target);
  /// Counts a plan for the frontier at `target`; blacklists it after max_plans_per_target.
  void registerPlan(const Eigen::Vector2d& target);
  void addSwept(const mrpt::poses::CPose2D& e);
  /// Keeps the points a drive was blocked by (DriveResult::blocking_points):
  /// the planner marks them occupied from the next step on.
  void rememberObstacles(const std::vector<Eigen::Vector2d>& points);
  /// The end's known floor cut off from the robot into status_ (and a message from 5 m^2).
  void noteCutOff(double cut_off_m2);
  /// cut_off_replan_m2: replaces a plan that found nothing, with `cut_off_m2`
  /// of known floor cut off, by the relaxed one when that finds a way.
  void replanShutIn(exploration::PlanResult& plan, double cut_off_m2, std::size_t step,
                    const std::vector<Eigen::Vector2d>& approach);
  /// When the known floor fell by half or more (floorCollapsed), or when
  /// `cut_off_m2` of it is cut off from the robot (cutOffShutsIn; an end
  /// with nothing to plan): ends the run "the map shut the robot in" with a
  /// message ending in `detail` or naming the cut-off floor; true then.
  bool endShutIn(const std::string& detail, double cut_off_m2 = 0);
  /// The plan's frontiers and known floor into status_ (and known_floor_).
  void noteFrontiers(const exploration::PlanResult& plan);
  /// The free floor found over the last stagnation_steps planning steps
  /// [m^2]; empty when the rule is off or the run is not that long yet.
  std::optional<double> stagnationGain() const;
  /// The free floor found while the robot drove the last stagnation_path_m
  /// metres [m^2]; empty when the rule is off or the path is not that long yet.
  std::optional<double> pathStagnationGain() const { return floorGainOver(params_.stagnation_path_m); }
  /// The free floor found while the robot drove the last `window` metres
  /// [m^2]; empty when `window` is 0 or the path is not that long yet.
  std::optional<double> floorGainOver(double window) const;
  /// The end of a run that stopped finding floor: "stagnation" (or "only
  /// small pockets left", ExplorationLoopParams::tail_path_m) and a message
  /// saying what is left; false while the run goes on.
  bool stagnated();
  void onRobotStep();
  /// scan_mode = continuous: the robot drove or turned enough, and long
  /// enough ago, since the last scan.
  bool scanDue() const;
  void message(const std::string& line);
  /// The listener's stop reason, max_steps (only `between_steps`), or the
  /// time limit; empty when the run goes on.
  std::string limitReached(bool between_steps);
  /// Ends the run inside a drive (a listener's stop or the time limit),
  /// as onRobotStep() does: also after a stop's scan, which takes time too.
  void stopIfLimitReached();
  /// Clock seconds since run() started.
  double elapsedSeconds() const;
  /// The projection cache, told where the map changed since the last plan.
  exploration::ProjectionCache* projectionCache();

  navigation::RobotInterface& robot_;
  ScanSource& scans_;
  const Clock& clock_;
  exploration::PlannerParams planner_;
  ExplorationLoopParams params_;
  Listener* listener_;
  mapping::SlamIcp slam_;
  exploration::ProjectionCache projection_cache_;
  mapping::MapRevision projected_at_;  ///< the map's revision projection_cache_ last saw
  /// The unknown cells the stops looked at (shared with the plan inputs).
  std::shared_ptr<exploration::FrontierLooks> looks_ = std::make_shared<exploration::FrontierLooks>();
  std::unique_ptr<PosedRobot> posed_;
  std::unique_ptr<navigation::StopAndScanDriver> driver_;
  mrpt::Clock::time_point t_start_;
  mrpt::poses::CPose2D pose_at_stop_, odo_at_stop_, last_estimate_;
  mrpt::poses::CPose2D odo_at_scan_;      ///< odometry at the last scan taken (integrated or not)
  std::unique_ptr<PendingScan> pending_;  ///< the scan SlamIcp integrates beside the driving
  double t_last_scan_s_ = -std::numeric_limits<double>::infinity();  ///< robot time of the last scan [s]
  double t_last_step_s_ = std::numeric_limits<double>::quiet_NaN();  ///< robot time onRobotStep() or a scan last saw [s]
  mapping::MapRevision checked_at_;  ///< the map's revision at the last plan or targetSeen() check
  std::vector<Eigen::Vector2d> blacklist_;
  TargetCounts failures_;  ///< failed drives per frontier
  TargetCounts plans_;     ///< plans so far per frontier
  exploration::SweptPath swept_;
  std::vector<double> known_floor_;  ///< known_floor_m2 at each planning step
  std::vector<double> path_at_plan_;  ///< path_length_m at each planning step [m]
  std::vector<Eigen::Vector2d> planned_;  ///< the frontier (or target) of every plan so far
  /// Points drives were blocked by that the map may not hold (map frame).
  std::vector<Eigen::Vector2d> sensed_obstacles_;
  /// Cell keys of the low obstacles the current plan was made with (sorted).
  std::vector<std::uint64_t> low_at_plan_;
  /// path_length_m when low_obstacle_replan last ended a drive [m]
  double path_at_interrupt_ = -std::numeric_limits<double>::infinity();
  /// params_.low_obstacle_replan resolved (lowObstacleReplanInForce).
  bool low_replan_ = false;
  /// params_.replan_at_stops resolved for the planner's strategy.
  bool replan_at_stops_ = false;
  /// A circle drive's last turn may end this much off the target's yaw, or a
  /// multiple of it (the cameras see the same: continuous mode) [rad]; 0 = none.
  double view_period_ = 0;
  ExplorationStatus status_;
};

}  // namespace voxplore::mission
