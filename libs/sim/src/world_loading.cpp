/* voxplore — loading worlds: dispatch by extension, meshes via assimp, ground
 * plane and start-pose parsing. World files: world_file.cpp; HouseExpo floor
 * plans: floor_plan.cpp. */

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <mrpt/core/bits_math.h>
#include <voxplore/sim/world_loading.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "json_file.h"

namespace voxplore::sim
{
namespace
{
std::string lowercase(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trim(const std::string& s)
{
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos)
  {
    return {};
  }
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

/// Parses a whole token as a finite double; false when it is not one.
bool parseFiniteDouble(const std::string& token, double& value)
{
  const std::string t = trim(token);
  if (t.empty())
  {
    return false;
  }
  try
  {
    std::size_t used = 0;
    value = std::stod(t, &used);
    return used == t.size() && std::isfinite(value);
  }
  catch (const std::exception&)
  {
    return false;
  }
}

/// Copies the triangles of all meshes of an assimp scene (already
/// pre-transformed into one frame) into `out`.
void copyTriangles(const aiScene& scene, TriangleMesh& out)
{
  for (unsigned m = 0; m < scene.mNumMeshes; ++m)
  {
    const aiMesh& mesh = *scene.mMeshes[m];
    const int offset = static_cast<int>(out.vertices.size());
    out.vertices.reserve(out.vertices.size() + mesh.mNumVertices);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v)
    {
      const aiVector3D& p = mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f)
    {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3)
      {
        continue;  // points and lines carry no surface
      }
      out.triangles.emplace_back(offset + static_cast<int>(face.mIndices[0]),
                                 offset + static_cast<int>(face.mIndices[1]),
                                 offset + static_cast<int>(face.mIndices[2]));
    }
  }
}
}  // namespace

World loadWorld(const std::string& path, const std::optional<mrpt::poses::CPose2D>& start,
                const WorldLoadOptions& opts)
{
  const std::string ext = lowercase(std::filesystem::path(path).extension().string());
  World world;
  if (ext == ".world")
  {
    world = loadWorldFile(path, opts);
    if (start)
    {
      world.start = *start;
    }
    return world;
  }
  if (ext == ".json")
  {
    world = loadFloorPlan(path, opts);
  }
  else
  {
    world.name = std::filesystem::path(path).stem().string();
    world.source_path = path;
    world.mesh = loadMeshFile(path);
    if (opts.add_ground_plane)
    {
      addGroundPlane(world, opts.ground_margin_m);
    }
  }
  world.start = start.value_or(mrpt::poses::CPose2D(0, 0, 0));
  return world;
}

TriangleMesh loadMeshFile(const std::string& path)
{
  detail::requireNonEmptyFile(path);
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices |
                                  aiProcess_JoinIdenticalVertices);
  if (scene == nullptr)
  {
    detail::failFile(path, std::string("cannot read mesh: ") + importer.GetErrorString());
  }
  TriangleMesh mesh;
  copyTriangles(*scene, mesh);
  if (mesh.empty())
  {
    detail::failFile(path, "mesh contains no triangles");
  }
  const long bad = mesh.firstNonFiniteVertex();
  if (bad >= 0)
  {
    const Eigen::Vector3f& v = mesh.vertices[static_cast<std::size_t>(bad)];
    std::ostringstream os;
    os << "vertex " << bad << " (after loading) is not finite: (" << v.x() << ", " << v.y() << ", "
       << v.z() << ")";
    detail::failFile(path, os.str());
  }
  return mesh;
}

void addGroundPlane(World& world, double margin_m)
{
  Eigen::AlignedBox2d xy;  // empty
  const Eigen::AlignedBox3f b = world.mesh.bounds();
  if (!b.isEmpty())
  {
    xy.extend(b.min().head<2>().cast<double>());
    xy.extend(b.max().head<2>().cast<double>());
  }
  for (const auto& outline : world.free_space_outlines)
  {
    for (const auto& p : outline)
    {
      xy.extend(p);
    }
  }
  if (xy.isEmpty())
  {
    return;  // nothing to put a floor under
  }
  const Eigen::Vector2f lo = (xy.min().array() - margin_m).matrix().cast<float>();
  const Eigen::Vector2f hi = (xy.max().array() + margin_m).matrix().cast<float>();
  // Counter-clockwise seen from above: the floor's normal points up (+Z).
  world.mesh.addQuad({lo.x(), lo.y(), 0.0f}, {hi.x(), lo.y(), 0.0f}, {hi.x(), hi.y(), 0.0f},
                     {lo.x(), hi.y(), 0.0f});
}

mrpt::poses::CPose2D parseStartPose(const std::string& text)
{
  std::vector<std::string> fields;
  std::stringstream ss(text);
  std::string field;
  while (std::getline(ss, field, ','))
  {
    fields.push_back(field);
  }
  if (!text.empty() && text.back() == ',')
  {
    fields.emplace_back();  // a trailing comma leaves an empty, invalid field
  }
  double v[3] = {0, 0, 0};
  bool ok = fields.size() == 2 || fields.size() == 3;
  for (std::size_t i = 0; ok && i < fields.size(); ++i)
  {
    ok = parseFiniteDouble(fields[i], v[i]);
  }
  if (!ok)
  {
    throw std::runtime_error("invalid start pose '" + text +
                             "': expected \"x,y\" or \"x,y,yaw_deg\" (metres, degrees)");
  }
  return mrpt::poses::CPose2D(v[0], v[1], mrpt::DEG2RAD(v[2]));
}

}  // namespace voxplore::sim
