/* voxplore — a simulated world: inside-obstacle tests on analytic solids and floor plans. */

#include <voxplore/common/polygon.h>
#include <voxplore/sim/World.h>

#include <cmath>

namespace voxplore::sim
{
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
    if (outline.size() >= 3 && common::pointInPolygon(outline, x, y))
    {
      return false;
    }
  }
  return true;
}

}  // namespace voxplore::sim
