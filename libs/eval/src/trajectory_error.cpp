#include <mrpt/math/wrap2pi.h>
#include <voxplore/eval/trajectory_error.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace voxplore::eval
{
TrajectoryError trajectoryError(
    const std::vector<common::StampedPose>& est, const std::vector<common::StampedPose>& gt,
    double max_dt_s)
{
  // Associate each estimate with the nearest ground-truth timestamp.
  std::vector<std::pair<const common::StampedPose*, const common::StampedPose*>> pairs;
  for (const auto& e : est)
  {
    const auto it = std::lower_bound(gt.begin(), gt.end(), e.t,
                                     [](const common::StampedPose& g, double t) { return g.t < t; });
    const common::StampedPose* best = nullptr;
    for (auto c : {it, it == gt.begin() ? it : std::prev(it)})
      if (c != gt.end() && std::abs(c->t - e.t) <= max_dt_s &&
          (!best || std::abs(c->t - e.t) < std::abs(best->t - e.t)))
        best = &*c;
    if (best) pairs.emplace_back(&e, best);
  }
  if (pairs.empty())
    throw std::runtime_error("trajectoryError: no estimate pose matches a ground-truth timestamp");

  const mrpt::poses::CPose3D T_world_map = pairs.front().second->pose - pairs.front().first->pose;
  TrajectoryError r;
  double sum2 = 0;
  for (const auto& [e, g] : pairs)
  {
    const mrpt::poses::CPose3D pe = T_world_map + e->pose;
    const double d = std::hypot(pe.x() - g->pose.x(), pe.y() - g->pose.y());
    const double dyaw = std::abs(mrpt::math::wrapToPi(pe.yaw() - g->pose.yaw()));
    sum2 += d * d;
    r.ate_max_m = std::max(r.ate_max_m, d);
    r.max_yaw_error_rad = std::max(r.max_yaw_error_rad, dyaw);
    r.final_xy_error_m = d;
    r.final_yaw_error_rad = dyaw;
  }
  r.matched = pairs.size();
  r.ate_rmse_m = std::sqrt(sum2 / double(pairs.size()));
  return r;
}

}  // namespace voxplore::eval
