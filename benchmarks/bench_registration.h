/* voxplore-bench — 'registration': each stop's planar ICP against the
 * ground-truth map of the stops before it, so that its own error shows
 * without the drift of the run. */
#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <vector>

#include "bench_slam.h"

namespace voxplore::bench
{
/// @brief One stop's registration from ground truth(k-1) + odometry.
struct RegistrationError
{
  std::size_t stop = 0;
  double step_m = 0;            ///< true translation since the previous stop [m]
  double odometry_error_m = 0;  ///< the prediction's translation error [m]
  double error_m = 0;           ///< the registered pose's translation error [m]
  double along_m = 0, across_m = 0;  ///< the error in the true robot frame (x forward) [m]
  double yaw_error_deg = 0;
  double goodness = 0, info_ratio = 0;
  bool accepted = false, relocalized = false;
};

struct RegistrationErrors
{
  std::vector<RegistrationError> stops;  ///< every stop after the first
};

/// @brief Registers every stop after the first against a metaview of the
///        stops before it at their ground-truth poses (SlamIcp's
///        alignPlanar, then relocalizePlanar after a rejection).
/// @throws std::runtime_error without ground truth or when a stop has none
RegistrationErrors measureRegistration(const SlamBenchData& data,
                                       const std::function<void(std::size_t)>& on_stop = {});

/// @brief measureRegistration(), its error distribution and worst stops on
///        `out`, registration.csv in opts.csv_dir.
void runRegistrationTable(const SlamBenchData& data, const SlamBenchOptions& opts, std::ostream& out);

}  // namespace voxplore::bench
