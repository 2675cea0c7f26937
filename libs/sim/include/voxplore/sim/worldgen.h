/* voxplore — procedural office buildings as test material (issue 10).
 *
 * A building is painted as axis-aligned regions (corridors, rooms, a hall) on
 * a 5 cm lattice; walls are the boundaries between regions (and between a
 * region and the outside), cut where a door joins two regions. Furniture
 * stands against the room walls and never in a door's approach. Everything
 * is drawn from one seeded generator: the same seed and parameters give the
 * same file, byte for byte. Our own code: no library generates buildings
 * for a planar robot with ordinary doors (MRPT has none; HouseExpo is a fixed
 * data set). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace voxplore::sim
{
/// @brief The [worldgen] section: what kind of building to draw.
struct WorldGenParams : public mrpt::config::CLoadableOptions
{
  std::string layout = "mixed";  ///< corridor | ring | branching | hall | mixed (one of the four by seed)
  double min_floor_m2 = 200;     ///< target floor area drawn in [min, max] [m^2]
  double max_floor_m2 = 1500;
  double min_side_m = 15;        ///< building sides are kept in [min, max] [m]
  double max_side_m = 60;
  int rooms = 0;                 ///< rooms wanted (about); 0 = as the room widths give
  double corridor_width_min_m = 1.8;  ///< corridor free width drawn in [min, max] [m]
  double corridor_width_max_m = 2.4;
  double room_depth_min_m = 3.5;      ///< room depth away from its corridor [m]
  double room_depth_max_m = 6.0;
  double room_width_min_m = 3.0;      ///< room width along its corridor [m]
  double room_width_max_m = 6.0;
  double door_width_min_m = 0.85;     ///< free opening between the jambs [m]
  double door_width_max_m = 1.0;
  double wide_opening_share = 0.0;    ///< share of doors drawn as wide openings instead [0..1]
  double wide_opening_min_m = 1.6;
  double wide_opening_max_m = 2.0;
  double wall_thickness_m = 0.15;
  double wall_height_m = 2.5;
  bool furniture = true;              ///< tables, chairs, cabinets, shelves in rooms and hall
  double furniture_density = 1.0;     ///< scales the items per room (0 = none)
  double featureless_corridor_m = 0;  ///< corridor / branching: a blank corridor stretch this long at the east end [m]
  bool look_alike_rooms = false;      ///< all rooms the same size and furniture (false loop closures)

  /// @brief The first parameter out of range, as {key, why}; {"", ""} when all
  ///        are valid. The one set of rules behind loadFromConfigFile() (which
  ///        names the file) and generateBuilding().
  std::pair<std::string, std::string> firstInvalid() const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief An axis-aligned rectangle [x0, x1] x [y0, y1] in metres.
struct Rect2
{
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  double area() const { return width() * height(); }
  Eigen::Vector2d center() const { return {0.5 * (x0 + x1), 0.5 * (y0 + y1)}; }
};

/// @brief A corridor, room or hall: the union of its rectangles (the lattice
///        outline, walls centred on its edges, so the free space is inset by
///        half a wall thickness).
struct GenRegion
{
  enum class Kind
  {
    Corridor,
    Room,
    Hall
  };
  int id = 0;  ///< 1-based
  Kind kind = Kind::Room;
  std::vector<Rect2> rects;
  std::string name;
};

/// @brief An opening in the wall between two regions.
struct GenDoor
{
  int region_a = 0, region_b = 0;  ///< region ids
  Eigen::Vector2d center{0, 0};    ///< on the wall's centre line
  bool along_x = true;             ///< the wall runs along x (the door is crossed along y)
  double width_m = 0;              ///< free opening between the jambs
  bool wide = false;               ///< drawn as a wide opening
};

/// @brief One piece of furniture (the .world element it becomes).
struct GenItem
{
  std::string type;  ///< table | chair | box
  std::string label;
  Eigen::Vector2d center{0, 0};
  Eigen::Vector2d size{0, 0};  ///< footprint (table, box)
  double height_m = 0;         ///< table top / box height
  double yaw_deg = 0;
};

/// @brief A wall segment (a .world "wall" element).
struct GenWall
{
  Eigen::Vector2d from{0, 0}, to{0, 0};
};

/// @brief A generated building with its ground truth.
struct GeneratedBuilding
{
  uint64_t seed = 0;
  std::string layout;
  WorldGenParams params;
  std::vector<GenRegion> regions;
  std::vector<GenDoor> doors;
  std::vector<GenWall> walls;
  std::vector<GenItem> items;
  Eigen::Vector3d start{0, 0, 0};  ///< x, y, yaw_deg: in a corridor, free for the omniRob
  Rect2 bounds;                    ///< the outer wall lines
  double floor_area_m2 = 0;        ///< free floor inside the walls (furniture not subtracted)

  /// @brief Number of regions of kind Room.
  std::size_t roomCount() const;
};

/// @brief Draws a building. @throws std::invalid_argument for parameters
///        WorldGenParams::firstInvalid() rejects, naming the key.
GeneratedBuilding generateBuilding(const WorldGenParams& params, uint64_t seed);

/// @brief The building as a `.world` JSON text (format: world_loading.h).
std::string buildingWorldJson(const GeneratedBuilding& b);

/// @brief Ground truth as JSON: layout, seed, floor area, regions with their
///        rectangles, doors with their widths, the start pose, the parameters.
std::string buildingGroundTruthJson(const GeneratedBuilding& b);

}  // namespace voxplore::sim
