/* voxplore — collision space generation (thesis 4.5.2) with exact Euclidean
 * distance transforms instead of stamping a disc around every cell. */
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
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

void CollisionParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                         const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(r_coll_m, double, c, s);
  common::requireValid(r_coll_m >= 0, c, s, "r_coll_m", "must be >= 0");
}

void CollisionParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(r_coll_m, c, s);
}

CollisionSpace computeCollisionSpace(const GroundGrid& g, const CollisionParams& p)
{
  ASSERTMSG_(p.r_coll_m >= 0, "computeCollisionSpace: r_coll_m must be >= 0");
  const double res = g.state.getResolution();
  CollisionSpace cs;
  cs.radius_m =
      p.r_coll_m + std::sqrt(2.0) * res;  // thesis 4.5.2: r_coll + sqrt(2) l_res (eq. 4.4)
  const std::vector<double> sq_occ = squaredDistanceTo(g, GroundState::Occupied);
  const std::vector<double> sq_unk = squaredDistanceTo(g, GroundState::Unknown);
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

}  // namespace voxplore::exploration
