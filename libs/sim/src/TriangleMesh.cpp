/* voxplore — a triangle soup in world coordinates (metres, Z up). */

#include <voxplore/sim/TriangleMesh.h>

#include <cmath>
#include <stdexcept>

namespace voxplore::sim
{
namespace
{
constexpr float kTwoPi = 6.283185307179586f;
}  // namespace

void TriangleMesh::append(const TriangleMesh& other, const Eigen::Isometry3f& T_world_other,
                          float scale)
{
  const int offset = static_cast<int>(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices)
  {
    vertices.push_back(T_world_other * (scale * v));
  }
  triangles.reserve(triangles.size() + other.triangles.size());
  const Eigen::Vector3i shift(offset, offset, offset);
  for (const auto& t : other.triangles)
  {
    triangles.push_back(t + shift);
  }
}

void TriangleMesh::addTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                               const Eigen::Vector3f& c)
{
  const int i = static_cast<int>(vertices.size());
  vertices.push_back(a);
  vertices.push_back(b);
  vertices.push_back(c);
  triangles.emplace_back(i, i + 1, i + 2);
}

void TriangleMesh::addQuad(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                           const Eigen::Vector3f& c, const Eigen::Vector3f& d)
{
  const int i = static_cast<int>(vertices.size());
  vertices.push_back(a);
  vertices.push_back(b);
  vertices.push_back(c);
  vertices.push_back(d);
  triangles.emplace_back(i, i + 1, i + 2);
  triangles.emplace_back(i, i + 2, i + 3);
}

void TriangleMesh::addBox(const Eigen::Vector3f& center, const Eigen::Vector3f& size, float yaw_rad)
{
  const Eigen::Vector3f h = 0.5f * size;
  const Eigen::Matrix3f R = Eigen::AngleAxisf(yaw_rad, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  const int i = static_cast<int>(vertices.size());
  // Corner k has sign bits (x: bit 0, y: bit 1, z: bit 2); 1 means +half size.
  for (int k = 0; k < 8; ++k)
  {
    const Eigen::Vector3f local((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                                (k & 4) ? h.z() : -h.z());
    vertices.push_back(center + R * local);
  }
  // Faces as quads in counter-clockwise order seen from outside.
  const int faces[6][4] = {
      {0, 2, 3, 1},  // bottom (-Z)
      {4, 5, 7, 6},  // top (+Z)
      {0, 1, 5, 4},  // -Y
      {2, 6, 7, 3},  // +Y
      {0, 4, 6, 2},  // -X
      {1, 3, 7, 5},  // +X
  };
  for (const auto& f : faces)
  {
    triangles.emplace_back(i + f[0], i + f[1], i + f[2]);
    triangles.emplace_back(i + f[0], i + f[2], i + f[3]);
  }
}

void TriangleMesh::addCylinder(const Eigen::Vector2f& center_xy, float radius, float z0, float z1,
                               int segments)
{
  if (segments < 3)
  {
    throw std::invalid_argument("TriangleMesh::addCylinder: segments must be >= 3");
  }
  const int i = static_cast<int>(vertices.size());
  const int bottom_center = i;
  const int top_center = i + 1;
  vertices.emplace_back(center_xy.x(), center_xy.y(), z0);
  vertices.emplace_back(center_xy.x(), center_xy.y(), z1);
  // Ring vertex s: bottom at i + 2 + 2 s, top at i + 3 + 2 s.
  for (int s = 0; s < segments; ++s)
  {
    const float a = kTwoPi * static_cast<float>(s) / static_cast<float>(segments);
    const float x = center_xy.x() + radius * std::cos(a);
    const float y = center_xy.y() + radius * std::sin(a);
    vertices.emplace_back(x, y, z0);
    vertices.emplace_back(x, y, z1);
  }
  for (int s = 0; s < segments; ++s)
  {
    const int b0 = i + 2 + 2 * s;
    const int t0 = b0 + 1;
    const int b1 = i + 2 + 2 * ((s + 1) % segments);
    const int t1 = b1 + 1;
    triangles.emplace_back(b0, b1, t1);  // side, outward normal
    triangles.emplace_back(b0, t1, t0);
    triangles.emplace_back(bottom_center, b1, b0);  // bottom cap, normal -Z
    triangles.emplace_back(top_center, t0, t1);     // top cap, normal +Z
  }
}

Eigen::AlignedBox3f TriangleMesh::bounds() const
{
  Eigen::AlignedBox3f box;  // default-constructed: empty
  for (const auto& t : triangles)
  {
    for (int k = 0; k < 3; ++k)
    {
      box.extend(vertices.at(static_cast<std::size_t>(t[k])));
    }
  }
  return box;
}

long TriangleMesh::firstNonFiniteVertex() const
{
  for (std::size_t k = 0; k < vertices.size(); ++k)
  {
    if (!vertices[k].allFinite())
    {
      return static_cast<long>(k);
    }
  }
  return -1;
}

}  // namespace voxplore::sim
