/* voxplore — ExplorationLoop: low obstacles seen on the way end a drive
 * ([explore] low_obstacle_replan). */
#include <voxplore/exploration/grid.h>
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
std::int64_t cellKey(const Eigen::Vector2d& p, double res)
{
  const auto ix = static_cast<std::int64_t>(std::floor(p.x() / res));
  const auto iy = static_cast<std::int64_t>(std::floor(p.y() / res));
  return (iy << 32) ^ (ix & 0xffffffffLL);
}

/// Whether the planner would stamp the low obstacle cell at q Occupied, by
/// exploration::stampObstacles' rule on G as the plan had it: a cell G
/// held Free (or Unknown, with low_on_unknown) none of whose 8 neighbours
/// the voxel columns made Occupied (a wall's or a leg's base leaking into
/// the cell in front: the stamps skip them, and so do the interruptions,
/// or they ended a drive every few stops: omniRob b5 / b6, 111-186 a run,
/// coverage -0.04 to -0.08) nor is the robot's cell.
bool plannerStamps(const exploration::GroundGrid& g, const Eigen::Vector2d& q,
                   const exploration::Cell& robot, bool low_on_unknown)
{
  using exploration::GroundState;
  exploration::Cell c;
  if (!exploration::cellOf(g.state, q, c)) return false;
  const std::size_t nx = g.state.getSizeX();
  const auto lowStamp = [&](int x, int y)
  { return !g.low_was.empty() && g.low_was[static_cast<std::size_t>(y) * nx + x] != 0; };
  GroundState was = *g.state.cellByIndex(c.cx, c.cy);
  if (lowStamp(c.cx, c.cy)) return false;  // stamped already: the plan kept off it
  if (was != GroundState::Free && !(was == GroundState::Unknown && low_on_unknown)) return false;
  for (int dy = -1; dy <= 1; dy++)
    for (int dx = -1; dx <= 1; dx++)
    {
      const int x = c.cx + dx, y = c.cy + dy;
      if (x == robot.cx && y == robot.cy) return false;
      if (exploration::inGrid(g.state, x, y) &&
          *g.state.cellByIndex(x, y) == GroundState::Occupied && !lowStamp(x, y))
        return false;
    }
  return true;
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
  const double reach = planner_.collision.r_coll_m + planner_.collision.footprint_margin_m +
                       res * std::sqrt(0.5);
  const mrpt::poses::CPose2D here = poseEstimate();
  const Eigen::Vector2d start(here.x(), here.y());
  exploration::Cell robot_cell{-1000000, -1000000};
  if (plan.ground) exploration::cellOf(plan.ground->state, start, robot_cell);
  for (const auto& c : slam_.octomap().lowObstacles())
  {
    if (std::binary_search(low_at_plan_.begin(), low_at_plan_.end(), cellKey(c, res))) continue;
    if (plan.ground && !plannerStamps(*plan.ground, c, robot_cell,
                                      planner_.collision.low_obstacles_on_unknown))
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
