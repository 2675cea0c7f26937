/* voxplore — procedural buildings: the [worldgen] parameters and their one validation. */

#include <mrpt/config/CConfigFileBase.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/worldgen.h>

#include <set>

namespace voxplore::sim
{
void WorldGenParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(layout, string, c, s);
  MRPT_LOAD_CONFIG_VAR(min_floor_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_floor_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_side_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_side_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rooms, int, c, s);
  MRPT_LOAD_CONFIG_VAR(corridor_width_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(corridor_width_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(room_depth_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(room_depth_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(room_width_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(room_width_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(door_width_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(door_width_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wide_opening_share, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wide_opening_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wide_opening_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wall_thickness_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(wall_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(furniture, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(furniture_density, double, c, s);
  MRPT_LOAD_CONFIG_VAR(featureless_corridor_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(look_alike_rooms, bool, c, s);
  const auto [key, why] = firstInvalid();
  common::requireValid(key.empty(), c, s, key, why);
}

std::pair<std::string, std::string> WorldGenParams::firstInvalid() const
{
  // Written as !(ok) so that NaN is invalid too.
  static const std::set<std::string> kLayouts{"corridor", "ring", "branching", "hall", "mixed"};
  if (!kLayouts.count(layout))
    return {"layout", "must be corridor, ring, branching, hall or mixed"};
  if (!(min_floor_m2 > 0 && min_floor_m2 <= max_floor_m2))
    return {"min_floor_m2", "must be positive and <= max_floor_m2"};
  if (!(min_side_m >= 8 && min_side_m <= max_side_m))
    return {"min_side_m", "must be >= 8 m and <= max_side_m"};
  if (rooms < 0)
    return {"rooms", "must be >= 0"};
  if (!(corridor_width_min_m >= 1.0 && corridor_width_min_m <= corridor_width_max_m))
    return {"corridor_width_min_m", "must be >= 1 m and <= corridor_width_max_m"};
  if (!(room_depth_min_m >= 2.0 && room_depth_min_m <= room_depth_max_m))
    return {"room_depth_min_m", "must be >= 2 m and <= room_depth_max_m"};
  if (!(room_width_min_m >= 2.0 && room_width_min_m <= room_width_max_m))
    return {"room_width_min_m", "must be >= 2 m and <= room_width_max_m"};
  if (!(door_width_min_m >= 0.3 && door_width_min_m <= door_width_max_m))
    return {"door_width_min_m", "must be >= 0.3 m and <= door_width_max_m"};
  if (!(door_width_max_m <= room_width_min_m - 1.0))
    return {"door_width_max_m",
            "must leave 0.5 m of wall on each side in the narrowest room (room_width_min_m - 1)"};
  if (!(wide_opening_share >= 0 && wide_opening_share <= 1))
    return {"wide_opening_share", "must be in [0, 1]"};
  if (!(wide_opening_min_m <= wide_opening_max_m && wide_opening_max_m <= room_width_min_m - 1.0))
    return {"wide_opening_max_m", "must be >= wide_opening_min_m and <= room_width_min_m - 1"};
  if (!(wall_thickness_m > 0.02 && wall_thickness_m <= 0.5))
    return {"wall_thickness_m", "must be in (0.02, 0.5] m"};
  if (!(wall_height_m > 0.7))
    return {"wall_height_m", "must be above the robots (> 0.7 m)"};
  if (!(furniture_density >= 0 && furniture_density <= 3))
    return {"furniture_density", "must be in [0, 3]"};
  if (!(featureless_corridor_m >= 0 && featureless_corridor_m <= 100))
    return {"featureless_corridor_m", "must be in [0, 100] m"};
  return {};
}

void WorldGenParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(layout, c, s);
  MRPT_SAVE_CONFIG_VAR(min_floor_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(max_floor_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(min_side_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_side_m, c, s);
  MRPT_SAVE_CONFIG_VAR(rooms, c, s);
  MRPT_SAVE_CONFIG_VAR(corridor_width_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(corridor_width_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(room_depth_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(room_depth_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(room_width_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(room_width_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(door_width_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(door_width_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(wide_opening_share, c, s);
  MRPT_SAVE_CONFIG_VAR(wide_opening_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(wide_opening_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(wall_thickness_m, c, s);
  MRPT_SAVE_CONFIG_VAR(wall_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(furniture, c, s);
  MRPT_SAVE_CONFIG_VAR(furniture_density, c, s);
  MRPT_SAVE_CONFIG_VAR(featureless_corridor_m, c, s);
  MRPT_SAVE_CONFIG_VAR(look_alike_rooms, c, s);
}

}  // namespace voxplore::sim
