/* voxplore — voxplore-replay: offline SlamIcp over a rawlog. */
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace voxplore::apps
{
/// @brief Command-line options of voxplore-replay.
struct ReplayOptions
{
  std::string config;       ///< ini with [cloud] [metaview] [icp] [octomap] (empty: defaults)
  std::string rawlog;       ///< input rawlog (plain or gzip)
  std::string out_dir;      ///< output directory
  std::string ground_truth; ///< TUM file; empty: trajectory_gt.tum beside the rawlog when present
  std::optional<bool> icp;  ///< overrides [icp] enabled
  std::size_t max_stops = 0;  ///< 0 = all
  bool quiet = false;
  bool verbose = false;  ///< corrupt rawlog: MRPT's full message too (the error is one line)
};

/// @brief What a replay did.
struct ReplaySummary
{
  std::size_t entries = 0;        ///< rawlog entries read
  std::size_t stops = 0;          ///< entries with depth images (processed)
  std::size_t flagged = 0;        ///< stops whose ICP was rejected or skipped
  std::size_t integrated = 0;     ///< stops that entered the maps (flagged ones do not)
  std::size_t relocalized = 0;    ///< stops whose pose was found again after a rejected ICP
  std::size_t skipped_cameras = 0;  ///< depth images skipped as faulty or missing, over all stops
  std::size_t warnings = 0;       ///< warnings printed (faulty cameras, odometry)
  /// "end of rawlog", "max_stops" (--max-stops reached), "interrupted" (SIGINT / SIGTERM) or
  /// "rawlog error" (corrupt or truncated; execute() then throws after writing the outputs)
  std::string termination_reason = "end of rawlog";
  std::size_t degenerate = 0;     ///< stops with a degenerate direction
  std::size_t missing_odometry = 0;
  std::size_t metaview_points = 0;
  std::size_t loop_closures = 0;  ///< loops closed (confirmed, graph relaxed)
  std::size_t loop_edges = 0;     ///< loop edges in the pose graph
  double loop_max_shift_m = 0;    ///< the largest keyframe shift of any relaxation [m]
  std::vector<std::size_t> loop_stops;  ///< the stops that closed a loop
  bool has_ground_truth = false;
  double ate_rmse_m = 0, ate_max_m = 0, final_yaw_error_deg = 0, final_xy_error_m = 0;
  double ate_online_rmse_m = 0;  ///< ATE of trajectory_online.tum (before later relaxations) [m]
  double mean_stop_ms = 0;
};

/// @brief voxplore-replay: SlamIcp over a rawlog of CObservation3DRangeScan +
///        odometry; writes map.bt, map.simplemap, metaview.ply,
///        trajectory_est.tum, stops.csv, params.ini and summary.json to DIR.
class ReplayApp
{
 public:
  /// @brief Parses the command line (TCLAP, --help) and runs. Never throws.
  int run(int argc, const char* const* argv);
  /// @brief Runs with parsed options. Whatever was mapped before a failure
  ///        is written before the exception propagates.
  /// @throws std::runtime_error on bad input, naming the file, entry or key.
  ReplaySummary execute(const ReplayOptions& opts);
};

}  // namespace voxplore::apps
