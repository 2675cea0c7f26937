/* voxplore — loading worlds: world files, triangle meshes, HouseExpo floor plans.
 *
 * World file (`*.world`, JSON): composes meshes, floor plans and primitives
 * with a robot start pose. Format (all lengths in metres, angles in degrees):
 *
 *   {
 *     "name": "dlr_test_room",
 *     "start": {"x": 2.0, "y": 4.0, "yaw_deg": 0},
 *     "ground_plane": true,                 // add a floor quad under everything (default true)
 *     "elements": [
 *       {"type": "mesh", "file": "x.obj", "translation": [0,0,0], "yaw_deg": 0, "scale": 1},
 *       {"type": "floorplan", "file": "plan.json", "wall_height": 2.5},
 *       {"type": "box", "center": [x,y,z], "size": [sx,sy,sz], "yaw_deg": 0},
 *       {"type": "cylinder", "center": [x,y], "radius": r, "z": [z0,z1]},
 *       {"type": "wall", "from": [x0,y0], "to": [x1,y1], "thickness": 0.15, "height": 2.5},
 *       {"type": "table", "center": [x,y], "size": [sx,sy], "height": 0.75, "yaw_deg": 0},
 *       {"type": "chair", "center": [x,y], "yaw_deg": 0}
 *     ]
 *   }
 * Relative file paths are relative to the world file's folder. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/sim/World.h>

#include <optional>
#include <string>

namespace voxplore::sim
{
/// @brief Options for floor plans and bare meshes loaded without a world file.
struct WorldLoadOptions
{
  double wall_height_m = 2.5;       ///< extrusion height of floor-plan walls
  bool add_ground_plane = true;     ///< add a floor quad (z = 0) covering the bounds + margin
  double ground_margin_m = 1.0;     ///< how far the ground plane extends past the bounds
};

/// @brief Loads any world input by extension: `.world` (JSON world file),
///        `.json` (HouseExpo floor plan), or a mesh assimp reads (`.obj`,
///        `.ply`, `.stl`, ...). For floor plans and meshes the start pose is
///        `start` (default 0,0,0); for world files `start` overrides the file's.
/// @throws std::runtime_error naming the file for a missing, empty or
///         malformed input, or non-finite vertices.
World loadWorld(
    const std::string& path, const std::optional<mrpt::poses::CPose2D>& start = std::nullopt,
    const WorldLoadOptions& opts = {});

/// @brief Loads a triangle mesh with assimp (triangulated, all nodes'
///        transforms applied).
/// @throws std::runtime_error naming the file when missing, unreadable,
///         empty (no triangles) or with non-finite vertices.
TriangleMesh loadMeshFile(const std::string& path);

/// @brief Reads a HouseExpo floor-plan JSON: `verts` is one closed polygon
///        bounding the free space. Its edges become vertical walls of
///        `wall_height_m`; the polygon is recorded in
///        World::free_space_outlines.
/// @throws std::runtime_error naming the file when malformed.
World loadFloorPlan(const std::string& path, const WorldLoadOptions& opts = {});

/// @brief Reads a `.world` JSON file (see the format above).
/// @throws std::runtime_error naming the file (and the element index) when malformed.
World loadWorldFile(const std::string& path, const WorldLoadOptions& opts = {});

/// @brief Parses the text of a `.world` file as if read from `path`: errors
///        name `path`, relative element files resolve against its folder and
///        World::name is its stem (`path` itself is not read). loadWorldFile()
///        reads the file and calls this; the fuzz target calls it directly.
/// @throws std::runtime_error naming `path` (and the element index) when malformed.
World parseWorldFile(const std::string& text, const std::string& path,
                     const WorldLoadOptions& opts = {});

/// @brief Parses the text of a HouseExpo floor plan as if read from `path`
///        (see loadFloorPlan(); `path` names it in errors and is not read).
/// @throws std::runtime_error naming `path` when malformed.
World parseFloorPlan(const std::string& text, const std::string& path,
                     const WorldLoadOptions& opts = {});

/// @brief Adds a ground quad at z = 0 covering the mesh bounds plus `margin_m`.
void addGroundPlane(World& world, double margin_m);

/// @brief Parses "x,y,yaw_deg" (yaw optional) into a pose (yaw in radians).
/// @throws std::runtime_error on malformed text.
mrpt::poses::CPose2D parseStartPose(const std::string& text);

}  // namespace voxplore::sim
