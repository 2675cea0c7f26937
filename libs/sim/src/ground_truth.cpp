/* voxplore — ground truth of a world: occupied voxels and reachable free floor. */

#include <mrpt/core/exceptions.h>
#include <voxplore/common/distance_transform.h>
#include <voxplore/sim/ground_truth.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace voxplore::sim
{
namespace
{
using Vec3 = Eigen::Vector3d;

/// Exact triangle / axis-aligned cube overlap (Akenine-Möller 2001, "Fast 3D
/// triangle-box overlap testing"): the 13 separating axes are the 9 edge x
/// box-axis cross products, the 3 box axes (covered by the voxel range the
/// caller loops over, so not repeated here) and the triangle normal. Per
/// triangle quantities are computed once. Touching counts as overlap.
class TriangleBoxTester
{
 public:
  TriangleBoxTester(const Vec3& a, const Vec3& b, const Vec3& c) : v_{a, b, c}
  {
    const std::array<Vec3, 3> edges{b - a, c - b, a - c};
    normal_ = edges[0].cross(edges[1]);
    for (int e = 0; e < 3; ++e)
    {
      for (int k = 0; k < 3; ++k)
      {
        const Vec3 axis = edges[e].cross(Vec3::Unit(k));
        axes_[3 * e + k] = axis;
        radius_[3 * e + k] = axis.cwiseAbs().sum();
      }
    }
    normal_radius_ = normal_.cwiseAbs().sum();
  }

  /// @brief True when the closed cube of half size `h` centred at `c` touches the triangle.
  bool overlaps(const Vec3& c, double h) const
  {
    const std::array<Vec3, 3> v{v_[0] - c, v_[1] - c, v_[2] - c};
    if (std::abs(normal_.dot(v[0])) > h * normal_radius_) return false;
    for (int i = 0; i < 9; ++i)
    {
      const double p0 = axes_[i].dot(v[0]), p1 = axes_[i].dot(v[1]), p2 = axes_[i].dot(v[2]);
      const double r = h * radius_[i];
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
    return true;
  }

  /// @brief z range of the triangle's plane over the column [x0,x1] x [y0,y1];
  ///        false when the plane is vertical or the triangle degenerate (no useful bound).
  bool planeZRange(double x0, double x1, double y0, double y1, double& z_lo, double& z_hi) const
  {
    if (!(std::abs(normal_.z()) > 1e-6 * normal_.norm())) return false;
    const double d = normal_.dot(v_[0]);
    z_lo = std::numeric_limits<double>::infinity();
    z_hi = -z_lo;
    for (const double x : {x0, x1})
    {
      for (const double y : {y0, y1})
      {
        const double z = (d - normal_.x() * x - normal_.y() * y) / normal_.z();
        z_lo = std::min(z_lo, z);
        z_hi = std::max(z_hi, z);
      }
    }
    return true;
  }

 private:
  std::array<Vec3, 3> v_;
  Vec3 normal_;
  double normal_radius_ = 0;
  std::array<Vec3, 9> axes_;
  std::array<double, 9> radius_{};
};

int voxelOf(double x, double res)
{
  return static_cast<int>(std::floor(x / res));
}

/// Appends the voxels of one triangle, iz limited to [iz_min, iz_max].
/// Voxels are closed boxes (touching counts) tested with a relative
/// tolerance of 1e-9: a face lying on a grid plane (x = 4.0 at 5 cm, where
/// 4.0 / 0.05 rounds to 79.999...) marks the voxels on both sides of it
/// instead of, by rounding, neither.
void rasterizeTriangle(const Vec3& a, const Vec3& b, const Vec3& c, double res, int iz_min,
                       int iz_max, std::vector<VoxelIndex>& out)
{
  const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
  const int z0 = std::max(voxelOf(lo.z(), res) - 1, iz_min);
  const int z1 = std::min(voxelOf(hi.z(), res) + 1, iz_max);
  if (z0 > z1) return;
  const TriangleBoxTester tester(a, b, c);
  const double h = 0.5 * res * (1.0 + 1e-9);
  for (int ix = voxelOf(lo.x(), res) - 1, x1 = voxelOf(hi.x(), res) + 1; ix <= x1; ++ix)
  {
    for (int iy = voxelOf(lo.y(), res) - 1, y1 = voxelOf(hi.y(), res) + 1; iy <= y1; ++iy)
    {
      int zc0 = z0, zc1 = z1;
      double z_lo = 0, z_hi = 0;
      if (tester.planeZRange(ix * res, (ix + 1) * res, iy * res, (iy + 1) * res, z_lo, z_hi))
      {  // only voxels the plane crosses in this column (one voxel of slack)
        zc0 = std::max(zc0, voxelOf(z_lo, res) - 1);
        zc1 = std::min(zc1, voxelOf(z_hi, res) + 1);
      }
      for (int iz = zc0; iz <= zc1; ++iz)
      {
        const Vec3 centre((ix + 0.5) * res, (iy + 0.5) * res, (iz + 0.5) * res);
        // Box-normal axes of the SAT: the voxel must overlap the triangle's bounds.
        const bool in_bounds = ((centre.array() + h) >= lo.array()).all() &&
                               ((centre.array() - h) <= hi.array()).all();
        if (in_bounds && tester.overlaps(centre, h)) out.emplace_back(ix, iy, iz);
      }
    }
  }
}

/// The grid over the mesh bounds plus one cell on every side (around the
/// start alone when the mesh is empty).
FloorGrid makeFloorGrid(const World& world, const mrpt::poses::CPose2D& start, double res)
{
  Eigen::Vector2d lo(start.x(), start.y()), hi = lo;
  if (!world.mesh.empty())
  {
    const Eigen::AlignedBox3f b = world.mesh.bounds();
    lo = b.min().head<2>().cast<double>();
    hi = b.max().head<2>().cast<double>();
  }
  FloorGrid g;
  g.res_m = res;
  g.origin = lo - Eigen::Vector2d(res, res);
  g.nx = static_cast<int>(std::floor((hi.x() - lo.x()) / res)) + 3;
  g.ny = static_cast<int>(std::floor((hi.y() - lo.y()) / res)) + 3;
  g.cells.assign(static_cast<std::size_t>(g.nx) * g.ny, 0);
  return g;
}

/// Marks every cell whose square overlaps an obstacle polygon of the checker.
void markObstacles(const CollisionChecker& checker, FloorGrid& g)
{
  const double res = g.res_m;
  const auto index = [&](double v, double o, int n)
  { return std::clamp(static_cast<int>(std::floor((v - o) / res)), 0, n - 1); };
  ConvexPolygon2D square;
  square.vertices.resize(4);
  for (const ConvexPolygon2D& p : checker.obstacles())
  {
    for (int iy = index(p.min.y(), g.origin.y(), g.ny); iy <= index(p.max.y(), g.origin.y(), g.ny);
         ++iy)
    {
      for (int ix = index(p.min.x(), g.origin.x(), g.nx);
           ix <= index(p.max.x(), g.origin.x(), g.nx); ++ix)
      {
        if (g.at(ix, iy)) continue;
        const Eigen::Vector2d c0 = g.origin + res * Eigen::Vector2d(ix, iy);
        const Eigen::Vector2d c1 = c0 + Eigen::Vector2d(res, res);
        square.vertices = {c0, {c1.x(), c0.y()}, c1, {c0.x(), c1.y()}};
        square.min = c0;
        square.max = c1;
        if (convexPolygonsOverlap(square, p)) g.at(ix, iy) = 1;
      }
    }
  }
}

/// 8-connected flood fill over `passable` cells from (sx, sy) into `out`.
template <typename Pred>
void floodFill8(int sx, int sy, Pred passable, FloorGrid& out)
{
  std::vector<std::pair<int, int>> stack{{sx, sy}};
  out.at(sx, sy) = 1;
  while (!stack.empty())
  {
    const auto [x, y] = stack.back();
    stack.pop_back();
    for (int dy = -1; dy <= 1; ++dy)
    {
      for (int dx = -1; dx <= 1; ++dx)
      {
        const int nx = x + dx, ny = y + dy;
        if (!out.inside(nx, ny) || out.at(nx, ny) || !passable(nx, ny)) continue;
        out.at(nx, ny) = 1;
        stack.emplace_back(nx, ny);
      }
    }
  }
}


/// Sorts (x, then y, then z) and removes duplicates. Packs the indices into
/// 64-bit keys (21 bits per axis) when the extent allows: about 3x faster.
void sortUnique(std::vector<VoxelIndex>& v)
{
  if (v.empty()) return;
  Eigen::Vector3i lo = v.front(), hi = v.front();
  for (const VoxelIndex& i : v)
  {
    lo = lo.cwiseMin(i);
    hi = hi.cwiseMax(i);
  }
  constexpr int kBits = 21;
  if ((hi.cast<int64_t>() - lo.cast<int64_t>()).maxCoeff() >= (int64_t{1} << kBits))
  {
    const auto less = [](const VoxelIndex& a, const VoxelIndex& b)
    { return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3); };
    std::sort(v.begin(), v.end(), less);
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return;
  }
  std::vector<uint64_t> keys(v.size());
  for (std::size_t k = 0; k < v.size(); ++k)
  {
    const Eigen::Matrix<uint64_t, 3, 1> d = (v[k] - lo).cast<uint64_t>();
    keys[k] = (d.x() << (2 * kBits)) | (d.y() << kBits) | d.z();
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;
  v.resize(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k)
  {
    v[k] = lo + Eigen::Vector3i(static_cast<int>(keys[k] >> (2 * kBits)),
                                static_cast<int>((keys[k] >> kBits) & kMask),
                                static_cast<int>(keys[k] & kMask));
  }
}

}  // namespace

std::vector<VoxelIndex> occupiedVoxels(const TriangleMesh& mesh, double res_m, double z_min_m,
                                       double z_max_m)
{
  ASSERTMSG_(res_m > 0, mrpt::format("occupiedVoxels: resolution must be > 0, got %g", res_m));
  // Clamp the z limits so that the voxel indices stay within int range.
  const double z_limit = 1e9 * res_m;
  const int iz_min = voxelOf(std::clamp(z_min_m, -z_limit, z_limit), res_m);
  const int iz_max = voxelOf(std::clamp(z_max_m, -z_limit, z_limit), res_m);
  std::vector<VoxelIndex> out;
  for (const Eigen::Vector3i& t : mesh.triangles)
  {
    rasterizeTriangle(mesh.vertices[t[0]].cast<double>(), mesh.vertices[t[1]].cast<double>(),
                      mesh.vertices[t[2]].cast<double>(), res_m, iz_min, iz_max, out);
  }
  sortUnique(out);
  return out;
}

FloorGrid FloorGrid::emptyLike() const
{
  FloorGrid out = *this;
  std::fill(out.cells.begin(), out.cells.end(), uint8_t{0});
  return out;
}

double FloorGrid::areaM2() const
{
  return static_cast<double>(std::count(cells.begin(), cells.end(), uint8_t{1})) * res_m * res_m;
}

std::vector<double> FloorGrid::squaredCellDistance(bool to_nonzero) const
{
  std::vector<double> d(cells.size());
  for (std::size_t i = 0; i < d.size(); ++i)
    d[i] = (cells[i] != 0) == to_nonzero ? 0.0 : common::kEdtFar;
  if (nx > 0 && ny > 0) common::squaredDistanceTransform(d, nx, ny);
  return d;
}

FloorGrid obstacleFloorGrid(const World& world, const CollisionChecker& checker,
                            const mrpt::poses::CPose2D& start, double res_m,
                            const Eigen::AlignedBox2d* region)
{
  ASSERTMSG_(res_m > 0, mrpt::format("obstacleFloorGrid: resolution must be > 0, got %g", res_m));
  FloorGrid g = makeFloorGrid(world, start, res_m);
  markObstacles(checker, g);
  if (region)
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix)
        if (!region->contains(g.center(ix, iy))) g.at(ix, iy) = 1;
  return g;
}

ReachableFloor reachableFreeFloor(const World& world, const CollisionChecker& checker,
                                  const mrpt::poses::CPose2D& start, double robot_radius_m,
                                  double res_m, const Eigen::AlignedBox2d* region)
{
  ASSERTMSG_(res_m > 0, mrpt::format("reachableFreeFloor: resolution must be > 0, got %g", res_m));
  ASSERTMSG_(robot_radius_m >= 0,
             mrpt::format("reachableFreeFloor: robot radius must be >= 0, got %g", robot_radius_m));
  ReachableFloor r;
  r.obstacle = obstacleFloorGrid(world, checker, start, res_m, region);
  r.reachable = r.obstacle.emptyLike();
  r.free_floor = r.obstacle.emptyLike();
  const FloorGrid& obs = r.obstacle;
  const int nx = obs.nx;

  // Centres farther than the radius from every obstacle cell centre. Ties
  // within rounding (r / res = 5.999...) count as "at the radius": not clear
  // of obstacles, but within reach for the free floor.
  const double radius_cells2 = std::pow(robot_radius_m / res_m, 2) * (1 + 1e-9);
  const std::vector<double> d_obs = obs.squaredCellDistance();
  const auto clear = [&](int x, int y)
  { return d_obs[static_cast<std::size_t>(y) * nx + x] > radius_cells2; };

  const double fx = std::floor((start.x() - obs.origin.x()) / res_m);
  const double fy = std::floor((start.y() - obs.origin.y()) / res_m);
  if (!(fx >= 0 && fy >= 0 && fx < obs.nx && fy < obs.ny)) return r;  // start outside: empty
  const int sx = static_cast<int>(fx), sy = static_cast<int>(fy);
  if (!clear(sx, sy)) return r;  // start too close to an obstacle: empty result
  floodFill8(sx, sy, clear, r.reachable);

  // Free floor: non-obstacle cells within the radius of a reachable centre.
  const FloorGrid& reach = r.reachable;
  const std::vector<double> d_reach = reach.squaredCellDistance();
  for (std::size_t i = 0; i < d_reach.size(); ++i)
    r.free_floor.cells[i] = (obs.cells[i] == 0 && d_reach[i] <= radius_cells2) ? 1 : 0;

  r.reachable_area_m2 = r.reachable.areaM2();
  r.free_floor_area_m2 = r.free_floor.areaM2();
  return r;
}

Eigen::AlignedBox2d obstacleBounds(const CollisionChecker& checker)
{
  Eigen::AlignedBox2d b;  // empty
  for (const ConvexPolygon2D& p : checker.obstacles())
  {
    b.extend(Eigen::Vector2d(p.min.x(), p.min.y()));
    b.extend(Eigen::Vector2d(p.max.x(), p.max.y()));
  }
  return b;
}

}  // namespace voxplore::sim
