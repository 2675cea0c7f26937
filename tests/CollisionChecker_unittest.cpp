/* voxplore — tests of the 2D separating-axis test and the footprint collision checker. */

#include <gtest/gtest.h>
#include <mrpt/core/bits_math.h>
#include <voxplore/sim/CollisionChecker.h>

#include <cmath>
#include <random>

using namespace voxplore::sim;
using Eigen::Vector2d;
using Eigen::Vector3f;

namespace
{
ConvexPolygon2D poly(std::vector<Vector2d> v)
{
  ConvexPolygon2D p;
  p.vertices = std::move(v);
  p.min = p.max = p.vertices.front();
  for (const auto& q : p.vertices)
  {
    p.min = p.min.cwiseMin(q);
    p.max = p.max.cwiseMax(q);
  }
  return p;
}

ConvexPolygon2D square(double x0, double y0, double side)
{
  return poly({{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}});
}

bool overlap(const ConvexPolygon2D& a, const ConvexPolygon2D& b)
{
  const bool ab = convexPolygonsOverlap(a, b), ba = convexPolygonsOverlap(b, a);
  EXPECT_EQ(ab, ba) << "the SAT test must be symmetric";
  return ab;
}

/// A floor quad at z = 0 over [-10, 10]^2.
World floorWorld()
{
  World w;
  w.name = "test";
  w.mesh.addQuad({-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0});
  return w;
}

// --- independent reference for the randomized SAT check -------------------
double orient(const Vector2d& a, const Vector2d& b, const Vector2d& c)
{
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

bool onSegment(const Vector2d& a, const Vector2d& b, const Vector2d& p)
{
  return orient(a, b, p) == 0 && p.x() >= std::min(a.x(), b.x()) &&
         p.x() <= std::max(a.x(), b.x()) && p.y() >= std::min(a.y(), b.y()) &&
         p.y() <= std::max(a.y(), b.y());
}

bool segmentsIntersect(const Vector2d& a, const Vector2d& b, const Vector2d& c, const Vector2d& d)
{
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return onSegment(a, b, c) || onSegment(a, b, d) || onSegment(c, d, a) || onSegment(c, d, b);
}

/// Point inside or on a convex polygon with >= 3 counter-clockwise vertices.
bool insideConvex(const std::vector<Vector2d>& v, const Vector2d& p)
{
  if (v.size() < 3) return false;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (orient(v[i], v[(i + 1) % v.size()], p) < 0) return false;
  return true;
}

/// Overlap by edge intersections and containment (no separating axes).
bool referenceOverlap(const ConvexPolygon2D& a, const ConvexPolygon2D& b)
{
  const auto& va = a.vertices;
  const auto& vb = b.vertices;
  for (std::size_t i = 0; i < va.size(); ++i)
    for (std::size_t j = 0; j < vb.size(); ++j)
      if (segmentsIntersect(va[i], va[(i + 1) % va.size()], vb[j], vb[(j + 1) % vb.size()]))
        return true;
  return insideConvex(va, vb.front()) || insideConvex(vb, va.front());
}

/// A random convex polygon with 1 (point), 2 (segment) or 3-6 vertices (ccw).
ConvexPolygon2D randomPolygon(std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> centre(-2, 2), radius(0.05, 1.5), angle(0, 2 * M_PI);
  std::uniform_int_distribution<int> count(1, 6);
  const Vector2d c(centre(rng), centre(rng));
  const int n = count(rng);
  std::vector<double> angles(n);
  for (auto& a : angles) a = angle(rng);
  std::sort(angles.begin(), angles.end());
  const double r = radius(rng);
  std::vector<Vector2d> v;
  for (double a : angles) v.push_back(c + r * Vector2d(std::cos(a), std::sin(a)));
  return poly(v);
}
}  // namespace

TEST(ConvexPolygonsOverlap, Squares)
{
  const auto a = square(0, 0, 1);
  EXPECT_TRUE(overlap(a, square(0.5, 0.5, 1)));
  EXPECT_TRUE(overlap(a, square(0.25, 0.25, 0.5)));  // contained
  EXPECT_FALSE(overlap(a, square(1.001, 0, 1)));
  EXPECT_TRUE(overlap(a, square(1, 0.5, 1)));  // shared edge: touching counts
  EXPECT_TRUE(overlap(a, square(1, 1, 1)));    // shared corner
  EXPECT_FALSE(overlap(a, square(1, 1.0000001, 1)));
}

TEST(ConvexPolygonsOverlap, SeparatedOnlyByAnEdgeNormal)
{
  // The bounding boxes overlap; only the triangle's hypotenuse separates them.
  const auto tri = poly({{0, 0}, {2, 0}, {0, 2}});
  EXPECT_FALSE(overlap(tri, square(1.05, 1.05, 1)));
  EXPECT_TRUE(overlap(tri, square(1.0, 1.0, 1)));  // corner on the hypotenuse
  EXPECT_TRUE(overlap(tri, square(0.95, 0.95, 1)));
}

TEST(ConvexPolygonsOverlap, Segments)
{
  const auto sq = square(0, 0, 1);
  EXPECT_TRUE(overlap(sq, poly({{-1, 0.5}, {2, 0.5}})));     // crosses, no vertex inside
  EXPECT_TRUE(overlap(sq, poly({{0.2, 0.2}, {0.8, 0.7}})));  // inside
  EXPECT_TRUE(overlap(sq, poly({{1, 1}, {2, 3}})));          // touches a corner
  EXPECT_TRUE(overlap(sq, poly({{1, -1}, {1, 3}})));         // lies along an edge
  // Diagonal segment passing the corner (1,1) at a distance: only its normal separates.
  EXPECT_FALSE(overlap(sq, poly({{2.1, 0}, {0, 2.1}})));
  EXPECT_TRUE(overlap(sq, poly({{2.0, 0}, {0, 2.0}})));
}

TEST(ConvexPolygonsOverlap, CollinearAndParallelSegments)
{
  const auto s = poly({{0, 0}, {1, 1}});
  EXPECT_FALSE(overlap(s, poly({{1.1, 1.1}, {2, 2}})));  // collinear, gap: direction axis
  EXPECT_TRUE(overlap(s, poly({{1, 1}, {2, 2}})));       // collinear, shared end point
  EXPECT_TRUE(overlap(s, poly({{0.5, 0.5}, {2, 2}})));   // collinear, overlapping
  EXPECT_FALSE(overlap(s, poly({{0, 0.1}, {1, 1.1}})));  // parallel
  EXPECT_TRUE(overlap(s, poly({{0, 1}, {1, 0}})));       // crossing
  EXPECT_FALSE(overlap(s, poly({{0, 1}, {0.4, 0.6001}})));
  // Three collinear vertices given as a "polygon" behave like the segment.
  EXPECT_FALSE(overlap(poly({{0, 0}, {0.5, 0.5}, {1, 1}}), poly({{1.1, 1.1}, {2, 2}})));
}

TEST(ConvexPolygonsOverlap, Points)
{
  const auto sq = square(0, 0, 1);
  EXPECT_TRUE(overlap(sq, poly({{0.5, 0.5}})));
  EXPECT_TRUE(overlap(sq, poly({{1, 0.3}})));  // on an edge
  EXPECT_FALSE(overlap(sq, poly({{1.0001, 0.3}})));
  const auto tri = poly({{0, 0}, {2, 0}, {0, 2}});
  EXPECT_FALSE(overlap(tri, poly({{1.01, 1.01}})));
  EXPECT_TRUE(overlap(tri, poly({{1, 1}})));
  const auto seg = poly({{0, 0}, {2, 1}});
  EXPECT_TRUE(overlap(seg, poly({{1, 0.5}})));
  EXPECT_FALSE(overlap(seg, poly({{1, 0.5001}})));
  EXPECT_FALSE(overlap(seg, poly({{2.2, 1.1}})));  // on the line, past the end
  EXPECT_TRUE(overlap(poly({{3, 4}}), poly({{3, 4}})));
  EXPECT_FALSE(overlap(poly({{3, 4}}), poly({{3, 4.0001}})));
  EXPECT_FALSE(overlap(sq, ConvexPolygon2D{}));
}

TEST(ConvexPolygonsOverlap, AgreesWithEdgeIntersectionReference)
{
  std::mt19937_64 rng(42);
  int overlapping = 0;
  for (int i = 0; i < 20000; ++i)
  {
    const auto a = randomPolygon(rng), b = randomPolygon(rng);
    const bool expected = referenceOverlap(a, b);
    overlapping += expected;
    ASSERT_EQ(convexPolygonsOverlap(a, b), expected) << "pair " << i;
  }
  EXPECT_GT(overlapping, 2000);  // both outcomes are well represented
  EXPECT_LT(overlapping, 18000);
}

TEST(Footprint, CornersAndCircumradius)
{
  const Footprint fp{1.2, 0.712};
  EXPECT_NEAR(fp.circumradius(), std::hypot(0.6, 0.356), 1e-12);
  const auto p = fp.at(mrpt::poses::CPose2D(1, 2, M_PI / 2));
  ASSERT_EQ(p.vertices.size(), 4u);
  EXPECT_NEAR(p.min.x(), 1 - 0.356, 1e-12);
  EXPECT_NEAR(p.max.x(), 1 + 0.356, 1e-12);
  EXPECT_NEAR(p.min.y(), 2 - 0.6, 1e-12);
  EXPECT_NEAR(p.max.y(), 2 + 0.6, 1e-12);
}

TEST(CollisionChecker, WallBecomesSegmentsAndFloorIsIgnored)
{
  World w = floorWorld();
  w.mesh.addBox({2.0625f, 0, 1}, {0.125f, 4, 2});  // wall, faces at x = 2 and 2.125
  const CollisionChecker checker(w, 0.03, 0.645);
  // Floor, wall top (z = 2) and bottom (z = 0) are dropped; 4 sides x 2 triangles remain.
  ASSERT_EQ(checker.obstacles().size(), 8u);
  for (const auto& o : checker.obstacles()) EXPECT_EQ(o.vertices.size(), 2u);
}

TEST(CollisionChecker, SlantedTriangleIsClippedToTheSlab)
{
  World w;
  w.mesh.addTriangle({0, 0, 0}, {2, 0, 0}, {0, 2, 2});  // z = y
  const CollisionChecker checker(w, 0.03, 0.645);
  ASSERT_EQ(checker.obstacles().size(), 1u);
  const auto& o = checker.obstacles().front();
  EXPECT_EQ(o.vertices.size(), 4u);
  EXPECT_NEAR(o.min.x(), 0, 1e-6);
  EXPECT_NEAR(o.min.y(), 0.03, 1e-6);
  EXPECT_NEAR(o.max.x(), 1.97, 1e-6);
  EXPECT_NEAR(o.max.y(), 0.645, 1e-6);
}

TEST(CollisionChecker, FootprintAgainstWallInEveryOrientation)
{
  World w = floorWorld();
  const double wall_x = 2.0;  // the wall's -X face, exact in float
  w.mesh.addBox({2.0625f, 0, 1}, {0.125f, 8, 2});
  const CollisionChecker checker(w, 0.03, 0.645);
  const Footprint fp{1.2, 0.712};
  for (int deg = 0; deg <= 360; deg += 5)
  {
    const double yaw = mrpt::DEG2RAD(double(deg));
    // Half extent of the rotated rectangle along the wall normal (+X).
    const double extent = std::abs(0.6 * std::cos(yaw)) + std::abs(0.356 * std::sin(yaw));
    const auto at = [&](double gap)
    { return mrpt::poses::CPose2D(wall_x - extent - gap, 0.3, yaw); };
    EXPECT_TRUE(checker.collides(at(-1e-6), fp)) << deg << " deg, penetrating 1 um";
    EXPECT_TRUE(checker.collides(at(-0.05), fp)) << deg << " deg, penetrating 5 cm";
    EXPECT_FALSE(checker.collides(at(1e-6), fp)) << deg << " deg, 1 um away";
    EXPECT_FALSE(checker.collides(at(0.003), fp)) << deg << " deg, 3 mm away";
    // Beyond the wall (x > 2.125 + extent) it is free again; inside it, it collides.
    EXPECT_TRUE(checker.collides(mrpt::poses::CPose2D(2.0625, 0, yaw), fp)) << deg;
    EXPECT_FALSE(checker.collides(mrpt::poses::CPose2D(2.125 + extent + 0.003, 0, yaw), fp));
  }
}

TEST(CollisionChecker, GeometryAboveRobotOrBelowClearanceIsFree)
{
  World w = floorWorld();
  w.mesh.addBox({0, 0, 0.85f}, {2, 2, 0.3f});   // overhang from z = 0.7 to 1.0
  w.mesh.addBox({0, 0, 0.01f}, {3, 3, 0.02f});  // rug up to z = 0.02
  const CollisionChecker checker(w, 0.03, 0.645);
  EXPECT_TRUE(checker.obstacles().empty());
  const Footprint fp;
  EXPECT_FALSE(checker.collides(mrpt::poses::CPose2D(0, 0, 0.3), fp));

  // Geometry reaching exactly up to z_low is floor (e.g. a threshold strip).
  World flush = floorWorld();
  flush.mesh.addBox({0, 0, 0.015625f}, {0.5f, 0.5f, 0.03125f});  // top at 1/32 m, exact
  EXPECT_TRUE(CollisionChecker(flush, 0.03125, 0.645).obstacles().empty());
  EXPECT_FALSE(CollisionChecker(flush, 0.03125, 0.645).collides({0, 0, 0}, fp));
  EXPECT_TRUE(CollisionChecker(flush, 0.03, 0.645).collides({0, 0, 0}, fp));

  World low = floorWorld();
  low.mesh.addBox({0.5f, 0, 0.025f}, {0.2f, 0.2f, 0.05f});  // 5 cm step: an obstacle
  low.mesh.addBox({-3, 0, 0.8f}, {0.2f, 0.2f, 0.4f});       // hanging down to z = 0.6
  const CollisionChecker checker_low(low, 0.03, 0.645);
  EXPECT_TRUE(checker_low.collides(mrpt::poses::CPose2D(0, 0, 0), fp));
  EXPECT_TRUE(checker_low.collides(mrpt::poses::CPose2D(-3, 0, 0), fp));
  EXPECT_FALSE(checker_low.collides(mrpt::poses::CPose2D(-1.5, 0, 0), fp));
}

TEST(CollisionChecker, CentreInsideAnalyticSolid)
{
  World w = floorWorld();
  Solid s;
  s.kind = Solid::Kind::Box;
  s.center = {5, 5, 1};
  s.size = {4, 4, 2};
  w.solids.push_back(s);  // no triangles: only World::insideObstacle knows it
  const CollisionChecker checker(w, 0.03, 0.645);
  EXPECT_TRUE(checker.collides(mrpt::poses::CPose2D(5, 5, 0), Footprint{}));
  EXPECT_FALSE(checker.collides(mrpt::poses::CPose2D(0, 0, 0), Footprint{}));
}

TEST(CollisionChecker, ManyObstaclesMatchBruteForce)
{
  World w = floorWorld();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> xy(-9, 9), size(0.05, 1.0), yaw(-M_PI, M_PI);
  for (int i = 0; i < 200; ++i)
  {
    w.mesh.addBox({float(xy(rng)), float(xy(rng)), 0.5f}, {float(size(rng)), float(size(rng)), 1},
                  float(yaw(rng)));
  }
  const CollisionChecker checker(w, 0.03, 0.645);
  const Footprint fp;
  int hits = 0;
  for (int i = 0; i < 2000; ++i)
  {
    const mrpt::poses::CPose2D pose(xy(rng), xy(rng), yaw(rng));
    const auto foot = fp.at(pose);
    bool expected = false;
    for (const auto& o : checker.obstacles()) expected = expected || convexPolygonsOverlap(foot, o);
    hits += expected;
    ASSERT_EQ(checker.collides(pose, fp), expected) << "pose " << i;
  }
  EXPECT_GT(hits, 100);
  EXPECT_LT(hits, 1900);
}
