/* voxplore — `.world` files: JSON composing meshes, floor plans and primitives
 * (format in world_loading.h). Every error names the file and the element. */

#include <mrpt/core/bits_math.h>
#include <voxplore/sim/world_loading.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>

#include "json_file.h"

namespace voxplore::sim
{
namespace
{
using detail::Fields;
using detail::Where;
using nlohmann::json;

// Default wall and furniture dimensions (m).
constexpr double kWallThickness = 0.15;
constexpr double kWallHeight = 2.5;
constexpr double kTableHeight = 0.75;
constexpr float kTableTopThickness = 0.04f;
constexpr float kTableLegSize = 0.05f;
constexpr float kTableLegInset = 0.05f;  // from the top's corner to the leg's outer faces
constexpr float kChairSeatSize = 0.45f;
constexpr float kChairSeatHeight = 0.45f;  // top of the seat
constexpr float kChairSeatThickness = 0.04f;
constexpr float kChairLegSize = 0.04f;
constexpr float kChairBackThickness = 0.04f;
constexpr float kChairBackTop = 0.90f;

/// Adds a box to the mesh and to the analytic solids.
void addSolidBox(World& world, const Eigen::Vector3f& center, const Eigen::Vector3f& size,
                 float yaw)
{
  world.mesh.addBox(center, size, yaw);
  Solid s;
  s.kind = Solid::Kind::Box;
  s.center = center;
  s.size = size;
  s.yaw_rad = yaw;
  world.solids.push_back(s);
}

/// A point given in an object's frame (origin `center_xy`, rotated by `yaw`) in world XY.
Eigen::Vector2f toWorld(const Eigen::Vector2f& center_xy, float yaw, const Eigen::Vector2f& local)
{
  return center_xy + Eigen::Rotation2Df(yaw) * local;
}

/// Four square legs from the floor to `top_z`, inset `inset` from the corners of sx x sy.
void addLegs(World& world, const Eigen::Vector2f& c, float yaw, const Eigen::Vector2f& size,
             float leg, float inset, float top_z)
{
  const Eigen::Vector2f off = 0.5f * size - Eigen::Vector2f::Constant(inset + 0.5f * leg);
  for (const float sx : {-1.0f, 1.0f})
  {
    for (const float sy : {-1.0f, 1.0f})
    {
      const Eigen::Vector2f p = toWorld(c, yaw, {sx * off.x(), sy * off.y()});
      addSolidBox(world, {p.x(), p.y(), 0.5f * top_z}, {leg, leg, top_z}, yaw);
    }
  }
}

void loadMeshElement(const Fields& f, const std::filesystem::path& dir, World& world)
{
  f.requireKnownKeys({"type", "label", "file", "translation", "yaw_deg", "scale"});
  const std::filesystem::path file = dir / f.string("file");
  const Eigen::Vector3f t = f.vector<3>("translation", Eigen::Vector3f::Zero());
  const auto yaw = static_cast<float>(mrpt::DEG2RAD(f.number("yaw_deg", 0.0)));
  const auto scale = static_cast<float>(f.positive("scale", 1.0));
  TriangleMesh mesh;
  try
  {
    mesh = loadMeshFile(file.string());
  }
  catch (const std::runtime_error& e)
  {
    f.where().fail(e.what());
  }
  Eigen::Isometry3f T = Eigen::Isometry3f::Identity();
  T.translate(t);
  T.rotate(Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()));
  world.mesh.append(mesh, T, scale);
}

void loadFloorPlanElement(const Fields& f, const std::filesystem::path& dir,
                          const WorldLoadOptions& opts, World& world)
{
  f.requireKnownKeys({"type", "label", "file", "wall_height"});
  WorldLoadOptions plan_opts = opts;
  plan_opts.add_ground_plane = false;
  plan_opts.wall_height_m = f.positive("wall_height", opts.wall_height_m);
  World plan;
  try
  {
    plan = loadFloorPlan((dir / f.string("file")).string(), plan_opts);
  }
  catch (const std::runtime_error& e)
  {
    f.where().fail(e.what());
  }
  world.mesh.append(plan.mesh);
  for (auto& outline : plan.free_space_outlines)
  {
    world.free_space_outlines.push_back(std::move(outline));
  }
}

void loadBoxElement(const Fields& f, World& world)
{
  f.requireKnownKeys({"type", "label", "center", "size", "yaw_deg"});
  const Eigen::Vector3f size = f.vector<3>("size");
  if (!(size.minCoeff() > 0))
  {
    f.where().fail("every entry of 'size' must be > 0");
  }
  addSolidBox(world, f.vector<3>("center"), size,
              static_cast<float>(mrpt::DEG2RAD(f.number("yaw_deg", 0.0))));
}

void loadCylinderElement(const Fields& f, World& world)
{
  f.requireKnownKeys({"type", "label", "center", "radius", "z"});
  const Eigen::Vector2f c = f.vector<2>("center");
  const auto r = static_cast<float>(f.positive("radius"));
  const Eigen::Vector2f z = f.vector<2>("z");
  if (!(z[1] > z[0]))
  {
    f.where().fail("field 'z' must be [z0, z1] with z1 > z0");
  }
  world.mesh.addCylinder(c, r, z[0], z[1]);
  Solid s;
  s.kind = Solid::Kind::Cylinder;
  s.center = {c.x(), c.y(), 0.5f * (z[0] + z[1])};
  s.size = {2 * r, 2 * r, z[1] - z[0]};
  world.solids.push_back(s);
}

void loadWallElement(const Fields& f, World& world)
{
  f.requireKnownKeys({"type", "label", "from", "to", "thickness", "height"});
  const Eigen::Vector2f a = f.vector<2>("from");
  const Eigen::Vector2f b = f.vector<2>("to");
  const auto thickness = static_cast<float>(f.positive("thickness", kWallThickness));
  const auto height = static_cast<float>(f.positive("height", kWallHeight));
  const Eigen::Vector2f d = b - a;
  if (!(d.norm() > 0))
  {
    f.where().fail("'from' and 'to' must differ");
  }
  const Eigen::Vector2f mid = 0.5f * (a + b);
  addSolidBox(world, {mid.x(), mid.y(), 0.5f * height}, {d.norm(), thickness, height},
              std::atan2(d.y(), d.x()));
}

void loadTableElement(const Fields& f, World& world)
{
  f.requireKnownKeys({"type", "label", "center", "size", "height", "yaw_deg"});
  const Eigen::Vector2f c = f.vector<2>("center");
  const Eigen::Vector2f size = f.vector<2>("size");
  const auto height = static_cast<float>(f.positive("height", kTableHeight));
  const auto yaw = static_cast<float>(mrpt::DEG2RAD(f.number("yaw_deg", 0.0)));
  const float min_side = 2 * (kTableLegInset + kTableLegSize);
  if (!(size.minCoeff() > min_side))
  {
    f.where().fail("every entry of 'size' must be > " + std::to_string(min_side) + " m");
  }
  if (!(height > kTableTopThickness))
  {
    f.where().fail("'height' must exceed the top's thickness " +
                   std::to_string(kTableTopThickness));
  }
  addSolidBox(world, {c.x(), c.y(), height - 0.5f * kTableTopThickness},
              {size.x(), size.y(), kTableTopThickness}, yaw);
  addLegs(world, c, yaw, size, kTableLegSize, kTableLegInset, height - kTableTopThickness);
}

void loadChairElement(const Fields& f, World& world)
{
  f.requireKnownKeys({"type", "label", "center", "yaw_deg"});
  const Eigen::Vector2f c = f.vector<2>("center");
  const auto yaw = static_cast<float>(mrpt::DEG2RAD(f.number("yaw_deg", 0.0)));
  const float seat_bottom = kChairSeatHeight - kChairSeatThickness;
  addSolidBox(world, {c.x(), c.y(), kChairSeatHeight - 0.5f * kChairSeatThickness},
              {kChairSeatSize, kChairSeatSize, kChairSeatThickness}, yaw);
  addLegs(world, c, yaw, Eigen::Vector2f::Constant(kChairSeatSize), kChairLegSize, 0.0f,
          seat_bottom);
  // Backrest on the chair's -X side, from the seat up to kChairBackTop.
  const Eigen::Vector2f back =
      toWorld(c, yaw, {-0.5f * kChairSeatSize + 0.5f * kChairBackThickness, 0.0f});
  const float back_h = kChairBackTop - kChairSeatHeight;
  addSolidBox(world, {back.x(), back.y(), kChairSeatHeight + 0.5f * back_h},
              {kChairBackThickness, kChairSeatSize, back_h}, yaw);
}

void loadElement(const json& element, std::size_t index, const std::string& path,
                 const std::filesystem::path& dir, const WorldLoadOptions& opts, World& world)
{
  const std::string at = "elements[" + std::to_string(index) + "]";
  if (!element.is_object())
  {
    detail::failFile(path, at + ": must be a JSON object, got " + element.dump());
  }
  const Fields typed(element, Where{path, at});
  const std::string type = typed.string("type");
  const Fields f(element, Where{path, at + " (" + type + ")"});
  using Loader = std::function<void(const Fields&)>;
  const std::map<std::string, Loader> loaders = {
      {"mesh", [&](const Fields& x) { loadMeshElement(x, dir, world); }},
      {"floorplan", [&](const Fields& x) { loadFloorPlanElement(x, dir, opts, world); }},
      {"box", [&](const Fields& x) { loadBoxElement(x, world); }},
      {"cylinder", [&](const Fields& x) { loadCylinderElement(x, world); }},
      {"wall", [&](const Fields& x) { loadWallElement(x, world); }},
      {"table", [&](const Fields& x) { loadTableElement(x, world); }},
      {"chair", [&](const Fields& x) { loadChairElement(x, world); }},
  };
  const auto it = loaders.find(type);
  if (it == loaders.end())
  {
    std::string known;
    for (const auto& entry : loaders)
    {
      known += (known.empty() ? "" : ", ") + entry.first;
    }
    f.where().fail("unknown element type '" + type + "' (known: " + known + ")");
  }
  const std::size_t first_vertex = world.mesh.vertices.size();
  it->second(f);
  // A number beyond float range (e.g. "radius": 1e300) gives infinite vertices
  // (found by fuzz/fuzz_world_file).
  for (std::size_t v = first_vertex; v < world.mesh.vertices.size(); ++v)
  {
    if (!world.mesh.vertices[v].allFinite())
    {
      f.where().fail("the element's geometry is not finite (a number beyond float range, |x| > " +
                     std::to_string(std::numeric_limits<float>::max()) + "?)");
    }
  }
}

mrpt::poses::CPose2D readStart(const json& doc, const std::string& path)
{
  if (!doc.contains("start"))
  {
    return mrpt::poses::CPose2D(0, 0, 0);
  }
  if (!doc.at("start").is_object())
  {
    detail::failFile(path, "field 'start' must be an object {\"x\", \"y\", \"yaw_deg\"}");
  }
  const Fields f(doc.at("start"), Where{path, "start"});
  f.requireKnownKeys({"x", "y", "yaw_deg"});
  return mrpt::poses::CPose2D(f.number("x"), f.number("y"),
                              mrpt::DEG2RAD(f.number("yaw_deg", 0.0)));
}
}  // namespace

World loadWorldFile(const std::string& path, const WorldLoadOptions& opts)
{
  return parseWorldFile(detail::readTextFile(path), path, opts);
}

World parseWorldFile(const std::string& text, const std::string& path, const WorldLoadOptions& opts)
{
  const json doc = detail::parseJsonText(text, path);
  if (!doc.is_object())
  {
    detail::failFile(path, "a world file must be a JSON object with an 'elements' array");
  }
  const Fields top(doc, Where{path, ""});
  top.requireKnownKeys({"name", "description", "start", "ground_plane", "elements"});
  if (top.has("name"))
  {
    top.string("name");  // type check only: World::name is the file stem
  }
  if (top.has("description"))
  {
    top.string("description");
  }
  const json& elements = top.required("elements");
  if (!elements.is_array())
  {
    detail::failFile(path, "field 'elements' must be an array");
  }

  World world;
  world.name = std::filesystem::path(path).stem().string();
  world.source_path = path;
  world.start = readStart(doc, path);
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  for (std::size_t i = 0; i < elements.size(); ++i)
  {
    loadElement(elements[i], i, path, dir, opts, world);
  }
  if (world.mesh.empty())
  {
    detail::failFile(path, "the world has no geometry (no element produced triangles)");
  }
  if (top.boolean("ground_plane", true))
  {
    addGroundPlane(world, opts.ground_margin_m);
  }
  return world;
}

}  // namespace voxplore::sim
