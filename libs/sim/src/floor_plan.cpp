/* voxplore — HouseExpo floor plans: one closed polygon bounding the free space,
 * extruded into vertical walls. */

#include <voxplore/sim/world_loading.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "json_file.h"

namespace voxplore::sim
{
namespace
{
using nlohmann::json;

/// Reads `verts` as a list of [x, y] pairs; throws naming the file and vertex.
std::vector<Eigen::Vector2d> readPolygon(const json& doc, const std::string& path)
{
  if (!doc.is_object())
  {
    detail::failFile(path, "expected a JSON object with a 'verts' array (HouseExpo floor plan)");
  }
  const auto it = doc.find("verts");
  if (it == doc.end())
  {
    detail::failFile(path, "missing required field 'verts'");
  }
  if (!it->is_array())
  {
    detail::failFile(path, "field 'verts' must be an array of [x, y] pairs");
  }
  std::vector<Eigen::Vector2d> poly;
  for (std::size_t i = 0; i < it->size(); ++i)
  {
    const json& v = (*it)[i];
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number())
    {
      detail::failFile(path, "verts[" + std::to_string(i) +
                                 "] must be an [x, y] pair of numbers, got " + v.dump());
    }
    const Eigen::Vector2d p(v[0].get<double>(), v[1].get<double>());
    if (!p.allFinite())
    {
      detail::failFile(path, "verts[" + std::to_string(i) + "] is not finite");
    }
    // The walls are float vertices: 1e308 is a finite double but an infinite
    // wall (found by fuzz/fuzz_floor_plan).
    if (!(p.cwiseAbs().maxCoeff() <= std::numeric_limits<float>::max()))
    {
      detail::failFile(path, "verts[" + std::to_string(i) +
                                 "] is beyond the float range of mesh vertices, got " + v.dump());
    }
    if (!poly.empty() && p == poly.back())
    {
      continue;  // repeated vertex: zero-length edge
    }
    poly.push_back(p);
  }
  if (poly.size() >= 2 && poly.front() == poly.back())
  {
    poly.pop_back();  // tolerate an explicitly closed ring
  }
  if (poly.size() < 3)
  {
    detail::failFile(path, "'verts' has " + std::to_string(poly.size()) +
                               " distinct vertices; a floor-plan polygon needs at least 3");
  }
  return poly;
}

/// Twice the signed area (positive when counter-clockwise).
double signedArea2(const std::vector<Eigen::Vector2d>& poly)
{
  double a = 0;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
  {
    a += poly[j].x() * poly[i].y() - poly[i].x() * poly[j].y();
  }
  return a;
}

/// One vertical quad per polygon edge, facing the free space (the inside).
void extrudeWalls(const std::vector<Eigen::Vector2d>& poly, float height, TriangleMesh& mesh)
{
  const bool ccw = signedArea2(poly) > 0;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    // For a counter-clockwise polygon the inside is on the left of a -> b; the
    // quad (b, a, a', b') then has its normal pointing left, into free space.
    const Eigen::Vector2f a = poly[ccw ? (i + 1) % n : i].cast<float>();
    const Eigen::Vector2f b = poly[ccw ? i : (i + 1) % n].cast<float>();
    mesh.addQuad({a.x(), a.y(), 0.0f}, {b.x(), b.y(), 0.0f}, {b.x(), b.y(), height},
                 {a.x(), a.y(), height});
  }
}
}  // namespace

World loadFloorPlan(const std::string& path, const WorldLoadOptions& opts)
{
  return parseFloorPlan(detail::readTextFile(path), path, opts);
}

World parseFloorPlan(const std::string& text, const std::string& path, const WorldLoadOptions& opts)
{
  if (!(opts.wall_height_m > 0) || !std::isfinite(opts.wall_height_m))
  {
    detail::failFile(path, "wall height must be > 0, got " + std::to_string(opts.wall_height_m));
  }
  const json doc = detail::parseJsonText(text, path);
  World world;
  world.name = std::filesystem::path(path).stem().string();
  world.source_path = path;
  auto poly = readPolygon(doc, path);
  extrudeWalls(poly, static_cast<float>(opts.wall_height_m), world.mesh);
  world.free_space_outlines.push_back(std::move(poly));
  if (opts.add_ground_plane)
  {
    addGroundPlane(world, opts.ground_margin_m);
  }
  return world;
}

}  // namespace voxplore::sim
