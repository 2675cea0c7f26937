/* voxplore — a simulated world: inside-obstacle tests on analytic solids and floor plans. */

#include <voxplore/sim/World.h>

#include <cmath>

namespace voxplore::sim
{
namespace
{
/// Even-odd crossing test: true when (x, y) is strictly inside the closed
/// polygon (points exactly on an edge may go either way).
bool pointInPolygon(const std::vector<Eigen::Vector2d>& poly, double x, double y)
{
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
  {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    // Half-open rule on y so that a vertex on the ray is counted once.
    if ((a.y() > y) != (b.y() > y))
    {
      const double x_cross = a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (x < x_cross)
      {
        inside = !inside;
      }
    }
  }
  return inside;
}
}  // namespace

bool Solid::contains(const Eigen::Vector3f& p) const
{
  const Eigen::Vector3f h = 0.5f * size;
  const Eigen::Vector3f d = p - center;
  if (!(std::abs(d.z()) < h.z()))
  {
    return false;
  }
  if (kind == Kind::Cylinder)
  {
    const float r = h.x();
    return d.x() * d.x() + d.y() * d.y() < r * r;
  }
  // Box: rotate the offset into the box frame (by -yaw).
  const float c = std::cos(yaw_rad);
  const float s = std::sin(yaw_rad);
  const float lx = c * d.x() + s * d.y();
  const float ly = -s * d.x() + c * d.y();
  return std::abs(lx) < h.x() && std::abs(ly) < h.y();
}

bool World::insideObstacle(double x, double y, double z) const
{
  const Eigen::Vector3f p(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  for (const auto& solid : solids)
  {
    if (solid.contains(p))
    {
      return true;
    }
  }
  if (free_space_outlines.empty())
  {
    return false;
  }
  for (const auto& outline : free_space_outlines)
  {
    if (outline.size() >= 3 && pointInPolygon(outline, x, y))
    {
      return false;
    }
  }
  return true;
}

}  // namespace voxplore::sim
