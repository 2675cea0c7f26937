/* voxplore — ExplorationLoop: low obstacles seen on the way end a drive
 * ([explore] low_obstacle_replan). */
#include <voxplore/exploration/grid.h>
#include <voxplore/exploration/stages.h>
#include <voxplore/mission/ExplorationLoop.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace voxplore::mission
{
namespace
{
/// The key of the cell holding (x, y): LowObstacleGrid's cells are
/// floor(coordinate / res), its obstacles their centres.
std::uint64_t cellKey(const Eigen::Vector2d& p, double res)
{
  // Unsigned: a left shift of a negative index is undefined (UBSan).
  const auto ix = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(p.x() / res)));
  const auto iy = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(p.y() / res)));
  return (iy << 32) ^ (ix & 0xffffffffULL);
}

/// Distance from p to the segment a-b [m].
double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}
}  // namespace

void ExplorationLoop::setLowAtPlan(const std::vector<Eigen::Vector2d>& low)
{
  const double res = slam_.octomap().params().l_res_m;
  low_at_plan_.clear();
  low_at_plan_.reserve(low.size());
  for (const auto& c : low) low_at_plan_.push_back(cellKey(c, res));
  std::sort(low_at_plan_.begin(), low_at_plan_.end());
}

bool ExplorationLoop::lowObstacleAhead(const exploration::PlanResult& plan,
                                       std::size_t from) const
{
  const auto& wps = plan.waypoints;
  if (from >= wps.size()) return false;
  const double res = slam_.octomap().params().l_res_m;
  // The body may turn anywhere on the way (MRPT's navigator between narrow
  // waypoints): its circumcircle, the planner's margin, and the cell's own
  // half diagonal.
  const double reach = planner_.collision.r_coll_m + planner_.collision.marginInForce(res) +
                       res * std::sqrt(0.5);
  const mrpt::poses::CPose2D here = poseEstimate();
  const Eigen::Vector2d start(here.x(), here.y());
  exploration::Cell robot_cell{-1000000, -1000000};
  if (plan.ground) exploration::cellOf(plan.ground->state, start, robot_cell);
  for (const auto& c : slam_.octomap().lowObstacles())
  {
    if (std::binary_search(low_at_plan_.begin(), low_at_plan_.end(), cellKey(c, res))) continue;
    // Only cells the planner would stamp (its rule on the plan's G): a
    // wall's or a leg's base leaks into the cell in front, and counting
    // those ended omniRob drives 111-186 times a run (b5 / b6, coverage
    // -0.04 to -0.08).
    exploration::Cell cell;
    if (plan.ground && !(exploration::cellOf(plan.ground->state, c, cell) &&
                         exploration::lowObstacleStamps(*plan.ground, cell, robot_cell,
                                                        planner_.collision.low_obstacles_on_unknown)))
      continue;
    Eigen::Vector2d a = start;
    for (std::size_t k = from; k < wps.size(); k++)
    {
      if (segmentDistance(c, a, wps[k]) < reach) return true;
      a = wps[k];
    }
  }
  return false;
}

}  // namespace voxplore::mission
