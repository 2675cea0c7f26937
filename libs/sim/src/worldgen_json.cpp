/* voxplore — procedural buildings: the .world file and the ground-truth JSON.
 * Numbers are printed with a fixed format, so that one seed gives the same
 * bytes everywhere. */

#include <cstdio>
#include <sstream>

#include "worldgen_internal.h"

namespace voxplore::sim
{
namespace
{
std::string num(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.4f", v == 0.0 ? 0.0 : v);  // no "-0.0000"
  return buf;
}

std::string xy(const Eigen::Vector2d& p) { return "[" + num(p.x()) + ", " + num(p.y()) + "]"; }

/// JSON string literal (labels are ours: letters, digits, spaces, '/').
std::string str(const std::string& s)
{
  std::string out = "\"";
  for (const char c : s)
  {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

const char* kindName(GenRegion::Kind k)
{
  switch (k)
  {
    case GenRegion::Kind::Corridor: return "corridor";
    case GenRegion::Kind::Hall: return "hall";
    default: return "room";
  }
}

std::string rect(const Rect2& r)
{
  return "[" + num(r.x0) + ", " + num(r.y0) + ", " + num(r.x1) + ", " + num(r.y1) + "]";
}
}  // namespace

std::string buildingWorldJson(const GeneratedBuilding& b)
{
  const WorldGenParams& p = b.params;
  std::ostringstream o;
  o << "{\n  \"name\": " << str("building_" + std::to_string(b.seed)) << ",\n";
  o << "  \"description\": "
    << str("voxplore-worldgen seed " + std::to_string(b.seed) + ": " + b.layout + " layout, " +
           std::to_string(b.roomCount()) + " rooms, " + std::to_string(b.doors.size()) + " doors, " +
           num(b.floor_area_m2) + " m2 of floor inside " + num(b.bounds.width()) + " x " +
           num(b.bounds.height()) + " m. Ground truth in building.json.")
    << ",\n";
  o << "  \"start\": {\"x\": " << num(b.start.x()) << ", \"y\": " << num(b.start.y())
    << ", \"yaw_deg\": " << num(b.start.z()) << "},\n";
  o << "  \"ground_plane\": true,\n  \"elements\": [\n";
  bool first = true;
  const auto sep = [&]()
  {
    if (!first) o << ",\n";
    first = false;
  };
  for (const GenWall& w : b.walls)
  {
    sep();
    o << "    {\"type\": \"wall\", \"from\": " << xy(w.from) << ", \"to\": " << xy(w.to)
      << ", \"thickness\": " << num(p.wall_thickness_m) << ", \"height\": " << num(p.wall_height_m)
      << "}";
  }
  for (const GenItem& it : b.items)
  {
    sep();
    o << "    {\"type\": " << str(it.type) << ", \"label\": " << str(it.label);
    if (it.type == "table")
      o << ", \"center\": " << xy(it.center) << ", \"size\": " << xy(it.size)
        << ", \"height\": " << num(it.height_m);
    else if (it.type == "chair")
      o << ", \"center\": " << xy(it.center) << ", \"yaw_deg\": " << num(it.yaw_deg);
    else
      o << ", \"center\": [" << num(it.center.x()) << ", " << num(it.center.y()) << ", "
        << num(0.5 * it.height_m) << "], \"size\": [" << num(it.size.x()) << ", "
        << num(it.size.y()) << ", " << num(it.height_m) << "]";
    o << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

std::string buildingGroundTruthJson(const GeneratedBuilding& b)
{
  std::ostringstream o;
  o << "{\n  \"generator\": \"voxplore-worldgen\",\n  \"seed\": " << b.seed
    << ",\n  \"layout\": " << str(b.layout) << ",\n  \"floor_area_m2\": " << num(b.floor_area_m2)
    << ",\n  \"bounds\": " << rect(b.bounds) << ",\n  \"start\": [" << num(b.start.x()) << ", "
    << num(b.start.y()) << ", " << num(b.start.z()) << "],\n";
  o << "  \"rooms\": " << b.roomCount() << ",\n  \"regions\": [\n";
  const double t = b.params.wall_thickness_m;
  for (std::size_t i = 0; i < b.regions.size(); i++)
  {
    const GenRegion& r = b.regions[i];
    o << "    {\"id\": " << r.id << ", \"kind\": " << str(kindName(r.kind))
      << ", \"name\": " << str(r.name) << ", \"rects\": [";
    for (std::size_t k = 0; k < r.rects.size(); k++) o << (k ? ", " : "") << rect(r.rects[k]);
    const Rect2& q = r.rects.front();
    o << "], \"interior\": "
      << rect({q.x0 + 0.5 * t, q.y0 + 0.5 * t, q.x1 - 0.5 * t, q.y1 - 0.5 * t}) << "}"
      << (i + 1 < b.regions.size() ? ",\n" : "\n");
  }
  o << "  ],\n  \"doors\": [\n";
  for (std::size_t i = 0; i < b.doors.size(); i++)
  {
    const GenDoor& d = b.doors[i];
    o << "    {\"regions\": [" << d.region_a << ", " << d.region_b << "], \"center\": "
      << xy(d.center) << ", \"wall_along\": " << str(d.along_x ? "x" : "y")
      << ", \"width_m\": " << num(d.width_m) << ", \"wide\": " << (d.wide ? "true" : "false")
      << "}" << (i + 1 < b.doors.size() ? ",\n" : "\n");
  }
  const WorldGenParams& p = b.params;
  o << "  ],\n  \"params\": {\"layout\": " << str(p.layout)
    << ", \"min_floor_m2\": " << num(p.min_floor_m2) << ", \"max_floor_m2\": " << num(p.max_floor_m2)
    << ", \"min_side_m\": " << num(p.min_side_m) << ", \"max_side_m\": " << num(p.max_side_m)
    << ", \"rooms\": " << p.rooms << ", \"corridor_width_min_m\": " << num(p.corridor_width_min_m)
    << ", \"corridor_width_max_m\": " << num(p.corridor_width_max_m)
    << ", \"room_depth_min_m\": " << num(p.room_depth_min_m)
    << ", \"room_depth_max_m\": " << num(p.room_depth_max_m)
    << ", \"room_width_min_m\": " << num(p.room_width_min_m)
    << ", \"room_width_max_m\": " << num(p.room_width_max_m)
    << ", \"door_width_min_m\": " << num(p.door_width_min_m)
    << ", \"door_width_max_m\": " << num(p.door_width_max_m)
    << ", \"wide_opening_share\": " << num(p.wide_opening_share)
    << ", \"wide_opening_min_m\": " << num(p.wide_opening_min_m)
    << ", \"wide_opening_max_m\": " << num(p.wide_opening_max_m)
    << ", \"wall_thickness_m\": " << num(p.wall_thickness_m)
    << ", \"wall_height_m\": " << num(p.wall_height_m)
    << ", \"furniture\": " << (p.furniture ? "true" : "false")
    << ", \"furniture_density\": " << num(p.furniture_density)
    << ", \"featureless_corridor_m\": " << num(p.featureless_corridor_m)
    << ", \"look_alike_rooms\": " << (p.look_alike_rooms ? "true" : "false") << "},\n";
  o << "  \"walls\": " << b.walls.size() << ",\n  \"items\": " << b.items.size() << "\n}\n";
  return o.str();
}

}  // namespace voxplore::sim
