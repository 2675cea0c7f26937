/* voxplore — a triangle soup in world coordinates (metres, Z up). */
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace voxplore::sim
{
/// @brief Indexed triangle mesh. Vertices in metres, Z up, floor at z = 0.
struct TriangleMesh
{
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;  ///< vertex indices, counter-clockwise seen from outside

  bool empty() const { return triangles.empty(); }
  std::size_t numTriangles() const { return triangles.size(); }

  /// @brief Appends `other` transformed by `T_world_other` (applied after scaling).
  void append(
      const TriangleMesh& other,
      const Eigen::Isometry3f& T_world_other = Eigen::Isometry3f::Identity(), float scale = 1.0f);

  /// @brief Adds one triangle from three explicit corners.
  void addTriangle(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c);

  /// @brief Adds the quad a-b-c-d (in order around its border) as two triangles.
  void addQuad(
      const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
      const Eigen::Vector3f& d);

  /// @brief Adds a closed box: centre (m), full size (m), rotation about Z (rad).
  void addBox(const Eigen::Vector3f& center, const Eigen::Vector3f& size, float yaw_rad = 0.0f);

  /// @brief Adds a closed vertical cylinder from z0 to z1 with `segments` sides.
  void addCylinder(
      const Eigen::Vector2f& center_xy, float radius, float z0, float z1, int segments = 24);

  /// @brief Axis-aligned bounds of all vertices referenced by triangles; empty box when empty().
  Eigen::AlignedBox3f bounds() const;

  /// @brief Index of the first vertex that is NaN or infinite, or -1 when all are finite.
  long firstNonFiniteVertex() const;
};

}  // namespace voxplore::sim
