/* voxplore — collision space generation (thesis 4.5.2) with exact Euclidean
 * distance transforms instead of stamping a disc around every cell. */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/core/format.h>
#include <voxplore/common/config.h>
#include <voxplore/common/distance_transform.h>
#include <voxplore/exploration/stages.h>

#include <cmath>
#include <limits>
#include <vector>


namespace voxplore::exploration
{
namespace
{
/// Squared distance (cells) to the nearest cell of G in state `source`.
std::vector<double> squaredDistanceTo(const GroundGrid& g, GroundState source)
{
  const int nx = static_cast<int>(g.state.getSizeX());
  const int ny = static_cast<int>(g.state.getSizeY());
  std::vector<double> sq(static_cast<std::size_t>(nx) * ny);
  const auto& cells = g.state.data();
  for (std::size_t i = 0; i < sq.size(); ++i) sq[i] = cells[i] == source ? 0.0 : common::kEdtFar;
  if (nx > 0 && ny > 0) common::squaredDistanceTransform(sq, nx, ny);
  return sq;
}

/// 1 for the Unknown cells that stand for unexplored space: not 4-adjacent
/// to an Occupied cell (with `beside`: an unseen wall base hides at most the
/// obstacle's next cell, which the sqrt(2) l_res of the radius covers), and
/// in a 4-connected unknown pocket that is thicker than `depth_cells` or
/// touches the grid border (thin pockets are wall interiors and the unseen
/// backs of furniture, bounded by known space on all sides).
std::vector<uint8_t> openUnknownMask(const GroundGrid& g, bool beside, double depth_cells)
{
  const int nx = static_cast<int>(g.state.getSizeX());
  const int ny = static_cast<int>(g.state.getSizeY());
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  const auto& cells = g.state.data();
  // Judged on the voxel columns' states: a low obstacle cell counts as what
  // they made of it (GroundGrid::low_was), so that stamping a table base
  // neither closes the unknown beside it nor splits a pocket; closed itself below.
  const bool has_low = g.low_was.size() == n;
  const auto was = [&](std::size_t i) { return has_low ? g.low_was[i] : uint8_t{0}; };
  const auto unknown = [&](std::size_t i)
  { return cells[i] == GroundState::Unknown || was(i) == 2; };
  std::vector<uint8_t> open(n, 0);
  for (std::size_t i = 0; i < n; ++i) open[i] = unknown(i) ? 1 : 0;
  if (beside)
  {
    const auto occ = [&](int x, int y)
    {
      if (x < 0 || y < 0 || x >= nx || y >= ny) return false;
      const std::size_t i = static_cast<std::size_t>(y) * nx + x;
      return cells[i] == GroundState::Occupied && was(i) == 0;
    };
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
      {
        const std::size_t i = static_cast<std::size_t>(y) * nx + x;
        if (open[i] && (occ(x + 1, y) || occ(x - 1, y) || occ(x, y + 1) || occ(x, y - 1)))
          open[i] = 0;
      }
  }
  const auto closeLow = [&]
  {
    if (has_low)
      for (std::size_t i = 0; i < n; ++i)
        if (g.low_was[i]) open[i] = 0;
  };
  if (depth_cells <= 0 || n == 0)
  {
    closeLow();
    return open;
  }
  // Depth of every unknown cell: distance to the nearest known cell.
  std::vector<double> sq(n);
  for (std::size_t i = 0; i < n; ++i) sq[i] = unknown(i) ? common::kEdtFar : 0.0;
  common::squaredDistanceTransform(sq, nx, ny);
  const double depth2 = depth_cells * depth_cells;
  std::vector<uint8_t> seen(n, 0);
  std::vector<int> stack, pocket;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (!unknown(seed) || seen[seed]) continue;
    bool thick = false;
    pocket.clear();
    stack.assign(1, static_cast<int>(seed));
    seen[seed] = 1;
    while (!stack.empty())
    {
      const int i = stack.back();
      stack.pop_back();
      pocket.push_back(i);
      const int x = i % nx, y = i / nx;
      if (x == 0 || y == 0 || x == nx - 1 || y == ny - 1 || sq[i] > depth2) thick = true;
      const int nb[4] = {x + 1 < nx ? i + 1 : -1, x > 0 ? i - 1 : -1, y + 1 < ny ? i + nx : -1,
                         y > 0 ? i - nx : -1};
      for (const int j : nb)
        if (j >= 0 && !seen[j] && unknown(static_cast<std::size_t>(j)))
        {
          seen[j] = 1;
          stack.push_back(j);
        }
    }
    if (!thick)
      for (const int i : pocket) open[i] = 0;
  }
  closeLow();
  return open;
}

/// Squared distance (cells) to the nearest cell with mask[i] != 0.
std::vector<double> squaredDistanceToMask(const GroundGrid& g, const std::vector<uint8_t>& mask)
{
  const int nx = static_cast<int>(g.state.getSizeX());
  const int ny = static_cast<int>(g.state.getSizeY());
  std::vector<double> sq(mask.size());
  for (std::size_t i = 0; i < sq.size(); ++i) sq[i] = mask[i] ? 0.0 : common::kEdtFar;
  if (nx > 0 && ny > 0) common::squaredDistanceTransform(sq, nx, ny);
  return sq;
}

/// Clearance grid in metres (+inf where the grid holds no source cell).
Grid<float> clearanceGrid(const Grid<GroundState>& like, const std::vector<double>& sq)
{
  Grid<float> out;
  const float zero = 0;
  const double res = like.getResolution();
  out.setSize(like.getXMin(), like.getXMax(), like.getYMin(), like.getYMax(), res, &zero);
  auto it = out.begin();
  for (std::size_t i = 0; i < sq.size(); ++i, ++it)
  {
    *it = sq[i] >= common::kEdtFar / 2 ? std::numeric_limits<float>::infinity()
                                       : static_cast<float>(std::sqrt(sq[i]) * res);
  }
  return out;
}
}  // namespace

const char* CollisionParams::toString(Model m)
{
  switch (m)
  {
    case Model::Circle:
      return "circle";
    case Model::Footprint:
      return "footprint";
    case Model::Auto:
      return "auto";
  }
  return "?";
}

double CollisionParams::plannerCircleDiameter(double l_res_m) const
{
  return 2.0 * (r_coll_m + std::sqrt(2.0) * l_res_m);
}

CollisionParams::Model CollisionParams::modelInForce(double l_res_m) const
{
  if (model != Model::Auto) return model;
  return plannerCircleDiameter(l_res_m) > auto_footprint_above_m ? Model::Footprint : Model::Circle;
}

double CollisionParams::marginInForce(double l_res_m) const
{
  if (footprint_margin_m != kAuto) return footprint_margin_m;
  return doorWithMargin(auto_margin_max_m, l_res_m) <= auto_door_m ? auto_margin_max_m
                                                                   : auto_margin_min_m;
}

double CollisionParams::squareShareInForce(double l_res_m) const
{
  if (footprint_square_share != kAuto) return footprint_square_share;
  return footprintTrimmed(l_res_m) ? 0.5 : 1.0;
}

double CollisionParams::lateralInForce(double l_res_m) const
{
  if (footprint_lateral_m != kAuto) return footprint_lateral_m;
  return footprintTrimmed(l_res_m) ? 0.5 * l_res_m : 0.0;
}

namespace
{
/// A number, or "auto" (CollisionParams::kAuto).
double readAutoOrNumber(const mrpt::config::CConfigFileBase& c, const std::string& s,
                        const std::string& key, double current)
{
  return common::readNumberOrWord(c, s, key, current, "auto", CollisionParams::kAuto);
}

std::string autoOrNumber(double v)
{
  return common::numberOrWord(v, "auto", CollisionParams::kAuto);
}
}  // namespace

void CollisionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(r_coll_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(ignore_unknown_beside_obstacles, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(min_open_unknown_depth_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacles_on_unknown, bool, c, s);
  common::requireValid(min_open_unknown_depth_m >= 0, c, s, "min_open_unknown_depth_m",
                       "must be >= 0");
  common::requireValid(r_coll_m >= 0, c, s, "r_coll_m", "must be >= 0");
  const std::string m = c.read_string(s, "model", toString(model));
  common::requireValid(m == "circle" || m == "footprint" || m == "auto", c, s, "model",
                       "expected auto, circle or footprint");
  model = m == "circle" ? Model::Circle : m == "footprint" ? Model::Footprint : Model::Auto;
  MRPT_LOAD_CONFIG_VAR(auto_footprint_above_m, double, c, s);
  common::requireValid(auto_footprint_above_m >= 0, c, s, "auto_footprint_above_m",
                       "must be >= 0");
  footprint_margin_m = readAutoOrNumber(c, s, "footprint_margin_m", footprint_margin_m);
  MRPT_LOAD_CONFIG_VAR(auto_margin_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(auto_margin_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_turn_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(yaw_bins, int, c, s);
  footprint_square_share = readAutoOrNumber(c, s, "footprint_square_share", footprint_square_share);
  common::requireValid(footprint_square_share == kAuto ||
                           (footprint_square_share >= 0 && footprint_square_share <= 1),
                       c, s, "footprint_square_share", "must be auto or in [0, 1]");
  MRPT_LOAD_CONFIG_VAR(footprint_turn_square_share, double, c, s);
  common::requireValid(footprint_turn_square_share >= 0 && footprint_turn_square_share <= 1, c, s,
                       "footprint_turn_square_share", "must be in [0, 1]");
  MRPT_LOAD_CONFIG_VAR(footprint_bin_span, double, c, s);
  footprint_lateral_m = readAutoOrNumber(c, s, "footprint_lateral_m", footprint_lateral_m);
  common::requireValid(
      footprint_lateral_m == kAuto || (footprint_lateral_m >= 0 && footprint_lateral_m <= 0.2), c,
      s, "footprint_lateral_m", "must be auto or in [0, 0.2]");
  MRPT_LOAD_CONFIG_VAR(auto_door_m, double, c, s);
  common::requireValid(auto_door_m > 0, c, s, "auto_door_m", "must be > 0");
  MRPT_LOAD_CONFIG_VAR(swept_passage, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(swept_passage_margin_m, double, c, s);
  common::requireValid(swept_passage_margin_m >= 0, c, s, "swept_passage_margin_m", "must be >= 0");
  common::requireValid(footprint_bin_span >= 0 && footprint_bin_span <= 1, c, s,
                       "footprint_bin_span", "must be in [0, 1]");
  common::requireValid(footprint_margin_m == kAuto || footprint_margin_m >= 0, c, s,
                       "footprint_margin_m", "must be auto or >= 0");
  common::requireValid(auto_margin_min_m >= 0, c, s, "auto_margin_min_m", "must be >= 0");
  common::requireValid(auto_margin_max_m >= auto_margin_min_m, c, s, "auto_margin_max_m",
                       "must be >= auto_margin_min_m");
  const double widest_margin = footprint_margin_m == kAuto ? auto_margin_max_m : footprint_margin_m;
  common::requireValid(footprint_turn_margin_m >= widest_margin, c, s, "footprint_turn_margin_m",
                       footprint_margin_m == kAuto ? "must be >= auto_margin_max_m"
                                                   : "must be >= footprint_margin_m");
  common::requireValid(yaw_bins >= 2 && yaw_bins <= 64, c, s, "yaw_bins", "must be in 2..64");
}

void CollisionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  // Full precision: r_coll follows the footprint's circumradius, and
  // voxplore-plan plans a run's step again from this file.
  c.write(s, "r_coll_m", mrpt::format("%.17g", r_coll_m));
  MRPT_SAVE_CONFIG_VAR(ignore_unknown_beside_obstacles, c, s);
  MRPT_SAVE_CONFIG_VAR(min_open_unknown_depth_m, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacles_on_unknown, c, s);
  c.write(s, "model", toString(model));
  MRPT_SAVE_CONFIG_VAR(auto_footprint_above_m, c, s);
  c.write(s, "footprint_margin_m", autoOrNumber(footprint_margin_m));
  MRPT_SAVE_CONFIG_VAR(auto_margin_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(auto_margin_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_turn_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(yaw_bins, c, s);
  c.write(s, "footprint_square_share", autoOrNumber(footprint_square_share));
  MRPT_SAVE_CONFIG_VAR(footprint_turn_square_share, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_bin_span, c, s);
  c.write(s, "footprint_lateral_m", autoOrNumber(footprint_lateral_m));
  MRPT_SAVE_CONFIG_VAR(auto_door_m, c, s);
  MRPT_SAVE_CONFIG_VAR(swept_passage, c, s);
  MRPT_SAVE_CONFIG_VAR(swept_passage_margin_m, c, s);
}

CollisionSpace computeCollisionSpace(const GroundGrid& g, const CollisionParams& p)
{
  ASSERTMSG_(p.r_coll_m >= 0, "computeCollisionSpace: r_coll_m must be >= 0");
  const double res = g.state.getResolution();
  CollisionSpace cs;
  cs.radius_m =
      p.r_coll_m + std::sqrt(2.0) * res;  // thesis 4.5.2: r_coll + sqrt(2) l_res (eq. 4.4)
  const std::vector<double> sq_occ = squaredDistanceTo(g, GroundState::Occupied);
  cs.open_unknown = openUnknownMask(g, p.ignore_unknown_beside_obstacles,
                                    p.min_open_unknown_depth_m / res);
  const std::vector<double> sq_unk = squaredDistanceToMask(g, cs.open_unknown);
  cs.clearance_occ_m = clearanceGrid(g.state, sq_occ);
  cs.clearance_unknown_m = clearanceGrid(g.state, sq_unk);

  // "within" the radius: squared cell distance * res^2 <= radius^2.
  const double r2_cells = (cs.radius_m / res) * (cs.radius_m / res);
  const SpaceState unknown = SpaceState::Unknown;
  cs.state.setSize(g.state.getXMin(), g.state.getXMax(), g.state.getYMin(), g.state.getYMax(), res,
                   &unknown);
  const auto& ground = g.state.data();
  auto out = cs.state.begin();
  for (std::size_t i = 0; i < ground.size(); ++i, ++out)
  {
    switch (ground[i])
    {
      case GroundState::Unknown:
        *out = SpaceState::Unknown;
        break;
      case GroundState::Occupied:
        *out = SpaceState::Occupied;
        break;
      case GroundState::Free:
        *out = sq_occ[i] <= r2_cells   ? SpaceState::Collision
               : sq_unk[i] <= r2_cells ? SpaceState::MaybeCollision
                                       : SpaceState::Free;
        break;
    }
  }
  return cs;
}

std::size_t openSweptPassages(CollisionSpace& cs, const SweptPath& swept, const CollisionParams& p)
{
  const int nx = static_cast<int>(cs.state.getSizeX()), ny = static_cast<int>(cs.state.getSizeY());
  const float min_clear = static_cast<float>(p.r_coll_m + p.swept_passage_margin_m);
  std::size_t opened = 0;
  for (const Eigen::Vector3d& q : swept)
  {
    Cell c;
    if (!cellOf(cs.state, Eigen::Vector2d(q.x(), q.y()), c)) continue;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
      {
        const int x = c.cx + dx, y = c.cy + dy;
        if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
        const std::size_t i = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
        SpaceState& st = *cs.state.cellByIndex(x, y);
        if (st != SpaceState::Collision && st != SpaceState::MaybeCollision) continue;
        if (cs.clearance_occ_m.data()[i] < min_clear) continue;
        st = SpaceState::Free;
        ++opened;
      }
  }
  return opened;
}

}  // namespace voxplore::exploration
