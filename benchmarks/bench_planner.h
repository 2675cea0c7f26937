/* voxplore-bench — the exploration planner rows of thesis table 5.2
 * (projection, collision space, frontiers, pose sampling, scan rating per
 * sample, path; issue 4): V of the first stops built by SlamIcp at each
 * l_res, then exploration::plan from the last pose, ours beside the thesis'
 * figures and beside the naive scan rating on the same sample poses. */
#pragma once

#include <iosfwd>

#include "bench_slam.h"

namespace voxplore::bench
{
/// @brief Runs the planner tables over opts.l_res_m and prints them to `out`.
///        Per l_res: replays the first opts.stops stops through SlamIcp
///        (d_min 20 mm, [octomap] l_res_m swept) to build V, plans from the
///        last stop whose plan rates a full set of max_samples poses (else the
///        last with any sample; the output says which) with the thesis'
///        PlannerParams, opts.repeat times at beam_reduction 3 and 1
///        (medians), and rates the plan's sample poses with rateScan and
///        rateScanNaive (gains compared). Writes table_5_2_planner.csv,
///        planner_scan_rating.csv, planner_maps.csv and planner_params.ini
///        into opts.csv_dir when set.
/// @throws std::runtime_error when the rawlog or config cannot be read.
void runPlannerTable(const SlamBenchOptions& opts, std::ostream& out);

}  // namespace voxplore::bench
