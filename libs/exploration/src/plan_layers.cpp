/* voxplore — the planner's first stages on their own (thesis 4.5.1-4.5.3):
 * G, the collision (and footprint) space and the frontiers, for checking
 * what is left while the robot drives, and the seen gate's count of a plan's
 * frontier cells. Split from Planner.cpp. */
#include <mrpt/system/CTicTac.h>
#include <octomap/OcTree.h>
#include <voxplore/exploration/Planner.h>

#include <memory>
#include <utility>

namespace voxplore::exploration
{
using mrpt::poses::CPose2D;

PlanResult planLayers(const octomap::OcTree& V, const CPose2D& robot, const PlannerParams& p,
                      const SweptPath& swept, const std::vector<Eigen::Vector2d>& sensed_obstacles,
                      const std::vector<Eigen::Vector2d>& low_obstacles,
                      ProjectionCache* projection_cache, FrontierLooks* looks)
{
  mrpt::system::CTicTac tic;
  GroundGrid g =
      projectToGround(V, robot, p.projectionInForce(V.getResolution()), swept, projection_cache);
  const double t_projection_ms = 1e3 * tic.Tac();
  PlanResult r = planLayersOn(std::move(g), robot, p, swept, sensed_obstacles, low_obstacles, looks);
  r.ms.projection += t_projection_ms;
  return r;
}

PlanResult planLayersOn(GroundGrid g, const CPose2D& robot, const PlannerParams& p,
                        const SweptPath& swept, const std::vector<Eigen::Vector2d>& sensed_obstacles,
                        const std::vector<Eigen::Vector2d>& low_obstacles, FrontierLooks* looks)
{
  PlanResult r;
  mrpt::system::CTicTac tic;
  const double res = g.state.getResolution();
  auto ground = std::make_shared<GroundGrid>(std::move(g));
  stampObstacles(*ground, sensed_obstacles, low_obstacles, p.collision.low_obstacles_on_unknown);
  r.ms.projection = 1e3 * tic.Tac();
  tic.Tic();
  auto space = std::make_shared<CollisionSpace>(computeCollisionSpace(*ground, p.collision));
  if (p.collision.usesFootprint(ground->state.getResolution()))
  {
    // Its layers go back to computeFootprintSpace's spares when the last
    // holder of this plan lets go (the step after next reuses them).
    std::shared_ptr<FootprintSpace> fs(
        new FootprintSpace(computeFootprintSpace(*ground, *space, p.collision, robot, swept)),
        [](FootprintSpace* f)
        {
          recycleFootprintSpace(std::move(*f));
          delete f;
        });
    applyFootprint(*space, *fs);
    r.footprint = fs;
  }
  else if (p.collision.swept_passage)
    openSweptPassages(*space, swept, p.collision);
  r.ms.collision = 1e3 * tic.Tac();
  tic.Tic();
  if (looks)
    r.retired = retireLooked(*looks, *ground, *space, p.projectionInForce(res),
                             p.rating, p.sampling, r.retired_m2);
  UnreachedFrontiers unreached;
  if (p.sampling.unreached_frontiers)
    unreached = {p.sampling.d_max_sample_m, p.sampling.unreached_min_depth_m,
                 p.sampling.unreached_min_unknown_m2};
  auto fm = std::make_shared<FrontierMap>(findFrontiers(*ground, *space, &r.retired, unreached));
  r.ms.frontiers = 1e3 * tic.Tac();
  r.ground = ground;
  r.space = space;
  r.frontiers = fm;
  return r;
}

std::size_t frontierCellsLeft(const Frontier& frontier, const GroundGrid& planned_on,
                              const GroundGrid& now, bool ignore_beside_obstacles)
{
  const auto& g = now.state;
  const auto at = [&](int x, int y, GroundState st)
  { return inGrid(g, x, y) && *g.cellByIndex(x, y) == st; };
  const auto openUnknownAt = [&](int x, int y)
  {
    if (!inGrid(g, x, y)) return true;
    if (*g.cellByIndex(x, y) != GroundState::Unknown) return false;
    return !ignore_beside_obstacles ||
           !(at(x + 1, y, GroundState::Occupied) || at(x - 1, y, GroundState::Occupied) ||
             at(x, y + 1, GroundState::Occupied) || at(x, y - 1, GroundState::Occupied));
  };
  std::size_t left = 0;
  for (const Cell& c : frontier.cells)
  {
    Cell k;
    if (!cellOf(g, cellCenter(planned_on.state, c), k) || openUnknownAt(k.cx + 1, k.cy) ||
        openUnknownAt(k.cx - 1, k.cy) || openUnknownAt(k.cx, k.cy + 1) ||
        openUnknownAt(k.cx, k.cy - 1))
      left++;
  }
  return left;
}

}  // namespace voxplore::exploration
