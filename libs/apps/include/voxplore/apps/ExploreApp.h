/* voxplore — voxplore-explore: the autonomous exploration mission (thesis fig. 4.4, 4.6). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <voxplore/mission/ExplorationLoop.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::apps
{
/// @brief Settings of voxplore-explore. ini section [explore]: the loop's
///        limits (mission::ExplorationLoopParams) and the simulator's
///        outputs and ground-truth evaluation.
struct ExploreParams : public mission::ExplorationLoopParams
{
  bool write_step_images = true;    ///< steps/step_NNN.png (renderPlan) at every step
  /// plans/step_NNN.txt + .ot (exploration::writePlanInputs) of the last this
  /// many planning steps, for voxplore-plan; the map is 10-60 MB a step. 0 = none
  int keep_plan_inputs = 0;
  int step_image_scale = 4;         ///< pixels per grid cell of the step images
  double gt_floor_res_m = 0.05;     ///< resolution of the ground-truth free floor (coverage_2d) [m]
  int coverage_yaw_bins = 72;       ///< coverage_2d: yaw bins over [0, 180) deg of the footprint's configuration space (2..128)
  double coverage_view_range_m = 3.0;  ///< coverage_2d: free floor in 2D line of sight of a footprint-reachable centre up to this distance counts [m]; 0 = only the floor the body covers
  double band_z_min_m = 0.10;       ///< coverage_3d: ground-truth surface voxels from this height [m]
  double band_z_max_m = 0.60;       ///< ... up to this height (the cameras' band) [m]
  /// Bound the exploration and the ground-truth free floor to the world's
  /// obstacle bounding box (a building open to the outside, e.g. a mesh on an
  /// added ground plane, is explored inside its own extent, not forever out
  /// into the yard); sets [projection] region in the map frame.
  bool region_from_world = true;

  /// @brief The section name this struct reads.
  static const char* section() { return "explore"; }
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Command-line options of voxplore-explore.
struct ExploreOptions
{
  std::string config;                ///< ini file (empty: built-in defaults)
  std::string world;                 ///< world file, mesh or floor plan
  std::string out_dir = "out/explore";
  std::optional<std::string> start;  ///< "x,y,yaw_deg" overrides the world's start
  std::optional<std::string> robot;  ///< omnirob | compact
  std::optional<int> seed;           ///< overrides [simulator] seed and [planner] seed
  std::optional<std::string> strategy;  ///< nbv | nearest, overrides [planner] strategy
  std::optional<int> max_steps;      ///< overrides [explore] max_steps
  bool quiet = false;                ///< no per-step lines, no parameter dump
};

/// @brief What a run achieved (also summary.json).
struct ExploreSummary
{
  std::string termination_reason;  ///< planner's done reason, "stagnation", "the map shut the robot in", "only small pockets left", "max_steps", "max_sim_time" or "interrupted" (SIGINT / SIGTERM)
  std::string planner_model;  ///< the collision model planned with: "circle" or "footprint" ([collision] model, auto resolved)
  std::size_t steps = 0;           ///< planning steps
  std::size_t stops = 0;           ///< scan stops (SlamIcp calls)
  std::size_t flagged_stops = 0;   ///< stops whose ICP was rejected (pose from odometry, kept out of the maps)
  std::size_t relocalized_stops = 0;  ///< stops found again after a rejected ICP (odometry jump)
  std::size_t held_stops = 0;      ///< stops whose large, unsure correction was held ([icp] hold_sigmas; counted in flagged_stops too)
  std::size_t kept_stops = 0;      ///< stops that kept their odometry prediction ([icp] keep_fitting_prediction)
  std::size_t loop_closures = 0;   ///< loops closed (confirmed, graph relaxed; [loop_closure])
  std::size_t loop_edges = 0;      ///< loop edges in the pose graph (closures and consistent revisits)
  double loop_max_shift_m = 0;     ///< the largest keyframe shift of any relaxation [m]
  std::size_t skipped_cameras = 0;    ///< depth images skipped as faulty or missing, over all stops
  std::size_t failed_drives = 0;   ///< waypoints not reached (Blocked / Timeout / Error)
  std::size_t blacklisted = 0;     ///< targets given up
  std::size_t guard_scaled = 0;    ///< commands the footprint guard slowed ([navigation] footprint_guard)
  std::size_t guard_held = 0;      ///< ... and held still
  std::size_t low_obstacle_replans = 0;  ///< drives ended by a low obstacle seen on the way
  std::size_t scans_moving = 0;  ///< scans taken while driving ([explore] scan_mode = continuous)
  std::size_t seen_checks = 0;   ///< frontiers computed again on the way (replan_on_the_way, replan_at_stops)
  double seen_check_s = 0;       ///< their wall time [s]
  std::size_t seen_gated = 0;        ///< of seen_checks, answered by the projection alone ([explore] seen_gate)
  std::size_t seen_gate_misses = 0;  ///< seen_gate = verify: the gate's wrong answers
  std::size_t targets_seen_on_the_way = 0;  ///< drives ended on the way: their frontier was seen ([explore] replan_on_the_way)
  std::size_t new_frontiers = 0;  ///< frontiers of the last step not near one planned before
  double known_floor_m2 = 0;       ///< free floor known in G at the end [m^2]
  double unobservable_m2 = 0;  ///< open unknown looked at and left unknown at the end ([sampling] retire_looks) [m^2]
  double known_floor_cut_off_m2 = 0;  ///< ... of it, cut off from the robot by the planner's collision space [m^2]
  /// Frontiers left at the end (map frame): centre x, y and length [m].
  std::vector<std::array<double, 3>> frontiers_left;
  double path_length_m = 0;        ///< ground-truth distance travelled [m]
  double time_translating_s = 0;   ///< mission time spent translating [s]
  double time_turning_s = 0;       ///< ... and turning in place; the rest the robot stood [s]
  double coverage_2d = 0;          ///< share of the GT free floor the robot's footprint reaches or sees (floor_reachable_m2) that the map knows as free
  double coverage_2d_planner_circle = 0;  ///< the same share of the floor the planner's collision circle (r_coll + sqrt(2) l_res) reaches
  double coverage_3d = 0;          ///< share of GT surface voxels in the band seen occupied
  double map_precision = 0;        ///< share of occupied map voxels within one voxel of a surface
  double map_precision_above_floor = 0;  ///< the same for voxels above the floor (z > l_res)
  std::size_t collisions = 0;      ///< simulator steps refused because they would collide
  double min_clearance_m = 0;      ///< footprint-to-world distance minimum along the true path [m]
  std::array<double, 3> min_clearance_pose{};  ///< world pose (x [m], y [m], yaw [deg]) where that minimum was
  std::vector<std::array<double, 3>> collision_poses;  ///< world pose (x, y, yaw [deg]) before each refused step
  double ate_rmse_m = 0;           ///< absolute trajectory error of the SLAM poses at stops [m]
  /// ... of the estimates when the robot left each stop (trajectory_online.tum),
  /// before later loop-closure relaxations [m]
  double ate_online_rmse_m = 0;
  double compute_s = 0;            ///< wall time of SLAM + planning [s]
  double sim_time_s = 0;           ///< simulated time [s]
  double coverage_2d_circumradius = 0;  ///< the same share of the floor the bare circumcircle reaches (passages narrower than the planner's radius included)
  double floor_reachable_m2 = 0;   ///< GT free floor the footprint (rotated rectangle, position x yaw) reaches or sees from there [m^2]
  double floor_reachable_planner_circle_m2 = 0;  ///< GT free floor the planner's circle reaches [m^2]
  double floor_reachable_circumradius_m2 = 0;    ///< GT free floor the bare circumcircle reaches [m^2]
  double peak_rss_mb = 0;          ///< peak resident memory of the process (VmHWM) [MiB]
};

/// @brief voxplore-explore: scan, SlamIcp, plan, drive waypoint by waypoint
///        with stop-and-scan, until the planner says done or a limit; writes
///        map.bt, map.simplemap, metaview.ply, run.rawlog, trajectory_gt.tum,
///        trajectory_est.tum, stops.csv, coverage.csv, steps/step_NNN.png,
///        params.ini and summary.json into the output directory.
class ExploreApp
{
 public:
  /// @brief Parses the command line (TCLAP, --help) and runs. Never throws.
  /// @return 0 on success, 1 on error (message on stderr)
  int run(int argc, const char* const* argv);

  /// @brief Runs with parsed options. On an exception mid-run the maps and
  ///        logs so far are written before it propagates.
  /// @throws std::runtime_error on bad input (naming the file or key).
  ExploreSummary execute(const ExploreOptions& opts);
};

/// @brief Writes `s` as JSON. @throws std::runtime_error naming the path.
void writeExploreSummary(const ExploreSummary& s, const std::string& path);

}  // namespace voxplore::apps
