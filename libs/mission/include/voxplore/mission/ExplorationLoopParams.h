/* voxplore — the exploration loop's own parameters, ini section [explore]
 * (split from ExplorationLoop.h). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <limits>
#include <string>

namespace voxplore::exploration
{
struct CollisionParams;
}

namespace voxplore::mission
{
/// @brief Limits and target bookkeeping of the loop. ini section [explore]
///        (apps::ExploreParams adds the simulator's evaluation keys there).
struct ExplorationLoopParams : public mrpt::config::CLoadableOptions
{
  int max_steps = 500;              ///< planning steps before giving up ("max_steps"; a safety net)
  /// Seconds of the Clock before giving up ("max_sim_time"), also inside a
  /// drive; the key keeps its name from the simulator [s]
  double max_sim_time_s = 3600.0;
  int max_failures_per_target = 2;  ///< failed drives towards one frontier before it is blacklisted
  int max_plans_per_target = 0;     ///< plans for one frontier before it is blacklisted; 0 = no limit (a frontier explored a little at every step, e.g. down a corridor, is planned many times)
  double min_progress_m = 0.05;     ///< a step that moves the robot less than this counts as a failed drive [m]
  /// Next-best-view, and the nearest strategy's view stand-off (footprint
  /// model): a frontier planned before (max_plans_per_target > 0 counts
  /// plans) is approached at its next plan: the target is its nearest
  /// reachable cell, not a view 1-3 m off (exploration::plan's `approach`).
  bool approach_replanned = true;
  /// Stagnation (issue 12): the run ends ("stagnation") when the free floor
  /// known in G grew by less than stagnation_min_gain_m2 over the last
  /// stagnation_steps planning steps (frontier slivers no pose clears, seen
  /// again and again); 0 = never.
  int stagnation_steps = 0;  ///< off by default: 20 cut b13 nbv (omniRob) from 0.843 to 0.594
  double stagnation_min_gain_m2 = 2.0;  ///< [m^2]
  /// Stagnation over the path (issue 12): the run ends ("stagnation") when
  /// the free floor known in G grew by less than stagnation_path_min_gain_m2
  /// while the robot drove the last stagnation_path_m metres. A window of
  /// metres, not steps: a robot failing at a door or a small world never
  /// fills it, and a long drive to an unexplored wing is shorter than it.
  /// 100 m / 5 m^2 cut b10 compact footprint nearest from 0.978 to 0.889
  /// (133 m of frontier slivers before the last room), 150 m / 5 m^2 b6
  /// compact circle nearest from 0.941 to 0.911 (264 m for 7 m^2 before
  /// its last room); 0 = never [m].
  double stagnation_path_m = 200;
  double stagnation_path_min_gain_m2 = 3.0;  ///< [m^2]
  /// Stagnation (either rule) ends a run only when no frontier left is new:
  /// each lies within [sampling] blacklist_radius_m of a frontier planned
  /// before. A room never targeted yet (b10 compact nearest's last room
  /// behind 133 m of slivers, b6 compact circle's behind 264 m) keeps the
  /// run going. false = the window alone. Off: judged offline on 35 runs
  /// (stagnation_offline.py --guard) it took away the one bad cut of a
  /// 100 m / 5 m^2 window (b2 compact nearest 0.984 -> 0.913) and nearly
  /// all its savings (path -6.8 % -> -0.7 %): frontier centres move as
  /// frontiers shrink, and a sliver planned before looks new.
  bool stagnation_new_frontier_guard = false;
  /// The tail (issue 12's "real end"): the run ends ("only small pockets
  /// left") when the free floor known in G grew by less than
  /// tail_min_gain_m2 while the robot drove the last tail_path_m metres and
  /// every frontier left borders only closed pockets of open unknown, each
  /// under tail_pocket_m2 (Frontier::unknown_m2: under a desk, beside a
  /// cabinet). A room not entered yet is a large or open pocket and keeps
  /// the run going, where a window of metres alone cut it (100 m / 5 m^2:
  /// b10 compact nearest 0.978 -> 0.889). 0 = off [m].
  double tail_path_m = 40;
  double tail_min_gain_m2 = 3.0;  ///< [m^2]
  double tail_pocket_m2 = 4.0;    ///< [m^2]
  /// Shut in (issue 12): when the planner finds nothing to do while at least
  /// this much known free floor, and more than half of it, is cut off from
  /// the robot (exploration::cutOffFloorM2), it plans once more trusting the swept
  /// path ([collision] swept_passage) and without the sensed points in the
  /// way (they are forgotten when that plan succeeds: the driver senses
  /// again what is really there). A door narrowed by drift, or by points
  /// sensed in it, shut the compact robot in a room and ended the run "no
  /// frontier" with most of the known building beyond it (b5, b9). 0 = off
  /// [m^2].
  double cut_off_replan_m2 = 20;
  /// Low obstacles on the way: at every stop of a drive, low obstacle
  /// cells ([octomap] low_obstacle_*) the map did not hold when the path
  /// was planned and the planner would stamp (exploration::stampObstacles'
  /// rule on the plan's G), closer to the rest of the path than the robot's
  /// circumradius plus the footprint margin (marginInForce) and half a cell's diagonal, end
  /// the drive, and the loop plans again (not a failure, not a plan of the
  /// target counted; not twice without the robot moving min_progress_m in
  /// between). The cameras see no floor within ~0.9 m of their rim:
  /// a table's 5 cm base plate seen on the approach is out of their view,
  /// and the guard's, when the body reaches it (turtlebot3_house, compact
  /// footprint, nearest: a collision planned before the plate was seen).
  /// Off = drive the plan to its end. Auto (the default, ini "auto"): on
  /// where the planner plans with the footprint and exact margins
  /// (CollisionParams::footprintTrimmed false: the compact robot), off
  /// elsewhere: on the omniRob's buildings it ended 28 drives a run and
  /// cost b5 nearest 0.980 -> 0.949 (twenty-fifth session).
  enum class Switch
  {
    Off,
    On,
    Auto
  };
  Switch low_obstacle_replan = Switch::Auto;
  /// Scanning (issue 15, thesis 6.2). StopAndScan (the thesis, the
  /// default): the robot stops at every waypoint and scans there.
  /// Continuous: it drives through the intermediate waypoints of a plan
  /// without stopping (StopAndScanDriver::passBy; footprint drives through
  /// narrow passages still turn and stop), and scans while it drives, at
  /// most scan_rate_hz and only after scan_every_m or scan_every_deg of
  /// odometry since the last scan; it stops and scans at the plan's last
  /// waypoint, at a failed drive and at a low obstacle ahead. Each scan is a
  /// stop for SlamIcp (registered with its odometry and deskewed, [cloud]
  /// deskew; the simulator exposes the cameras one after another,
  /// [simulator] camera_stagger_s).
  enum class ScanMode
  {
    StopAndScan,
    Continuous
  };
  ScanMode scan_mode = ScanMode::StopAndScan;
  /// Continuous: scans a second at most while driving; the loop looks once a
  /// robot step ([navigation] dt_s), so 1 / dt_s bounds it too [Hz].
  double scan_rate_hz = 10;
  double scan_every_m = 0.5;    ///< continuous: a scan after this much odometry translation [m] ...
  double scan_every_deg = 30;   ///< ... or this much rotation [deg]
  /// Continuous: an intermediate waypoint is passed within this distance [m].
  double pass_tolerance_m = 0.15;
  /// Continuous: after each waypoint passed with the map changed since the
  /// last look, compute the frontiers again from where the robot is
  /// (exploration::planLayers); when the plan's frontier is gone (no
  /// frontier's centre within [sampling] blacklist_radius_m of it: the scans
  /// on the way have seen it), the drive ends there, moving, and the loop
  /// plans from there. false = drive each plan to its end. On by default
  /// since the thirty-fourth session: 0.80x -> 0.76x the stop-and-scan
  /// mission time on the same 18 campaign runs (b1-b5), coverage as before.
  bool replan_on_the_way = true;
  /// Stop-and-scan: after each intermediate stop's scan, the same check as
  /// replan_on_the_way (the plan's frontier gone from the frontiers computed
  /// again from that stop); when it holds the drive ends at that stop and the
  /// loop plans from there, instead of driving on to a view of a frontier
  /// already seen (the thesis drives each plan to its end). Auto = on for
  /// the nbv strategy, off for the nearest baseline (which stays the
  /// thesis'); On / Off = for both.
  Switch replan_at_stops = Switch::Auto;
  /// The check of replan_on_the_way / replan_at_stops costs the frontiers
  /// computed again at every stop (projection, collision and footprint
  /// space, reachability: 90-160 ms on a 500 m^2 map, about 60 % of an nbv
  /// run's CPU in the forty-sixth session). Our own gate in front of it
  /// (no library has this question): the ground projection alone (cached,
  /// ProjectionCache) tells how many of the plan's frontier cells still
  /// border unknown; while at least seen_gate_fraction of them do, the
  /// frontier is taken as still there and the rest is skipped. false:
  /// every check computes the frontiers.
  bool seen_gate = false;
  /// Both the gate and the frontiers at every check; the full check decides
  /// (the run is the one with seen_gate = false) and summary.json counts
  /// seen_gate_misses, the checks the gate would have answered wrongly.
  bool seen_gate_verify = false;
  /// The gate's share of the plan's frontier cells that must still border
  /// unknown for the frontier to be taken as not seen, in (0, 1].
  double seen_gate_fraction = 0.9;
  /// @brief replan_at_stops resolved for the strategy (nbv true: the thesis'
  ///        next-best-view; false: the nearest baseline).
  bool replanAtStopsInForce(bool nbv) const;
  /// Continuous: a circle drive's last turn goes to the nearer of the
  /// target's yaw and its half turn when the cameras see the same from both
  /// (common::mountsSymmetricUnderHalfTurn; the thesis ring does). Off until
  /// a campaign shows it: 3 compact runs 1,302 -> 1,338 s (b4 nbv 321 ->
  /// 266 s, b4 nearest 236 -> 253 s, b1 nbv 745 -> 819 s: other courses).
  bool half_turn_views = false;
  /// @brief [path] turn_on_the_way_deg as in force: `configured` when >= 0,
  ///        else (auto) 150 deg in continuous mode (any planned turn; under
  ///        180 so that the way round stays the planned one) and 0 in
  ///        stop-and-scan (the robot stops at every waypoint anyway).
  static double turnOnTheWayDegInForce(double configured, ScanMode mode);
  /// Continuous: a scan taken while driving is registered and integrated
  /// beside the driving (SlamIcp::processStop on a worker thread) and its
  /// result is taken this long after the scan, or earlier when the drive
  /// ends, the next scan is due or the loop needs the map; meanwhile the
  /// robot drives on odometry from the stop before. The point in robot time
  /// where a result is taken does not depend on how long the thread took,
  /// so runs stay deterministic. 0 = at once: the control loop waits for
  /// SlamIcp (95 ms median, 1 s at a loop closure) [s].
  double scan_latency_s = 0;
  /// @brief low_obstacle_replan resolved for the planner's collision
  ///        parameters on a map of resolution l_res_m.
  bool lowObstacleReplanInForce(const exploration::CollisionParams& col, double l_res_m) const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

}  // namespace voxplore::mission
