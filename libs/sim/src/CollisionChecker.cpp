/* voxplore — footprint-vs-world collision checks for the simulated robot.
 *
 * Every world triangle is clipped to the slab z in [z_low, z_high]
 * (Sutherland–Hodgman against the two planes), projected to the floor, and
 * its convex hull kept as a ConvexPolygon2D (a vertical wall becomes a
 * segment). Queries are separating-axis tests against the polygons of the
 * uniform-grid buckets the query's bounds overlap. */

#include <mrpt/core/exceptions.h>
#include <voxplore/sim/CollisionChecker.h>

#include <algorithm>
#include <cmath>

namespace voxplore::sim
{
namespace
{
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

/// Above this many buckets the grid cell is doubled (huge, sparse worlds).
constexpr std::size_t kMaxBuckets = 4'000'000;

/// Sutherland–Hodgman: keeps the part of the polygon with z >= z0
/// (`keep_above`) or z <= z0. Crossing points are put exactly on the plane.
std::vector<Vec3> clipAgainstZ(const std::vector<Vec3>& poly, double z0, bool keep_above)
{
  std::vector<Vec3> out;
  out.reserve(poly.size() + 1);
  const auto inside = [&](const Vec3& p) { return keep_above ? p.z() >= z0 : p.z() <= z0; };
  for (std::size_t i = 0; i < poly.size(); ++i)
  {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % poly.size()];
    const bool a_in = inside(a);
    if (a_in) out.push_back(a);
    if (a_in != inside(b))
    {
      const double t = (z0 - a.z()) / (b.z() - a.z());
      Vec3 p = a + t * (b - a);
      p.z() = z0;
      out.push_back(p);
    }
  }
  return out;
}

double cross(const Vec2& o, const Vec2& a, const Vec2& b)
{
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

/// Andrew's monotone chain; collinear and repeated points removed, so the
/// result has 1 (point), 2 (segment) or >= 3 (counter-clockwise) vertices.
std::vector<Vec2> convexHull(std::vector<Vec2> pts)
{
  const auto less = [](const Vec2& a, const Vec2& b)
  { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); };
  std::sort(pts.begin(), pts.end(), less);
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() <= 2) return pts;
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)  // lower hull
  {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;)  // upper hull
  {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

ConvexPolygon2D makePolygon(std::vector<Vec2> vertices)
{
  ConvexPolygon2D poly;
  poly.vertices = std::move(vertices);
  if (poly.vertices.empty()) return poly;
  poly.min = poly.max = poly.vertices.front();
  for (const Vec2& v : poly.vertices)
  {
    poly.min = poly.min.cwiseMin(v);
    poly.max = poly.max.cwiseMax(v);
  }
  return poly;
}

/// The part of triangle abc inside the slab, projected to XY; empty when the
/// triangle lies entirely at or below z_low or entirely above z_high.
std::vector<Vec2> slabFootprint(const Vec3& a, const Vec3& b, const Vec3& c, double z_low,
                                double z_high)
{
  const double z_min = std::min({a.z(), b.z(), c.z()});
  const double z_max = std::max({a.z(), b.z(), c.z()});
  if (z_max <= z_low || z_min > z_high) return {};
  std::vector<Vec3> poly{a, b, c};
  if (z_min < z_low) poly = clipAgainstZ(poly, z_low, true);
  if (z_max > z_high) poly = clipAgainstZ(poly, z_high, false);
  std::vector<Vec2> xy;
  xy.reserve(poly.size());
  for (const Vec3& p : poly) xy.emplace_back(p.x(), p.y());
  return convexHull(std::move(xy));
}

struct Interval
{
  double lo, hi;
};

Interval project(const std::vector<Vec2>& vertices, const Vec2& axis)
{
  Interval r{vertices.front().dot(axis), vertices.front().dot(axis)};
  for (const Vec2& v : vertices)
  {
    const double d = v.dot(axis);
    r.lo = std::min(r.lo, d);
    r.hi = std::max(r.hi, d);
  }
  return r;
}

/// True when `axis` separates a and b strictly (touching is not separated).
bool separatedOn(const ConvexPolygon2D& a, const ConvexPolygon2D& b, const Vec2& axis)
{
  if (axis.x() == 0 && axis.y() == 0) return false;
  const Interval ia = project(a.vertices, axis);
  const Interval ib = project(b.vertices, axis);
  return ia.hi < ib.lo || ib.hi < ia.lo;
}

/// True when an edge normal of `p` (and, for a segment or a flat polygon, an
/// edge direction too) separates a and b. Together with the coordinate axes
/// tested first, the normals of both polygons are a complete set of axes; the
/// direction of a segment only matters for collinear segments, which the
/// coordinate axes already separate, and is kept as a cheap safeguard.
bool edgeAxisSeparates(const ConvexPolygon2D& p, const ConvexPolygon2D& a, const ConvexPolygon2D& b)
{
  const auto& v = p.vertices;
  const std::size_t n = v.size();
  if (n < 2) return false;
  double twice_area = 0;
  for (std::size_t i = 0; i < n; ++i) twice_area += cross(Vec2::Zero(), v[i], v[(i + 1) % n]);
  const bool flat = twice_area == 0;  // a segment, or collinear vertices
  const std::size_t edges = n == 2 ? 1 : n;
  for (std::size_t i = 0; i < edges; ++i)
  {
    const Vec2 e = v[(i + 1) % n] - v[i];
    if (separatedOn(a, b, Vec2(-e.y(), e.x()))) return true;
    if (flat && separatedOn(a, b, e)) return true;
  }
  return false;
}

/// Index of the grid cell holding coordinate `x`, clamped to [0, n).
int cellIndex(double x, double origin, double cell, int n)
{
  const double f = std::floor((x - origin) / cell);
  if (!(f > 0)) return 0;  // also catches NaN
  return f >= n - 1 ? n - 1 : static_cast<int>(f);
}

/// Every triangle's part inside the slab, projected to XY, as a convex polygon.
std::vector<ConvexPolygon2D> slabPolygons(const TriangleMesh& mesh, double z_low, double z_high)
{
  std::vector<ConvexPolygon2D> out;
  out.reserve(mesh.numTriangles() / 2);
  for (const Eigen::Vector3i& tri : mesh.triangles)
  {
    auto xy =
        slabFootprint(mesh.vertices[tri[0]].cast<double>(), mesh.vertices[tri[1]].cast<double>(),
                      mesh.vertices[tri[2]].cast<double>(), z_low, z_high);
    if (!xy.empty()) out.push_back(makePolygon(std::move(xy)));
  }
  return out;
}

/// A uniform grid over the polygons' bounds; each cell lists the polygons
/// whose bounds overlap it.
struct BucketGrid
{
  double cell = 0.5;
  Vec2 min{0, 0};
  int nx = 0, ny = 0;
  std::vector<std::vector<int>> buckets;
};

BucketGrid bucketPolygons(const std::vector<ConvexPolygon2D>& polys, double cell)
{
  BucketGrid g;
  g.cell = cell;
  if (polys.empty()) return g;
  Vec2 lo = polys.front().min, hi = polys.front().max;
  for (const auto& p : polys)
  {
    lo = lo.cwiseMin(p.min);
    hi = hi.cwiseMax(p.max);
  }
  const auto cellsAlong = [&](double extent) { return static_cast<int>(extent / g.cell) + 1; };
  while (double(cellsAlong(hi.x() - lo.x())) * cellsAlong(hi.y() - lo.y()) > double(kMaxBuckets))
    g.cell *= 2;
  g.min = lo;
  g.nx = cellsAlong(hi.x() - lo.x());
  g.ny = cellsAlong(hi.y() - lo.y());
  g.buckets.assign(static_cast<std::size_t>(g.nx) * g.ny, {});
  for (std::size_t i = 0; i < polys.size(); ++i)
  {
    const int x0 = cellIndex(polys[i].min.x(), lo.x(), g.cell, g.nx);
    const int x1 = cellIndex(polys[i].max.x(), lo.x(), g.cell, g.nx);
    const int y0 = cellIndex(polys[i].min.y(), lo.y(), g.cell, g.ny);
    const int y1 = cellIndex(polys[i].max.y(), lo.y(), g.cell, g.ny);
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix)
        g.buckets[static_cast<std::size_t>(iy) * g.nx + ix].push_back(static_cast<int>(i));
  }
  return g;
}

}  // namespace

bool convexPolygonsOverlap(const ConvexPolygon2D& a, const ConvexPolygon2D& b)
{
  if (a.vertices.empty() || b.vertices.empty()) return false;
  // The coordinate axes make point-vs-point exact and reject most pairs early.
  if (separatedOn(a, b, Vec2::UnitX()) || separatedOn(a, b, Vec2::UnitY())) return false;
  return !edgeAxisSeparates(a, a, b) && !edgeAxisSeparates(b, a, b);
}

ConvexPolygon2D Footprint::at(const mrpt::poses::CPose2D& pose) const
{
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  const double hl = 0.5 * length_m, hw = 0.5 * width_m;
  const Vec2 t(pose.x(), pose.y());
  std::vector<Vec2> corners;
  corners.reserve(4);
  const double signs[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};  // counter-clockwise
  for (const auto& sg : signs)
  {
    const double lx = sg[0] * hl, ly = sg[1] * hw;
    corners.push_back(t + Vec2(c * lx - s * ly, s * lx + c * ly));
  }
  return makePolygon(std::move(corners));
}

double Footprint::circumradius() const
{
  return std::hypot(0.5 * length_m, 0.5 * width_m);
}

CollisionChecker::CollisionChecker(const World& world, double z_low_m, double z_high_m)
    : world_(&world), z_low_(z_low_m), z_high_(z_high_m)
{
  ASSERTMSG_(z_low_m < z_high_m,
             mrpt::format("CollisionChecker: z_low (%g m) must be below z_high (%g m)", z_low_m,
                          z_high_m));
  obstacles_ = slabPolygons(world.mesh, z_low_, z_high_);
  BucketGrid grid = bucketPolygons(obstacles_, cell_);
  cell_ = grid.cell;
  grid_min_ = grid.min;
  nx_ = grid.nx;
  ny_ = grid.ny;
  buckets_ = std::move(grid.buckets);
}

bool CollisionChecker::collides(const mrpt::poses::CPose2D& pose, const Footprint& footprint) const
{
  if (overlapsObstacle(footprint.at(pose))) return true;
  return world_->insideObstacle(pose.x(), pose.y(), 0.5 * (z_low_ + z_high_));
}

bool CollisionChecker::overlapsObstacle(const ConvexPolygon2D& poly_in) const
{
  if (buckets_.empty() || poly_in.vertices.empty()) return false;
  // Recompute the bounds: callers may fill only the vertices.
  const ConvexPolygon2D poly = makePolygon(poly_in.vertices);
  const Vec2 grid_max = grid_min_ + cell_ * Vec2(nx_, ny_);
  if ((poly.max.array() < grid_min_.array()).any() || (poly.min.array() > grid_max.array()).any())
    return false;
  const int x0 = cellIndex(poly.min.x(), grid_min_.x(), cell_, nx_);
  const int x1 = cellIndex(poly.max.x(), grid_min_.x(), cell_, nx_);
  const int y0 = cellIndex(poly.min.y(), grid_min_.y(), cell_, ny_);
  const int y1 = cellIndex(poly.max.y(), grid_min_.y(), cell_, ny_);
  for (int iy = y0; iy <= y1; ++iy)
  {
    for (int ix = x0; ix <= x1; ++ix)
    {
      for (const int i : buckets_[static_cast<std::size_t>(iy) * nx_ + ix])
      {
        const ConvexPolygon2D& o = obstacles_[i];
        // Test each obstacle once: in the first cell it shares with the query.
        if (std::max(cellIndex(o.min.x(), grid_min_.x(), cell_, nx_), x0) != ix ||
            std::max(cellIndex(o.min.y(), grid_min_.y(), cell_, ny_), y0) != iy)
          continue;
        if (convexPolygonsOverlap(poly, o)) return true;
      }
    }
  }
  return false;
}

}  // namespace voxplore::sim
