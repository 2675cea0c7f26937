/* voxplore — scripted scan tours: drive through waypoints, stop and scan. */
#pragma once

#include <voxplore/sim/Simulator.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::sim
{
/// @brief One tour waypoint in world metres; yaw optional.
struct Waypoint
{
  double x = 0, y = 0;
  std::optional<double> yaw_rad;
};

/// @brief Reads "x y [yaw_deg]" per line; '#' starts a comment; blank lines skipped.
/// @throws std::runtime_error naming the file and line for malformed lines.
std::vector<Waypoint> loadWaypointsFile(const std::string& path);

/// @brief What a tour did.
struct TourResult
{
  std::size_t stops = 0;
  std::size_t blocked_segments = 0;  ///< stop points the robot could not reach
  double path_length_m = 0;          ///< ground-truth distance travelled
  bool stopped_early = false;        ///< should_stop() returned true before the end
};

/// @brief Scans at the start, then drives each segment in pieces of at most
///        scan_every_m, scanning at each piece end (and so at each waypoint).
///        A blocked piece is abandoned (the robot scans where it stopped and
///        goes on to the next waypoint).
/// @param on_stop called for every scan stop, in order
/// @param on_progress called after each waypoint with (waypoints done, total)
/// @param should_stop polled after every scan stop (so between stops, never
///        inside one); when it returns true the tour ends there with
///        TourResult::stopped_early set. Empty: never stops early.
TourResult runTour(
    Simulator& sim, const std::vector<Waypoint>& waypoints,
    const std::function<void(const ScanStop&)>& on_stop,
    const std::function<void(std::size_t, std::size_t)>& on_progress = {},
    const std::function<bool()>& should_stop = {});

}  // namespace voxplore::sim
