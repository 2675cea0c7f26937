/* voxplore-bench — 'loops': what one loop closure costs against the number
 * of keyframes (issue 11): detection against the old keyframes, the pose
 * graph's relaxation, and the rebuild of the metaview and the OctoMap from
 * every keyframe, plus the memory a keyframe holds. */
#pragma once

#include <cstddef>
#include <iosfwd>
#include <vector>

#include "bench_slam.h"

namespace voxplore::bench
{
/// @brief Settings of the 'loops' table.
struct LoopBenchOptions
{
  std::vector<std::size_t> keyframes{100, 500, 1000, 2000};  ///< one column per count
  std::size_t queries = 6;  ///< loop closures tried per column and repetition
  /// The drift of the revisiting keyframe's estimate that the detection must
  /// find (robot frame of its true pose) [m, m, rad]: 0.22 m and 2 deg, inside
  /// the default search window (>= 0.3 m, >= 5 deg).
  double offset_x_m = 0.20, offset_y_m = 0.10, offset_yaw_rad = 0.0349066;
};

/// @brief The issue-11 table: for each keyframe count N, keyframe k takes
///        recorded stop (k mod M) at its ground-truth pose (the stops repeat
///        on later laps when N > M); then a revisiting stop is detected
///        against the N old keyframes (once from its true pose, once from a
///        drifted estimate that the next stop confirms), the loop closure
///        relaxes the graph, and the metaview and the OctoMap are rebuilt from
///        the N keyframes as SlamIcp::rebuildMaps does. Timings are medians
///        over opts.repeat runs (and opts.queries revisits for detection and
///        relaxation). Markdown table on `out`, loops.csv in opts.csv_dir.
/// @throws std::runtime_error without ground truth, without a stop that has
///         one, or when [loop_closure] min_travel_m is not > 0.
void runLoopsTable(const SlamBenchData& data, const SlamBenchOptions& opts,
                   const LoopBenchOptions& loops, std::ostream& out);

}  // namespace voxplore::bench
