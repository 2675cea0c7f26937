/* voxplore — the scan SlamIcp integrates beside the driving
 * ([explore] scan_latency_s). Internal to libs/mission (ExplorationLoop*.cpp). */
#pragma once

#include <voxplore/mission/ExplorationLoop.h>

#include <future>
#include <utility>

namespace voxplore::mission
{
struct ExplorationLoop::PendingScan
{
  Scan scan;
  mrpt::poses::CPose2D odometry;  ///< the robot's odometry when it was taken
  double t_s = 0;                 ///< robot time it was taken [s]
  std::future<std::pair<mapping::StopReport, double>> result;  ///< report, SlamIcp seconds
};
}  // namespace voxplore::mission
