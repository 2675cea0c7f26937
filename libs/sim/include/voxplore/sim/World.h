/* voxplore — a simulated world: static triangle geometry plus a robot start pose. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/TriangleMesh.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace voxplore::sim
{
/// @brief A solid primitive kept analytically (besides its triangles) so that
///        "is this point inside an obstacle" has an exact answer.
struct Solid
{
  enum class Kind
  {
    Box,
    Cylinder
  };
  Kind kind = Kind::Box;
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  ///< box centre; cylinder: (x, y, (z0+z1)/2)
  Eigen::Vector3f size = Eigen::Vector3f::Zero();    ///< box full size; cylinder: (2r, 2r, z1-z0)
  float yaw_rad = 0.0f;                              ///< box rotation about Z

  /// @brief True when the point (x, y) at height z lies strictly inside.
  bool contains(const Eigen::Vector3f& p) const;
};

/// @brief The static world the simulator casts rays into and collides with.
struct World
{
  std::string name;         ///< short name (file stem)
  std::string source_path;  ///< the file it was loaded from (for error messages)
  TriangleMesh mesh;        ///< all geometry, world frame, metres, Z up, floor at z = 0
  mrpt::poses::CPose2D start;  ///< robot start pose in the world frame

  /// Analytic solids (boxes, cylinders) from world files, for inside tests.
  std::vector<Solid> solids;

  /// Floor-plan outlines bounding the free space (HouseExpo): a point outside
  /// every outline is inside an obstacle. Empty when the world has none.
  std::vector<std::vector<Eigen::Vector2d>> free_space_outlines;

  /// @brief True when (x, y) at height z is inside an analytic solid or
  ///        outside every floor-plan outline (when there are outlines).
  bool insideObstacle(double x, double y, double z) const;
};

}  // namespace voxplore::sim
