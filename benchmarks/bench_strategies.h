/* voxplore-bench — exploration strategies end to end (issue 5): every world
 * explored by voxplore-explore's loop (ExploreApp::execute) once with the next
 * best view planner (nbv, thesis chapter 4) and once with the nearest-frontier
 * baseline (nearest), side by side: steps, travel, coverage, compute time. */
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::bench
{
/// @brief Command-line settings of the strategies table.
struct StrategyBenchOptions
{
  std::string config;             ///< explore ini (config/explore.ini)
  std::string source_dir;         ///< simulated_worlds/ lives here
  std::string shared_worlds_dir;  ///< ../shared/worlds; missing: its worlds are skipped loudly
  std::string starts_file;        ///< simulated_worlds/shared_world_starts.txt
  std::string out_root = "/tmp/voxplore_bench_strategies";  ///< run directories go here
  std::optional<int> max_steps;  ///< overrides [explore] max_steps (quick runs)
  std::string csv_dir;           ///< write strategies.csv here when set
  bool quiet = false;            ///< no progress on stderr
};

/// @brief One line of shared_world_starts.txt.
struct SharedWorldStart
{
  std::string relative_path;  ///< under ../shared/worlds
  double x_m = 0, y_m = 0, yaw_deg = 0;
  std::string robot;  ///< omnirob | compact
};

/// @brief Reads "<relative path> x y yaw_deg robot" lines ('#' comments, blank lines).
/// @throws std::runtime_error naming the file and line when a line is malformed
///         or the file cannot be read.
std::vector<SharedWorldStart> readSharedWorldStarts(const std::string& path);

/// @brief Explores dlr_test_room and office (omnirob) and the shared worlds
///        of opts.starts_file (when opts.shared_worlds_dir holds them) with
///        strategy nbv and nearest, and prints one row per world to `out`:
///        steps, path length, coverage_2d and compute time of both, and the
///        travel ratio nbv / nearest (also per unit of coverage).
/// A run that throws is reported on stderr and its row shows "ERROR" with zeros.
/// @throws std::runtime_error when the starts file is malformed.
void runStrategiesTable(const StrategyBenchOptions& opts, std::ostream& out);

}  // namespace voxplore::bench
