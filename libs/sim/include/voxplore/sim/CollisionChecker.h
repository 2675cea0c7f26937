/* voxplore — footprint-vs-world collision checks for the simulated robot. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/World.h>

#include <Eigen/Core>
#include <vector>

namespace voxplore::sim
{
/// @brief A convex polygon in the XY plane (counter-clockwise or clockwise;
///        2 vertices = a segment, 1 = a point).
struct ConvexPolygon2D
{
  std::vector<Eigen::Vector2d> vertices;
  Eigen::Vector2d min{0, 0}, max{0, 0};  ///< axis-aligned bounds
};

/// @brief Exact 2D separating-axis test between two convex polygons
///        (degenerate segments and points included). Touching counts as overlap.
bool convexPolygonsOverlap(const ConvexPolygon2D& a, const ConvexPolygon2D& b);

/// @brief The robot footprint: a rectangle centred on the robot origin.
struct Footprint
{
  double length_m = 1.2;  ///< along robot +X
  double width_m = 0.712;  ///< along robot +Y
  /// @brief The rotated rectangle at `pose` as a convex polygon.
  ConvexPolygon2D at(const mrpt::poses::CPose2D& pose) const;
  /// @brief Radius of the circumscribed circle, sqrt((l/2)^2 + (w/2)^2).
  double circumradius() const;
};

/// @brief Answers "does the footprint at this pose touch any world geometry
///        between z_low and z_high?". Every triangle is clipped to that slab
///        and projected to the floor as a convex polygon; polygons are
///        bucketed in a uniform 2D grid for fast queries.
class CollisionChecker
{
 public:
  /// @param z_low_m geometry at or below this height is floor (ignored), e.g. 0.03 m
  /// @param z_high_m robot height: geometry above it cannot be hit
  CollisionChecker(const World& world, double z_low_m, double z_high_m);

  /// @brief True when the footprint at `pose` overlaps an obstacle or lies
  ///        (by its centre) inside an analytic solid / outside the floor plan.
  bool collides(const mrpt::poses::CPose2D& pose, const Footprint& footprint) const;

  /// @brief True when the convex polygon overlaps an obstacle polygon.
  bool overlapsObstacle(const ConvexPolygon2D& poly) const;

  /// @brief All obstacle polygons (projected clipped triangles).
  const std::vector<ConvexPolygon2D>& obstacles() const { return obstacles_; }

  double zLow() const { return z_low_; }
  double zHigh() const { return z_high_; }

 private:
  const World* world_;
  double z_low_, z_high_;
  std::vector<ConvexPolygon2D> obstacles_;
  // uniform bucket grid
  double cell_ = 0.5;
  Eigen::Vector2d grid_min_{0, 0};
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> buckets_;
};

}  // namespace voxplore::sim
