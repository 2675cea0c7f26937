/* voxplore — loop closure for SlamIcp (thesis 5.3.1 / 6.2): keyframes, a
 * planar pose graph, loop detection against old keyframes only, relaxation
 * with MRPT's sparse Levenberg-Marquardt (optimize_graph_spa_levmarq).
 *
 * Ours where MRPT has no fit: MRPT's loop *detection* (CLoopCloserERD) is
 * built for 2D laser scans and its graph-SLAM engine for its own node
 * registrars; the detection, the verification and the edge information below
 * are written for our merged 8-camera clouds. The optimiser is MRPT's. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/mapping/PlanarIcp.h>

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::mapping
{
/// @brief Loop closure settings. ini section [loop_closure].
struct LoopClosureParams : public mrpt::config::CLoadableOptions
{
  bool enabled = true;            ///< false: the thesis' SlamIcp (no pose graph, no correction)
  /// A keyframe is "old" for the current one when the robot has travelled at
  /// least this far (along its estimated path) since it [m].
  double min_travel_m = 12.0;
  /// Detection runs when an old keyframe's estimate is within this of the
  /// current estimate [m].
  double search_radius_m = 2.5;
  /// The submap: old keyframes within this of the current estimate [m].
  double submap_radius_m = 7.0;
  double submap_cell_m = 0.03;    ///< the submap's 2D point reduction [m]
  /// The submap holds only the keyframes within this much travel of the
  /// nearest old one (one pass, consistent with itself); 0 = every old
  /// keyframe in submap_radius_m (b17: such a submap pulled a right estimate 16 cm off) [m]
  double submap_pass_m = 0;
  /// A match that corrects the estimate (not a consistent one) is registered
  /// again against its anchor's own pass: the keyframes within anchor_pass_m
  /// of travel of the old keyframe nearest the match. Where that pass pairs
  /// at least anchor_min_goodness of the cloud, the match must be accepted
  /// there and stay within anchor_check_m and anchor_check_yaw, else there
  /// is no loop: a submap of several passes that drifted apart can pull a
  /// match onto another pass (b19 omniRob nearest: 0.177 m). A pass that
  /// pairs less cannot judge it. 0 = off [m].
  double anchor_check_m = 0.05;
  double anchor_check_yaw = mrpt::DEG2RAD(1.5);  ///< [rad] (ini: deg)
  double anchor_pass_m = 5.0;                    ///< [m]
  double anchor_min_goodness = 0.5;              ///< below it the pass does not judge
  /// Pose uncertainty that the search covers: drift_per_m times the distance
  /// travelled since the old keyframe, clamped to [min_window_m, max_window_m].
  double drift_per_m = 0.02;
  double min_window_m = 0.3;      ///< [m]
  double max_window_m = 1.5;      ///< [m]
  double yaw_drift_per_m = mrpt::DEG2RAD(0.2);  ///< yaw window per travelled m [rad] (ini: deg)
  double min_window_yaw = mrpt::DEG2RAD(5.0);   ///< [rad] (ini: deg)
  double max_window_yaw = mrpt::DEG2RAD(20.0);  ///< [rad] (ini: deg)
  double min_goodness = 0.8;      ///< share of the cloud paired with the submap within d_max_final_m
  /// A stop whose cloud (before the d_min reduction) has fewer points than
  /// this searches no loop and confirms none: a loop moves the whole graph,
  /// and a sparse view of open space pairs fully at a wrong pose
  /// (willowgarage nbv: stops of 1,016-1,342 points closed one loop
  /// 0.29-0.36 m off). Every loop search of 120 campaign runs (fifty-fourth
  /// session) had over 2,000 points, so they are unchanged. 0 = no limit.
  int min_points = 1500;
  /// Ambiguity: no distinct pose may come within this goodness of the best.
  double margin = 0.15;
  /// A correcting match whose translational information is lopsided
  /// (smallest / largest eigenvalue of its point-to-line J^T J,
  /// IcpResult::info_ratio, under probe_ratio) fixes the pose well across
  /// one direction only (a corridor, a hall's long wall) and is probed along
  /// the other: registered again from probe_m either side of it there, both
  /// must come back within probe_tol_m of it, else there is no loop (the
  /// cost is flat there and the match stays wherever it started: b3
  /// compact nearest seed 3, matches 0.16 and 0.21 m off along a wall at
  /// ratios 0.08 and 0.10, one confirming the other, and against the old
  /// stop's own pass too). 0 = off, the default: online it removed the
  /// campaign's 4 suspect closures but cost more ATE and map precision
  /// than they did (BENCHMARKS.md, fiftieth session); 0.3 probes.
  double probe_ratio = 0.0;
  double probe_m = 0.15;       ///< [m]
  double probe_tol_m = 0.025;  ///< [m]
  /// A match whose correction of the estimate is below this is consistent
  /// with the graph: its edge is added without confirmation and without a
  /// relaxation [m].
  double consistent_m = 0.03;
  double consistent_yaw = mrpt::DEG2RAD(0.5);  ///< [rad] (ini: deg)
  /// A larger correction must be confirmed by one of the next
  /// confirm_within keyframes: its own match must agree with the first
  /// match carried forward by odometry within confirm_xy_m + confirm_per_m
  /// x the distance driven, and confirm_yaw.
  int confirm_within = 3;
  double confirm_xy_m = 0.05;     ///< [m]
  double confirm_per_m = 0.02;    ///< [m per m driven]
  double confirm_yaw = mrpt::DEG2RAD(1.5);  ///< [rad] (ini: deg)
  /// A keyframe confirms (or replaces) a candidate only when the odometry
  /// since it has moved at least confirm_min_move_m or turned at least
  /// confirm_min_turn: one standing where the candidate stood sees the same
  /// submap the same way and repeats an aliased match (b17 compact nbv,
  /// stop-and-scan: a 16 cm false closure "confirmed" 2 cm away). Nearer
  /// keyframes wait (within confirm_within). 0 and 0 = off.
  double confirm_min_move_m = 0.0;  ///< [m]
  double confirm_min_turn = 0.0;    ///< [rad] (ini: deg)
  /// A consistent match (the registration against the metaview has already
  /// carried the estimate onto the old map) that agrees with a waiting
  /// candidate confirms it, and the loop closes: the stretch that drifted
  /// before the candidate is relaxed. false = a consistent match adds its
  /// edge only, and the candidate waits for a correcting match.
  bool confirm_when_consistent = true;
  /// Implicit loops. The metaview registration pairs a stop's cloud with
  /// every pass that saw the place, so where old walls are in view it
  /// carries the estimate back onto the old map by itself, and the edge from
  /// the previous keyframe holds that return as motion (the fifty-first
  /// session: 44 such returns in 40 runs left drifted stretches that no
  /// closure corrected). With chain_recent_m > 0, where a keyframe older
  /// than chain_recent_m of travel is within submap_radius_m, the edge from
  /// the previous keyframe is the stop's cloud registered against the
  /// keyframes of the last chain_recent_m of travel only (one pass, from the
  /// previous keyframe plus the odometry step; the metaview registration's
  /// edge when that is refused or degenerate), and the metaview registration
  /// becomes an edge from the nearest old keyframe, provided the old
  /// keyframes' points pair at least implicit_min_old_share of the cloud at
  /// the metaview pose (else an old keyframe behind a wall would pin the
  /// drifted estimate to itself). When the two differ beyond consistent_m /
  /// consistent_yaw and by at least implicit_min_m, the graph is relaxed:
  /// the return is spread over the loop instead of held as one step. Off by
  /// default: replays of 13 campaign runs, 5 better, 4 worse, 8 suspect
  /// closures (BENCHMARKS.md, fifty-second session). 0 = off [m].
  double chain_recent_m = 0.0;
  double implicit_min_old_share = 0.3;  ///< see chain_recent_m
  /// An implicit loop relaxes the graph only when the two registrations
  /// differ by at least this (translation + 3 m x yaw) [m]
  double implicit_min_m = 0.08;
  /// The maps are rebuilt from the keyframes when a relaxation moved a
  /// keyframe by more than this [m] (or yaw x 3 m by more than it).
  double rebuild_min_shift_m = 0.02;
  /// The OctoMap is rebuilt over the following stops, this many keyframes
  /// re-inserted per stop (the closing stop included), while planning goes
  /// on with the map as it was plus the new stops at corrected poses; the
  /// metaview, which the next registration needs, is moved at once. 0 =
  /// the whole OctoMap at the closing stop (22 s at 1,000 keyframes).
  int octomap_rebuild_per_stop = 30;
  /// Edge information from the registration's point-to-line information
  /// matrix: J^T J / sigma^2 x edge_info_scale, sigma = max(rms, edge_sigma_floor_m);
  /// the scale < 1 accounts for residuals that are not independent.
  double edge_sigma_floor_m = 0.01;
  double edge_info_scale = 0.05;
  double edge_min_std_m = 0.003;  ///< translation std of an edge at least [m]
  double edge_max_std_m = 1.0;    ///< ... at most (unconstrained directions) [m]
  double edge_min_std_yaw = mrpt::DEG2RAD(0.05);  ///< [rad] (ini: deg)
  double edge_max_std_yaw = mrpt::DEG2RAD(20.0);  ///< [rad] (ini: deg)
  /// Edges without a registration (odometry only): std per m driven.
  double odometry_std_per_m = 0.05;
  double odometry_std_yaw_per_m = mrpt::DEG2RAD(1.0);  ///< [rad per m] (ini: deg per m)
  int max_iterations = 100;       ///< Levenberg-Marquardt iterations at most

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief One integrated stop: what is needed to integrate it again.
struct Keyframe
{
  std::size_t stop = 0;            ///< StopReport::index
  mrpt::poses::CPose2D pose;       ///< T_map_robot, the graph's current estimate
  mrpt::poses::CPose2D odometry;   ///< the raw odometry reading at the stop
  double travel_m = 0;             ///< distance travelled (estimate) up to this stop
  /// The stop's cloud Q (robot frame, floor cut), reduced to one point per
  /// d_min cell: rebuilds the metaview and makes the loop submaps.
  mrpt::maps::CSimplePointsMap cloud;
  std::size_t cloud_points = 0;  ///< the stop's cloud before the reduction (min_points)
};

/// @brief What loop closure did at one keyframe (stops.csv, summary.json).
struct LoopEvent
{
  bool searched = false;           ///< old keyframes were near: a match was tried
  bool consistent = false;         ///< matched with a correction below consistent_*: edge added
  bool candidate = false;          ///< a larger correction found, waiting for confirmation
  bool closed = false;             ///< a confirmed loop: edges added and the graph relaxed
  bool rebuilt = false;            ///< the maps were rebuilt after the relaxation
  std::size_t with_stop = 0;       ///< the old keyframe (stop index) the loop edge joins
  mrpt::poses::CPose2D matched;    ///< the current keyframe's pose as the match put it
  double correction_m = 0;         ///< correction of the current estimate by the match [m]
  double correction_yaw = 0;       ///< ... [rad]
  double graph_shift_max_m = 0;    ///< largest keyframe displacement by the relaxation [m]
  double graph_shift_mean_m = 0;   ///< mean keyframe displacement [m]
  double goodness = 0;             ///< the match's goodness
  /// The anchor-pass check (anchor_check_m): how far the anchor's own pass
  /// moved the match, and its goodness there (-1: not checked).
  double anchor_shift_m = -1, anchor_shift_yaw = 0, anchor_goodness = 0;
  double t_detect_ms = 0, t_optimize_ms = 0, t_rebuild_ms = 0;
  std::string message;             ///< what happened, for the user (empty: nothing)
};

/// @brief How far ICP ends up from `match` (a registration of `cloud_robot`
///        against `submap` from `prediction`) when started `probe_m` either
///        side of it along its weak translational direction
///        (IcpResult::degenerate_dir), same yaw: the larger distance [m].
///        Where the scene fixes the pose along that direction the two come
///        back onto the match; where the cost is flat there (a corridor
///        whose only cross features the submap holds twice, from a pass
///        that drifted) they stay apart. LoopCloser's probe_ratio check.
///        Infinity when the match has no weak direction (no information).
double slideAlongWeak(const mrpt::maps::CPointsMap& submap, const Viewpoints* views,
                      const mrpt::maps::CPointsMap& cloud_robot, const mrpt::poses::CPose2D& prediction,
                      const IcpResult& match, const IcpParams& p, double probe_m);

/// @brief The keyframes, the pose graph and loop detection. SlamIcp owns
///        one; it can be used alone (the benchmark does).
class LoopCloser
{
 public:
  LoopCloser(const LoopClosureParams& params, const IcpParams& icp);
  ~LoopCloser();
  LoopCloser(LoopCloser&&) noexcept;
  LoopCloser& operator=(LoopCloser&&) noexcept;

  /// @brief Adds a keyframe at `pose` (its registration `reg`, if ICP
  ///        registered it, gives the information of the edge from the
  ///        previous keyframe), then looks for a loop and relaxes the graph
  ///        when one is confirmed. keyframes() then hold the corrected poses.
  /// @param cloud_robot the stop's robot-frame cloud (reduced here)
  /// @param d_min_m the reduction cell (the metaview's d_min)
  LoopEvent addKeyframe(std::size_t stop, const mrpt::poses::CPose2D& pose,
                        const mrpt::poses::CPose2D& odometry, double travel_m,
                        const mrpt::maps::CPointsMap& cloud_robot, double d_min_m,
                        const IcpResult* reg);

  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  std::size_t numEdges() const;
  std::size_t numLoopEdges() const { return loop_edges_; }
  const LoopClosureParams& params() const { return params_; }

  /// @brief The 2D submap of the old keyframes near `around` (keyframes with
  ///        travel_m in [min_travel_m, max_travel_m] within submap_radius_m),
  ///        map frame. Empty when none. `viewpoints` gets each point's
  ///        keyframe position (where it was seen from).
  mrpt::maps::CSimplePointsMap submapAround(const mrpt::poses::CPose2D& around, Viewpoints& viewpoints,
                                            double min_travel_m, double max_travel_m) const;

  /// @brief Relaxes the graph now (MRPT's SPA Levenberg-Marquardt), copies the
  ///        result into keyframes(); returns the largest and mean shift [m].
  std::pair<double, double> optimize();

  /// @brief Information matrix (x, y, yaw in the frame of `from`) of an
  ///        edge from a registration (null: odometry only, over `dist_m`).
  Eigen::Matrix3d edgeInformation(const IcpResult* reg, const mrpt::poses::CPose2D& from,
                                  double dist_m) const;

 private:
  struct Graph;
  struct Pending
  {
    std::size_t kf = 0, anchor = 0;  ///< keyframe indices
    mrpt::poses::CPose2D matched;    ///< the keyframe's pose as the match put it
    IcpResult reg;
  };
  /// A match at `matched` agrees with the estimate `estimate` (within
  /// consistent_m and consistent_yaw): it corrects nothing.
  bool consistent(const mrpt::poses::CPose2D& matched, const mrpt::poses::CPose2D& estimate) const;
  /// chain_recent_m: the cloud of keyframe `kf` (not yet added) registered
  /// against the keyframes of the last chain_recent_m of travel before it,
  /// from the previous keyframe plus the odometry step; nullopt when
  /// refused, degenerate or nothing recent is near. Called by implicitLoop()
  /// only (chain_recent_m > 0, keyframes() not empty).
  std::optional<IcpResult> chainRegistration(const Keyframe& kf) const;
  /// The keyframe nearest `pose` among those at least chain_recent_m of
  /// travel before `travel_m` and within submap_radius_m; nullopt if none.
  std::optional<std::size_t> nearestOlderThanChain(const mrpt::poses::CPose2D& pose, double travel_m) const;
  /// Loop detection for the newest keyframe: match, candidate,
  /// confirmation, relaxation; fills `ev`.
  void detectLoop(LoopEvent& ev);
  /// chain_recent_m: the recent pass's registration of a new keyframe
  /// and the old keyframe nearest it.
  struct ImplicitLoop
  {
    IcpResult chain;
    std::size_t anchor = 0;
    double old_share = 0;  ///< goodness of the cloud against the old keyframes at its metaview pose
  };
  /// For keyframe `kf` (not yet added): nullopt when no keyframe older than
  /// chain_recent_m of travel (and not the previous one) is within
  /// submap_radius_m, when those old keyframes pair less than
  /// implicit_min_old_share of its cloud at its metaview pose, or when the
  /// recent pass does not register it.
  std::optional<ImplicitLoop> implicitLoop(const Keyframe& kf) const;
  /// Relaxes the graph after the newest keyframe's metaview registration
  /// (at `registered`) came out inconsistent with the recent pass's; fills `ev`.
  void relaxImplicitLoop(LoopEvent& ev, const ImplicitLoop& implicit,
                         const mrpt::poses::CPose2D& registered);
  /// Match the newest keyframe against its old neighbours; nullopt: no match.
  std::optional<IcpResult> match(LoopEvent& ev, std::size_t& anchor);
  /// The match `r` registered again against its anchor's own pass
  /// (anchor_check_m): nullopt when it holds there, else why not.
  std::optional<std::string> anchorDisagrees(LoopEvent& ev, const IcpResult& r, std::size_t anchor,
                                             double max_travel, const IcpParams& p) const;
  void addLoopEdge(std::size_t anchor, std::size_t kf, const mrpt::poses::CPose2D& matched,
                   const IcpResult& reg);
  struct Agreement
  {
    bool agrees = false;
    double err_m = 0, err_yaw = 0;  ///< [m], [rad]
  };
  /// Does the newest keyframe `cur`, matched at `matched`, agree with the
  /// candidate carried forward by the odometry (confirm_xy_m, confirm_per_m,
  /// confirm_yaw)?
  Agreement agreement(const Pending& pending, const Keyframe& cur,
                      const mrpt::poses::CPose2D& matched) const;
  /// Relaxes the graph and records it in `ev` (closed, graph shift,
  /// optimisation time).
  void relax(LoopEvent& ev);
  /// Closes the waiting candidate: its edge, then `match`'s (to the newest
  /// keyframe from `anchor`) unless null (then the edges since the
  /// candidate become odometry edges), then the relaxation; fills ev's
  /// closure fields (closed, graph shift, optimisation time).
  void closePending(LoopEvent& ev, const IcpResult* match, std::size_t anchor);
  /// Why `r` does not hold along its weak direction (probe_ratio), or
  /// nothing when it holds or is not probed.
  std::optional<std::string> slidesAlongWeak(const mrpt::maps::CPointsMap& submap, const Viewpoints& views,
                                             const IcpResult& r, const IcpParams& p) const;
  /// Has a keyframe that moved `moved` (odometry) since the candidate
  /// moved or turned enough to confirm it (confirm_min_move_m / _turn)?
  bool independentOf(const mrpt::poses::CPose2D& moved) const;

  LoopClosureParams params_;
  IcpParams icp_;
  std::vector<Keyframe> keyframes_;
  std::unique_ptr<Graph> graph_;
  std::optional<Pending> pending_;
  std::size_t loop_edges_ = 0;
};

/// @brief `cloud` reduced to its first point per cubic cell of `cell_m`
///        (all points when cell_m <= 0).
mrpt::maps::CSimplePointsMap reduceCloud(const mrpt::maps::CPointsMap& cloud, double cell_m);

}  // namespace voxplore::mapping
