#include <mrpt/math/wrap2pi.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/tour.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace voxplore::sim
{
std::vector<Waypoint> loadWaypointsFile(const std::string& path)
{
  std::ifstream f(path);
  if (!f) throw std::runtime_error("waypoints file not found or unreadable: '" + path + "'");
  std::vector<Waypoint> out;
  std::string line;
  for (int lineno = 1; std::getline(f, line); lineno++)
  {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const std::string where = path + ":" + std::to_string(lineno);
    const auto v = common::parseNumberList(line, where);
    if (v.empty()) continue;
    if (v.size() < 2 || v.size() > 3)
      throw std::runtime_error(where + ": expected 'x y [yaw_deg]', got " +
                               std::to_string(v.size()) + " numbers");
    Waypoint w{v[0], v[1], std::nullopt};
    if (v.size() == 3) w.yaw_rad = mrpt::DEG2RAD(v[2]);
    out.push_back(w);
  }
  if (out.empty()) throw std::runtime_error(path + ": no waypoints in file");
  return out;
}

TourResult runTour(
    Simulator& sim, const std::vector<Waypoint>& waypoints,
    const std::function<void(const ScanStop&)>& on_stop,
    const std::function<void(std::size_t, std::size_t)>& on_progress,
    const std::function<bool()>& should_stop)
{
  TourResult res;
  const double travelled0 = sim.robot().distanceTravelled();
  auto scanHere = [&]() {
    on_stop(sim.scan());
    res.stops++;
  };
  auto stopRequested = [&]() {
    if (should_stop && should_stop()) res.stopped_early = true;
    return res.stopped_early;
  };
  scanHere();
  for (std::size_t wi = 0; wi < waypoints.size() && !stopRequested(); wi++)
  {
    const auto& wp = waypoints[wi];
    const auto p0 = sim.robot().groundTruth();
    const double len = std::hypot(wp.x - p0.x(), wp.y - p0.y());
    const double yaw_delta = wp.yaw_rad ? mrpt::math::wrapToPi(*wp.yaw_rad - p0.phi()) : 0.0;
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / sim.params().scan_every_m - 1e-9)));
    for (int k = 1; k <= pieces && !stopRequested(); k++)
    {
      const double f = double(k) / pieces;
      std::optional<double> yaw;
      if (wp.yaw_rad) yaw = mrpt::math::wrapToPi(p0.phi() + f * yaw_delta);
      const auto outcome =
          sim.driveTo(p0.x() + f * (wp.x - p0.x()), p0.y() + f * (wp.y - p0.y()), yaw);
      scanHere();
      if (outcome != DriveOutcome::Reached)
      {
        res.blocked_segments++;
        break;  // abandon this waypoint; go on with the next
      }
    }
    if (on_progress && !res.stopped_early) on_progress(wi + 1, waypoints.size());
  }
  res.path_length_m = sim.robot().distanceTravelled() - travelled0;
  return res;
}

}  // namespace voxplore::sim
