/* voxplore — point-in-polygon test shared by the world loader (floor-plan
 * outlines) and the planner (exploration region). */
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace voxplore::common
{
/// @brief Even-odd crossing test: true when (x, y) is strictly inside the
///        closed polygon `poly` (vertices in order, first not repeated);
///        points exactly on an edge may go either way.
inline bool pointInPolygon(const std::vector<Eigen::Vector2d>& poly, double x, double y)
{
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    // Half-open rule on y so that a vertex on the ray is counted once.
    if ((a.y() > y) != (b.y() > y) &&
        x < a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}
}  // namespace voxplore::common
