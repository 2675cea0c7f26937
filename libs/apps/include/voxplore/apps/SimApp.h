/* voxplore — the mrpt-sim application: a scripted scan tour through a world. */
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace voxplore::apps
{
/// @brief Command-line options of mrpt-sim.
struct SimOptions
{
  std::string world;        ///< world file, mesh or floor plan
  std::string waypoints;    ///< "x y [yaw_deg]" per line
  std::string out_dir;      ///< output directory
  std::string config;       ///< ini file (empty: built-in defaults)
  std::optional<int> seed;  ///< overrides [simulator] seed
  std::optional<std::string> start;  ///< "x,y,yaw_deg" overrides the world's start
  std::optional<std::string> robot;  ///< omnirob | compact
  bool no_noise = false;    ///< switch off sensor, motion and odometry noise
  bool quiet = false;       ///< no progress bar
};

/// @brief Summary of a finished tour.
struct SimRunSummary
{
  std::size_t stops = 0;
  std::size_t blocked_segments = 0;
  std::size_t collisions = 0;
  double path_length_m = 0;
  double sim_time_s = 0;
  bool interrupted = false;  ///< stopped between stops by SIGINT / SIGTERM (interruptRequested())
};

/// @brief mrpt-sim: drives the robot through waypoints, scanning every
///        scan_every_m and at each waypoint; writes DIR/run.rawlog,
///        DIR/trajectory_gt.tum, DIR/trajectory_odo.tum, DIR/topview.png and
///        DIR/params.ini (the parameters in force).
class SimApp
{
 public:
  /// @brief Parses the command line (TCLAP, --help) and runs. Never throws.
  /// @return 0 on success, 1 on error (message on stderr)
  int run(int argc, const char* const* argv);

  /// @brief Runs with parsed options. Polls interruptRequested() after every
  ///        stop: when set, ends the tour there and writes every output for
  ///        the stops so far (SimRunSummary::interrupted).
  ///        @throws std::runtime_error on bad input.
  SimRunSummary execute(const SimOptions& opts);
};

}  // namespace voxplore::apps
