/* voxplore — frontier choice, sample space and pose samples (thesis 4.5.4). */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <voxplore/common/config.h>
#include <voxplore/common/distance_transform.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <vector>


namespace voxplore::exploration
{
namespace
{
/// Frontier cells tested for line of sight: all of them up to this many,
/// else an evenly spaced subset of this size (plus the last cell). A
/// candidate that sees none of the subset may still see a skipped cell; for
/// frontiers longer than kMaxSightTargets cells this errs on the side of
/// excluding a cell, never of including a blind one.
constexpr std::size_t kMaxSightTargets = 32;

/// Thesis fig. 4.15: 4-connected Bresenham walk from a to b (every cell the
/// segment between the centres crosses; at an exact corner crossing it steps
/// in y first). False when a cell after `a` is Occupied, or, with
/// `open_unknown` given, Unknown but not open unknown (a wall's unseen
/// interior or base: CollisionSpace::open_unknown).
bool lineOfSight(const Grid<GroundState>& g, const Cell& a, const Cell& b,
                 const std::vector<uint8_t>* open_unknown)
{
  const int nx = static_cast<int>(g.getSizeX());
  const GroundState* st = g.data().data();
  const int ddx = std::abs(b.cx - a.cx), ddy = std::abs(b.cy - a.cy);
  const int sx = b.cx > a.cx ? 1 : -1, sy = b.cy > a.cy ? 1 : -1;
  int x = a.cx, y = a.cy;
  for (int ix = 0, iy = 0; ix < ddx || iy < ddy;)
  {
    // Step along the axis whose next cell border the segment crosses first.
    if (static_cast<long>(1 + 2 * ix) * ddy < static_cast<long>(1 + 2 * iy) * ddx)
    {
      x += sx;
      ++ix;
    }
    else
    {
      y += sy;
      ++iy;
    }
    const GroundState v = st[x + y * nx];
    if (v == GroundState::Occupied) return false;
    if (open_unknown && v == GroundState::Unknown &&
        !(*open_unknown)[static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx])
      return false;
  }
  return true;
}

/// The frontier cells tested for line of sight (see kMaxSightTargets).
std::vector<Cell> sightTargets(const Frontier& f)
{
  if (f.cells.size() <= kMaxSightTargets) return f.cells;
  std::vector<Cell> out;
  const std::size_t step = (f.cells.size() + kMaxSightTargets - 1) / kMaxSightTargets;
  for (std::size_t i = 0; i < f.cells.size(); i += step) out.push_back(f.cells[i]);
  out.push_back(f.cells.back());
  return out;
}

/// Half-open window of cells [x0, x1) x [y0, y1).
struct Window
{
  int x0, y0, x1, y1;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

/// Bounding box of the frontier grown by `grow` cells, clipped to the grid.
Window frontierWindow(const Frontier& f, int grow, int nx, int ny)
{
  Window w{nx, ny, 0, 0};
  for (const Cell& c : f.cells)
  {
    w.x0 = std::min(w.x0, c.cx);
    w.y0 = std::min(w.y0, c.cy);
    w.x1 = std::max(w.x1, c.cx + 1);
    w.y1 = std::max(w.y1, c.cy + 1);
  }
  return {std::max(0, w.x0 - grow), std::max(0, w.y0 - grow), std::min(nx, w.x1 + grow),
          std::min(ny, w.y1 + grow)};
}

}  // namespace

bool nearAny(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& points, double r)
{
  return std::any_of(points.begin(), points.end(),
                     [&](const Eigen::Vector2d& q) { return (p - q).norm() < r; });
}

void SamplingParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                        const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(th_f1_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(th_f2_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(d_min_sample_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(d_max_sample_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_samples, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_sample_dist_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(blacklist_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(view_standoff_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(sight_blocked_by_unknown, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(standoff_sight_blocked_by_unknown, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(judge_opening, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(judge_opening_min_unknown_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(enclosed_unknown_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(travel_cost_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(frontiers_rated, int, c, s);
  MRPT_LOAD_CONFIG_VAR(rate_reached_yaw, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(unreached_frontiers, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(unreached_min_unknown_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(unreached_min_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(retire_looks, int, c, s);
  MRPT_LOAD_CONFIG_VAR(look_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(retire_pocket_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(look_spacing_m, double, c, s);
  using common::requireValid;
  requireValid(th_f2_m >= 0, c, s, "th_f2_m", "must be >= 0");
  requireValid(th_f1_m >= th_f2_m, c, s, "th_f1_m", "need th_f1_m >= th_f2_m");
  requireValid(d_min_sample_m >= 0, c, s, "d_min_sample_m", "must be >= 0");
  requireValid(d_max_sample_m > d_min_sample_m, c, s, "d_max_sample_m",
               "need d_max_sample_m > d_min_sample_m");
  requireValid(max_samples >= 1, c, s, "max_samples", "must be >= 1");
  requireValid(min_sample_dist_m >= 0, c, s, "min_sample_dist_m", "must be >= 0");
  requireValid(blacklist_radius_m >= 0, c, s, "blacklist_radius_m", "must be >= 0");
  requireValid(view_standoff_m >= 0, c, s, "view_standoff_m", "must be >= 0");
  requireValid(judge_opening_min_unknown_m2 >= 0, c, s, "judge_opening_min_unknown_m2", "must be >= 0");
  requireValid(enclosed_unknown_m2 >= 0, c, s, "enclosed_unknown_m2", "must be >= 0");
  requireValid(travel_cost_per_m >= 0, c, s, "travel_cost_per_m", "must be >= 0");
  requireValid(unreached_min_unknown_m2 >= 0, c, s, "unreached_min_unknown_m2", "must be >= 0");
  requireValid(unreached_min_depth_m >= 0, c, s, "unreached_min_depth_m", "must be >= 0");
  requireValid(frontiers_rated >= 1, c, s, "frontiers_rated", "must be >= 1");
  requireValid(retire_looks >= 0, c, s, "retire_looks", "must be >= 0");
  requireValid(look_range_m > 0, c, s, "look_range_m", "must be > 0");
  requireValid(retire_pocket_m2 >= 0, c, s, "retire_pocket_m2", "must be >= 0");
  requireValid(look_spacing_m >= 0, c, s, "look_spacing_m", "must be >= 0");
}

void SamplingParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(th_f1_m, c, s);
  MRPT_SAVE_CONFIG_VAR(th_f2_m, c, s);
  MRPT_SAVE_CONFIG_VAR(d_min_sample_m, c, s);
  MRPT_SAVE_CONFIG_VAR(d_max_sample_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_samples, c, s);
  MRPT_SAVE_CONFIG_VAR(min_sample_dist_m, c, s);
  MRPT_SAVE_CONFIG_VAR(blacklist_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(view_standoff_m, c, s);
  MRPT_SAVE_CONFIG_VAR(sight_blocked_by_unknown, c, s);
  MRPT_SAVE_CONFIG_VAR(standoff_sight_blocked_by_unknown, c, s);
  MRPT_SAVE_CONFIG_VAR(judge_opening, c, s);
  MRPT_SAVE_CONFIG_VAR(judge_opening_min_unknown_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(enclosed_unknown_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(travel_cost_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR(frontiers_rated, c, s);
  MRPT_SAVE_CONFIG_VAR(rate_reached_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(unreached_frontiers, c, s);
  MRPT_SAVE_CONFIG_VAR(unreached_min_unknown_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(unreached_min_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(retire_looks, c, s);
  MRPT_SAVE_CONFIG_VAR(look_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(retire_pocket_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(look_spacing_m, c, s);
}

std::optional<std::size_t> chooseFrontier(const std::vector<Frontier>& frontiers,
                                          const SamplingParams& p,
                                          const std::vector<Eigen::Vector2d>& blacklist,
                                          const std::vector<std::size_t>& skip,
                                          const std::vector<double>* rank,
                                          const std::vector<uint8_t>* first)
{
  auto key = [&](std::size_t i) { return rank ? (*rank)[i] : frontiers[i].distance_m; };
  // Tier 0 (`first` given): the preferred frontiers longer than th_f2; then
  // the thesis' tiers over all frontiers.
  for (int tier = first ? 0 : 1; tier < 3; ++tier)
  {
    const double th = tier == 1 ? p.th_f1_m : p.th_f2_m;
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < frontiers.size(); ++i)
    {
      const Frontier& f = frontiers[i];
      if (tier == 0 && !(*first)[i]) continue;
      if (p.judgedLength(f) <= th || p.enclosed(f) || std::find(skip.begin(), skip.end(), i) != skip.end())
        continue;
      if (nearAny(f.center, blacklist, p.blacklist_radius_m)) continue;
      if (!best || key(i) < key(*best)) best = i;
    }
    if (best) return best;
  }
  return std::nullopt;
}

std::vector<Cell> sampleSpace(const GroundGrid& g, const CollisionSpace& cs, const FrontierMap& fm,
                              const Frontier& f, const SamplingParams& p)
{
  std::vector<Cell> space;
  if (f.cells.empty()) return space;
  const double res = cs.state.getResolution();
  const int nx = static_cast<int>(cs.state.getSizeX());
  const int ny = static_cast<int>(cs.state.getSizeY());
  const Window w =
      frontierWindow(f, static_cast<int>(std::ceil(p.d_max_sample_m / res)) + 1, nx, ny);

  // Distance to the nearest frontier cell: EDT seeded with the frontier cells.
  std::vector<double> sq(static_cast<std::size_t>(w.width()) * w.height(), common::kEdtFar);
  for (const Cell& c : f.cells) sq[(c.cx - w.x0) + (c.cy - w.y0) * w.width()] = 0.0;
  common::squaredDistanceTransform(sq, w.width(), w.height());

  const double lo2 = (p.d_min_sample_m / res) * (p.d_min_sample_m / res);
  const double hi2 = (p.d_max_sample_m / res) * (p.d_max_sample_m / res);
  const std::vector<Cell> targets = sightTargets(f);
  const uint8_t* reachable = fm.reachable.data().data();
  const std::vector<uint8_t>* open_unknown = p.sight_blocked_by_unknown ? &cs.open_unknown : nullptr;
  for (int cy = w.y0; cy < w.y1; ++cy)
  {
    for (int cx = w.x0; cx < w.x1; ++cx)
    {
      const double d2 = sq[(cx - w.x0) + (cy - w.y0) * w.width()];
      if (d2 < lo2 || d2 > hi2 || !reachable[cx + cy * nx]) continue;
      const Cell c{cx, cy};
      const bool sees = std::any_of(targets.begin(), targets.end(), [&](const Cell& t) {
        return lineOfSight(g.state, c, t, open_unknown);
      });
      if (sees) space.push_back(c);
    }
  }
  return space;
}

std::optional<Eigen::Vector2d> standoffGoal(const GroundGrid& g, const CollisionSpace& cs,
                                            const FrontierMap& fm, const Frontier& f,
                                            const SamplingParams& p)
{
  SamplingParams ring = p;
  ring.d_min_sample_m = p.view_standoff_m;
  ring.d_max_sample_m = p.view_standoff_m + 1.0;
  ring.sight_blocked_by_unknown = p.sight_blocked_by_unknown || p.standoff_sight_blocked_by_unknown;
  std::optional<Eigen::Vector2d> goal;
  double best = std::numeric_limits<double>::infinity();
  for (const Cell& c : sampleSpace(g, cs, fm, f, ring))
  {
    const Eigen::Vector2d xy = cellCenter(cs.state, c);
    const double d = (xy - f.center).squaredNorm();
    if (d < best)
    {
      best = d;
      goal = xy;
    }
  }
  return goal;
}

std::vector<mrpt::poses::CPose2D> samplePoses(const Grid<SpaceState>& grid,
                                              const std::vector<Cell>& space, const Frontier& f,
                                              const SamplingParams& p, std::mt19937_64& rng)
{
  std::vector<mrpt::poses::CPose2D> out;
  std::vector<Eigen::Vector2d> taken;
  std::vector<std::size_t> pool(space.size());
  std::iota(pool.begin(), pool.end(), std::size_t{0});
  std::size_t remaining = pool.size();
  while (remaining > 0 && out.size() < static_cast<std::size_t>(std::max(0, p.max_samples)))
  {
    // Draw without replacement: pick one of the remaining, move the last into its slot.
    std::uniform_int_distribution<std::size_t> pick(0, remaining - 1);
    const std::size_t k = pick(rng);
    const Cell c = space[pool[k]];
    pool[k] = pool[--remaining];
    const Eigen::Vector2d xy = cellCenter(grid, c);
    if (nearAny(xy, taken, p.min_sample_dist_m)) continue;
    taken.push_back(xy);
    const Eigen::Vector2d to_f = f.center - xy;
    out.emplace_back(xy.x(), xy.y(), std::atan2(to_f.y(), to_f.x()));
  }
  return out;
}

}  // namespace voxplore::exploration
