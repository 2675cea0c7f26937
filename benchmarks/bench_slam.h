/* voxplore-bench — the SlamIcp tables: thesis table 5.1 (metaview point
 * reduction d_min: integration into M, ICP, points in M, plus the trajectory
 * error it costs) and the "integration into V" row of table 5.2 (OctoMap
 * insertion per stop over l_res, ours beside stock OctoMap). */
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/mapping/SlamIcp.h>

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::bench
{
/// @brief Command-line settings of the SlamIcp tables.
struct SlamBenchOptions
{
  std::string rawlog;        ///< input rawlog (plain or gzip-compressed)
  std::string ground_truth;  ///< TUM ground truth; empty: trajectory_gt.tum beside the rawlog
  std::string config;        ///< SlamIcp ini ([cloud] [metaview] [icp] [octomap]); empty: defaults
  std::size_t stops = 10;    ///< replay the first N stops (the thesis: 10 measurements)
  std::vector<double> d_min_m;  ///< table 5.1 columns [m]
  std::vector<double> l_res_m;  ///< table 5.2 columns [m]
  bool poses_from_gt = false;   ///< table 5.2: ground-truth poses instead of ICP at d_min 20 mm
  unsigned repeat = 1;          ///< run each column this often; timings are the median
  std::string csv_dir;          ///< write table_5_1.csv / table_5_2_integration.csv here
  bool quiet = false;           ///< no progress on stderr
};

/// @brief The thesis' d_min sweep of table 5.1 [m].
std::vector<double> thesisDminSweep();
/// @brief The thesis' l_res sweep of table 5.2 [m].
std::vector<double> thesisLresSweep();

/// @brief One stop of the rawlog, held in memory for every column.
struct RecordedStop
{
  std::size_t entry = 0;                      ///< rawlog entry index
  mrpt::obs::CActionCollection::Ptr actions;  ///< may be empty
  mrpt::obs::CSensoryFrame::Ptr observations;
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> scans;  ///< its depth images
  mrpt::Clock::time_point timestamp;                           ///< of the first depth image
};

/// @brief What every SlamIcp table reads: the stops, the parameters, ground truth.
struct SlamBenchData
{
  std::vector<RecordedStop> stops;
  mapping::SlamIcpParams params;                  ///< defaults or --config
  std::vector<common::StampedPose> ground_truth;  ///< empty when none was found
  std::string ground_truth_path;                  ///< empty when none was found
};

/// @brief The ground-truth pose of a stop: the TUM row at its timestamp
///        (within 1 ms).
/// @param what names the caller in the error
/// @throws std::runtime_error "WHAT: no ground-truth pose for rawlog entry N
///         in 'FILE'" when there is none
mrpt::poses::CPose3D groundTruthOf(const SlamBenchData& data, const RecordedStop& stop,
                                   const std::string& what);

/// @brief Reads the first opts.stops stops with depth images, the parameters
///        and the ground truth (optional unless named on the command line).
/// @throws std::runtime_error naming the file when the rawlog, config or a
///         named ground truth cannot be read, or the rawlog holds no depth image.
SlamBenchData loadSlamBenchData(const SlamBenchOptions& opts);

/// @brief Replays every stop through a fresh SlamIcp with `params`.
/// @param on_stop called after each stop with the number of stops done (may be empty)
/// @return the reports, one per stop
std::vector<mapping::StopReport> replay(const SlamBenchData& data,
                                        const mapping::SlamIcpParams& params,
                                        const std::function<void(std::size_t)>& on_stop = {});

/// @brief Runs table 5.1 (d_min sweep), prints it to `out`, writes its CSV.
/// @return the ICP poses (T_map_robot) of the d_min = 20 mm column; empty
///         when the sweep has no such column.
std::vector<mrpt::poses::CPose3D> runDminTable(const SlamBenchData& data,
                                               const SlamBenchOptions& opts, std::ostream& out);

/// @brief Runs the "integration into V" row of table 5.2 over opts.l_res_m:
///        per stop the 8 depth images into fresh trees, ours and stock, at `poses`.
void runIntegrationTable(const SlamBenchData& data, const SlamBenchOptions& opts,
                         const std::vector<mrpt::poses::CPose3D>& poses, std::ostream& out);

/// @brief The poses table 5.2 inserts at: ground truth (opts.poses_from_gt)
///        or `icp_poses`, replaying at d_min 20 mm when that is empty.
/// @throws std::runtime_error when a stop has no ground-truth pose.
std::vector<mrpt::poses::CPose3D> integrationPoses(const SlamBenchData& data,
                                                   const SlamBenchOptions& opts,
                                                   std::vector<mrpt::poses::CPose3D> icp_poses);

/// @brief Median of `values` (which must not be empty).
double median(std::vector<double> values);

}  // namespace voxplore::bench
