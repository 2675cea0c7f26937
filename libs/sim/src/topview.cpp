/* voxplore — a top-view PNG of a world, optionally with a trajectory.
 *
 * Each pixel casts a ray straight down from above the world for the top
 * surface: floor (light), an obstacle up to robot height (grey, darker =
 * taller), or structure above the robot (blue: table tops, overhangs, tops of
 * tall walls). Under a blue top, a second ray from robot height down to floor
 * height looks for what the robot would hit there (grey). Vertical faces,
 * which downward rays cannot hit, are drawn as their projected segments, grey
 * when they reach into the robot's height band: tall walls show as grey
 * outlines around a blue top, tables as grey legs under a blue top. */

#include <mrpt/img/CImage.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/ground_truth.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace voxplore::sim
{
namespace
{
using mrpt::img::TColor;

constexpr double kFloorHeight_m = 0.03;  ///< top surfaces below this are floor
constexpr double kMaxPixels = 200e6;     ///< refuse absurd image sizes

/// Pixel <-> world mapping; image row 0 is the northern (max y) border.
struct PixelFrame
{
  double min_x, max_y, px_per_m;
  int width, height;

  Eigen::Vector2d world(int u, int v) const
  {
    return {min_x + (u + 0.5) / px_per_m, max_y - (v + 0.5) / px_per_m};
  }
  double uf(double x) const { return (x - min_x) * px_per_m; }
  double vf(double y) const { return (max_y - y) * px_per_m; }
  int u(double x) const { return static_cast<int>(std::floor(uf(x))); }
  int v(double y) const { return static_cast<int>(std::floor(vf(y))); }
};

/// What lies below one pixel.
struct TopSample
{
  double top_m = std::numeric_limits<double>::infinity();  ///< +inf: nothing at all
  bool blocks = false;  ///< geometry between floor height and robot height
};

TColor sampleColour(const TopSample& s, double robot_height_m)
{
  if (!std::isfinite(s.top_m)) return TColor(250, 250, 250);
  if (s.top_m < kFloorHeight_m) return TColor(228, 228, 224);
  if (s.blocks || s.top_m <= robot_height_m)
  {  // an obstacle: darker = taller, saturating at robot height
    const double t = (std::min(s.top_m, robot_height_m) - kFloorHeight_m) /
                     std::max(robot_height_m - kFloorHeight_m, 1e-6);
    const auto g = static_cast<uint8_t>(std::lround(150.0 - 120.0 * std::clamp(t, 0.0, 1.0)));
    return TColor(g, g, g);
  }
  // Only structure above the robot: blue, lighter higher up.
  const double t = std::clamp((s.top_m - robot_height_m) / 2.0, 0.0, 1.0);
  return TColor(static_cast<uint8_t>(80 + 70 * t), static_cast<uint8_t>(110 + 70 * t),
                static_cast<uint8_t>(190 + 50 * t));
}

/// Per pixel (row-major): the top surface, and for tops above the robot a
/// second ray from robot height down to floor height to find what blocks.
std::vector<TopSample> castSamples(const RayCaster& caster, float top_z, const PixelFrame& f,
                                   double robot_height_m)
{
  std::vector<TopSample> out(static_cast<std::size_t>(f.width) * f.height);
  const Eigen::Vector3f down(0.0f, 0.0f, -1.0f);
  const auto band = static_cast<float>(robot_height_m - kFloorHeight_m);
  for (int v = 0; v < f.height; ++v)
  {
    for (int u = 0; u < f.width; ++u)
    {
      const Eigen::Vector2d p = f.world(u, v);
      const Eigen::Vector3f origin(static_cast<float>(p.x()), static_cast<float>(p.y()), top_z);
      const float t = caster.cast(origin, down);
      if (!std::isfinite(t)) continue;
      TopSample& s = out[static_cast<std::size_t>(v) * f.width + u];
      s.top_m = double(top_z) - double(t);
      s.blocks = s.top_m >= kFloorHeight_m && s.top_m <= robot_height_m;
      if (s.top_m > robot_height_m && band > 0)
      {
        const Eigen::Vector3f low(origin.x(), origin.y(), static_cast<float>(robot_height_m));
        s.blocks = std::isfinite(caster.cast(low, down, 0.0f, band));
      }
    }
  }
  return out;
}

/// End points of a vertical (flat in XY) triangle's projection: the farthest pair.
std::array<Eigen::Vector2d, 2> projectedSegment(const std::array<Eigen::Vector3d, 3>& p)
{
  std::size_t i0 = 0, i1 = 1;
  for (const std::size_t i : {std::size_t{1}, std::size_t{2}})
  {
    const std::size_t j = (i + 1) % 3;
    if ((p[i] - p[j]).head<2>().squaredNorm() > (p[i0] - p[i1]).head<2>().squaredNorm())
    {
      i0 = i;
      i1 = j;
    }
  }
  return {p[i0].head<2>(), p[i1].head<2>()};
}

/// Vertical triangles (zero-thickness walls, e.g. extruded floor plans) are
/// parallel to the downward rays and never hit: draw their projected segment.
void addVerticalTriangles(const TriangleMesh& mesh, const PixelFrame& f, double robot_height_m,
                          std::vector<TopSample>& samples)
{
  for (const Eigen::Vector3i& t : mesh.triangles)
  {
    const std::array<Eigen::Vector3d, 3> p{mesh.vertices[t[0]].cast<double>(),
                                           mesh.vertices[t[1]].cast<double>(),
                                           mesh.vertices[t[2]].cast<double>()};
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    if (!(std::abs(n.z()) <= 1e-3 * n.norm())) continue;  // not vertical, or degenerate
    const double z_top = std::max({p[0].z(), p[1].z(), p[2].z()});
    const double z_bottom = std::min({p[0].z(), p[1].z(), p[2].z()});
    if (z_top < kFloorHeight_m) continue;
    const bool blocks = z_bottom <= robot_height_m;
    const auto [a, b] = projectedSegment(p);
    const Eigen::Vector2d u0(f.uf(a.x()), f.vf(a.y())), u1(f.uf(b.x()), f.vf(b.y()));
    const int steps = static_cast<int>(std::ceil(2.0 * (u1 - u0).lpNorm<Eigen::Infinity>())) + 1;
    for (int k = 0; k <= steps; ++k)
    {
      const Eigen::Vector2d q = u0 + (u1 - u0) * (double(k) / steps);
      const int u = std::clamp(static_cast<int>(std::floor(q.x())), 0, f.width - 1);
      const int v = std::clamp(static_cast<int>(std::floor(q.y())), 0, f.height - 1);
      TopSample& s = samples[static_cast<std::size_t>(v) * f.width + u];
      if (!std::isfinite(s.top_m) || s.top_m < z_top) s.top_m = z_top;
      s.blocks = s.blocks || blocks;
    }
  }
}

void drawTrajectory(const std::vector<mrpt::poses::CPose2D>& poses, const PixelFrame& f,
                    mrpt::img::CImage& img)
{
  if (poses.empty()) return;
  const TColor red(220, 30, 30), green(20, 170, 40);
  const auto line_w = static_cast<unsigned int>(std::max(1.0, f.px_per_m / 40.0));
  const int dot = static_cast<int>(std::max(1.0, f.px_per_m / 30.0));
  for (std::size_t i = 0; i + 1 < poses.size(); ++i)
  {
    img.line(f.u(poses[i].x()), f.v(poses[i].y()), f.u(poses[i + 1].x()), f.v(poses[i + 1].y()),
             red, line_w);
  }
  for (const auto& p : poses)
  {
    const int u = f.u(p.x()), v = f.v(p.y());
    img.filledRectangle(u - dot, v - dot, u + dot, v + dot, red);
  }
  // Start: a green circle with a tick along the heading (image v points south).
  const auto& s = poses.front();
  const int u = f.u(s.x()), v = f.v(s.y());
  const int radius = static_cast<int>(std::max(4.0, 0.25 * f.px_per_m));
  img.drawCircle(u, v, radius, green, 2);
  const double tick = 1.8 * radius;
  img.line(u, v, u + static_cast<int>(std::lround(tick * std::cos(s.phi()))),
           v - static_cast<int>(std::lround(tick * std::sin(s.phi()))), green, 2);
}

}  // namespace

void writeTopView(const World& world, const RayCaster& caster, const std::string& png_path,
                  double px_per_m, const std::vector<mrpt::poses::CPose2D>& trajectory,
                  double robot_height_m)
{
  const auto fail = [&](const std::string& why)
  { throw std::runtime_error("writeTopView: cannot write '" + png_path + "': " + why); };
  if (world.mesh.empty()) fail("the world has no geometry");
  if (!(px_per_m > 0)) fail("px_per_m must be > 0");
  const Eigen::AlignedBox3f b = world.mesh.bounds();
  const double w = std::max(1.0, std::ceil((double(b.max().x()) - b.min().x()) * px_per_m - 1e-6));
  const double h = std::max(1.0, std::ceil((double(b.max().y()) - b.min().y()) * px_per_m - 1e-6));
  if (w * h > kMaxPixels)
    fail("image too large (" + std::to_string(w) + " x " + std::to_string(h) + " px)");

  const PixelFrame f{b.min().x(), b.max().y(), px_per_m, static_cast<int>(w), static_cast<int>(h)};
  std::vector<TopSample> samples = castSamples(caster, b.max().z() + 1.0f, f, robot_height_m);
  addVerticalTriangles(world.mesh, f, robot_height_m, samples);
  mrpt::img::CImage img(static_cast<unsigned int>(f.width), static_cast<unsigned int>(f.height),
                        mrpt::img::CH_RGB);
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u)
      img.setPixel(
          u, v, sampleColour(samples[static_cast<std::size_t>(v) * f.width + u], robot_height_m));
  drawTrajectory(trajectory, f, img);

  bool ok = false;
  try
  {
    ok = img.saveToFile(png_path);
  }
  catch (const std::exception& e)
  {
    fail(e.what());
  }
  if (!ok) fail("saving the image failed (missing folder or no permission?)");
}

}  // namespace voxplore::sim
