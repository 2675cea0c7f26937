/* voxplore — procedural buildings: furniture against room walls and desk
 * islands in the open-plan hall, never in a door's approach. */

#include <algorithm>

#include "worldgen_internal.h"

namespace voxplore::sim::worldgen_detail
{
namespace
{
/// Everything stands within this distance of its wall, so that the middle of
/// every room stays free and joins its door's approach [m].
constexpr double kWallBand = 0.95;
/// Gap between an item and its wall, and between two items [m].
constexpr double kWallGap = 0.02, kItemGap = 0.10;
/// A door's approach kept free: this far past each jamb and into the room [m].
constexpr double kDoorSide = 0.45, kDoorDepth = 1.6;

/// A room seen from its door wall: u along that wall, v into the room.
struct RoomFrame
{
  Rect2 in;        ///< interior (walls' faces), world
  char side = 'S'; ///< which wall holds the door: S, N, W or E
  double U = 0, V = 0;

  Eigen::Vector2d world(double u, double v) const
  {
    switch (side)
    {
      case 'N': return {in.x1 - u, in.y1 - v};
      case 'W': return {in.x0 + v, in.y1 - u};
      case 'E': return {in.x1 - v, in.y0 + u};
      default: return {in.x0 + u, in.y0 + v};
    }
  }
  Rect2 world(const Rect2& local) const
  {
    const Eigen::Vector2d a = world(local.x0, local.y0), b = world(local.x1, local.y1);
    return {std::min(a.x(), b.x()), std::min(a.y(), b.y()), std::max(a.x(), b.x()),
            std::max(a.y(), b.y())};
  }
  /// World heading [deg] of the local direction at angle `local_deg` from +u.
  double heading(double local_deg) const
  {
    const double base = side == 'N' ? 180.0 : side == 'W' ? -90.0 : side == 'E' ? 90.0 : 0.0;
    double h = base + local_deg;
    while (h > 180.0) h -= 360.0;
    while (h <= -180.0) h += 360.0;
    return h;
  }
};

RoomFrame frameOf(const GenRegion& r, const GeneratedBuilding& b, double t)
{
  const Rect2& q = r.rects.front();
  RoomFrame f;
  f.in = {q.x0 + 0.5 * t, q.y0 + 0.5 * t, q.x1 - 0.5 * t, q.y1 - 0.5 * t};
  for (const GenDoor& d : b.doors)
  {
    if (d.region_a != r.id && d.region_b != r.id) continue;
    if (d.along_x) f.side = std::abs(d.center.y() - q.y0) < 1e-6 ? 'S' : 'N';
    else f.side = std::abs(d.center.x() - q.x0) < 1e-6 ? 'W' : 'E';
    break;
  }
  const bool ns = f.side == 'S' || f.side == 'N';
  f.U = ns ? f.in.width() : f.in.height();
  f.V = ns ? f.in.height() : f.in.width();
  return f;
}

/// World rectangles that furniture must keep out of: every door's approach.
std::vector<Rect2> doorZones(const GeneratedBuilding& b)
{
  std::vector<Rect2> z;
  for (const GenDoor& d : b.doors)
  {
    const double a = 0.5 * d.width_m + kDoorSide;
    z.push_back(d.along_x ? Rect2{d.center.x() - a, d.center.y() - kDoorDepth, d.center.x() + a,
                                  d.center.y() + kDoorDepth}
                          : Rect2{d.center.x() - kDoorDepth, d.center.y() - a,
                                  d.center.x() + kDoorDepth, d.center.y() + a});
  }
  return z;
}

class RoomFurnisher
{
 public:
  RoomFurnisher(const RoomFrame& f, const std::vector<Rect2>& zones, const std::string& name,
                std::vector<GenItem>& out)
      : f_(f), zones_(zones), name_(name), out_(out)
  {
  }

  /// Tries to place one item of along-wall length `a` and depth `d` (plus
  /// `chair_depth` in front for a chair) against a random wall.
  bool place(Rng& rng, const std::string& type, double a, double d, double h, bool chair)
  {
    for (int attempt = 0; attempt < 25; attempt++)
    {
      // wall 0: the door wall, 1: the far wall, 2 / 3: the side walls (u = 0 / u = U)
      const int wall = std::min(3, static_cast<int>(rng.uniform(0, 4)));
      const double len = wall < 2 ? f_.U : f_.V;
      if (len < a + 2 * kWallGap) continue;
      const double p = rng.uniform(kWallGap, len - a - kWallGap);
      const double reach = d + (chair ? 0.15 : 0.0);  // the chair stands out of the desk this much
      Rect2 body, all;
      double normal_deg = 0;  // local heading of the wall's inward normal
      switch (wall)
      {
        case 0: body = {p, kWallGap, p + a, kWallGap + d}; all = {p, kWallGap, p + a, kWallGap + reach}; normal_deg = 90; break;
        case 1: body = {p, f_.V - kWallGap - d, p + a, f_.V - kWallGap}; all = {p, f_.V - kWallGap - reach, p + a, f_.V - kWallGap}; normal_deg = -90; break;
        case 2: body = {kWallGap, p, kWallGap + d, p + a}; all = {kWallGap, p, kWallGap + reach, p + a}; normal_deg = 0; break;
        default: body = {f_.U - kWallGap - d, p, f_.U - kWallGap, p + a}; all = {f_.U - kWallGap - reach, p, f_.U - kWallGap, p + a}; normal_deg = 180; break;
      }
      if (reach + kWallGap > kWallBand) return false;
      const Rect2 w_all = f_.world(all);
      if (!free(w_all)) continue;
      const Rect2 w_body = f_.world(body);
      GenItem it;
      it.type = type;
      it.label = name_ + " " + (type == "box" ? (h > 1.7 ? "shelf" : "cabinet") : (chair ? "desk" : "side table"));
      it.center = w_body.center();
      it.size = {w_body.width(), w_body.height()};
      it.height_m = h;
      out_.push_back(it);
      if (chair)
      {
        // In front of the desk's middle, pushed in, facing the wall.
        const double m = 0.5 * (p + p + a), off = kWallGap + d - 0.1;
        const Eigen::Vector2d c = wall == 0   ? f_.world(m, off)
                                  : wall == 1 ? f_.world(m, f_.V - off)
                                  : wall == 2 ? f_.world(off, m)
                                              : f_.world(f_.U - off, m);
        GenItem ch;
        ch.type = "chair";
        ch.label = name_ + " chair";
        ch.center = c;
        ch.yaw_deg = f_.heading(normal_deg + 180.0);
        out_.push_back(ch);
      }
      taken_.push_back(w_all);
      return true;
    }
    return false;
  }

 private:
  bool free(const Rect2& r) const
  {
    for (const Rect2& z : zones_)
      if (overlaps(r, z)) return false;
    for (const Rect2& q : taken_)
      if (overlaps(r, q, kItemGap)) return false;
    return true;
  }

  const RoomFrame& f_;
  const std::vector<Rect2>& zones_;
  std::string name_;
  std::vector<GenItem>& out_;
  std::vector<Rect2> taken_;
};

void furnishRoom(const RoomFrame& f, const std::vector<Rect2>& zones, const std::string& name,
                 double density, Rng& rng, std::vector<GenItem>& out)
{
  RoomFurnisher fu(f, zones, name, out);
  const int n = static_cast<int>(std::lround(density * (1.0 + f.U * f.V / 10.0)));
  for (int i = 0; i < n; i++)
  {
    const double k = rng.uniform(0, 1);
    if (k < 0.4)
      fu.place(rng, "table", rng.uniform(1.2, 1.6), rng.uniform(0.6, 0.8), rng.uniform(0.72, 0.76),
               rng.chance(0.8));
    else if (k < 0.6)
      fu.place(rng, "box", rng.uniform(0.8, 2.0), rng.uniform(0.4, 0.6), rng.uniform(1.0, 1.6), false);
    else if (k < 0.8)
      fu.place(rng, "box", rng.uniform(0.8, 1.8), rng.uniform(0.3, 0.4), rng.uniform(1.8, 2.2), false);
    else
      fu.place(rng, "table", rng.uniform(0.6, 1.0), rng.uniform(0.6, 0.9), 0.72, false);
  }
}

/// Desk islands (two desks back to back, four chairs) on a grid with aisles
/// wide enough for the omniRob's planner circle, and cabinets on the far wall.
void furnishHall(const GenRegion& r, const std::vector<Rect2>& zones, double t, double density,
                 Rng& rng, std::vector<GenItem>& out)
{
  const Rect2& q = r.rects.front();
  const Rect2 in{q.x0 + 0.5 * t, q.y0 + 0.5 * t, q.x1 - 0.5 * t, q.y1 - 0.5 * t};
  constexpr double kAisle = 1.9, kMargin = 2.0, kHalfX = 0.8, kHalfY = 1.125;
  const double px = 2 * kHalfX + kAisle, py = 2 * kHalfY + kAisle;
  const int nx = static_cast<int>((in.width() - 2 * kMargin + kAisle) / px);
  const int ny = static_cast<int>((in.height() - 2 * kMargin + kAisle) / py);
  const double x0 = in.center().x() - 0.5 * (nx * px - kAisle) + kHalfX;
  const double y0 = in.center().y() - 0.5 * (ny * py - kAisle) + kHalfY;
  for (int j = 0; j < ny; j++)
    for (int i = 0; i < nx; i++)
    {
      if (!rng.chance(std::min(1.0, 0.75 * density))) continue;
      const Eigen::Vector2d c(x0 + i * px, y0 + j * py);
      const Rect2 all{c.x() - kHalfX, c.y() - kHalfY, c.x() + kHalfX, c.y() + kHalfY};
      if (std::any_of(zones.begin(), zones.end(), [&](const Rect2& z) { return overlaps(all, z); }))
        continue;
      const std::string name = r.name + " island " + std::to_string(j * nx + i + 1);
      for (const double s : {-1.0, 1.0})
      {
        GenItem desk;
        desk.type = "table";
        desk.label = name + " desk";
        desk.center = c + Eigen::Vector2d(0, s * 0.4);
        desk.size = {1.6, 0.8};
        desk.height_m = 0.74;
        out.push_back(desk);
        for (const double dx : {-0.4, 0.4})
        {
          GenItem ch;
          ch.type = "chair";
          ch.label = name + " chair";
          ch.center = c + Eigen::Vector2d(dx, s * 0.9);
          ch.yaw_deg = s > 0 ? -90.0 : 90.0;  // facing the island
          out.push_back(ch);
        }
      }
    }
  // A row of cabinets along the hall's south wall, clear of the islands' margin.
  for (double x = in.x0 + 0.5; x + 1.2 < in.x1 - 0.5; x += 3.0)
  {
    const Rect2 box{x, in.y0 + kWallGap, x + 1.2, in.y0 + kWallGap + 0.5};
    if (std::any_of(zones.begin(), zones.end(), [&](const Rect2& z) { return overlaps(box, z); }))
      continue;
    if (!rng.chance(0.5 * density)) continue;
    GenItem it;
    it.type = "box";
    it.label = r.name + " cabinet";
    it.center = box.center();
    it.size = {box.width(), box.height()};
    it.height_m = rng.uniform(1.0, 2.0);
    out.push_back(it);
  }
}

}  // namespace

void furnish(GeneratedBuilding& b, Rng& rng)
{
  const double t = snap(b.params.wall_thickness_m);
  const std::vector<Rect2> zones = doorZones(b);
  const uint64_t alike_seed = rng.next();
  for (const GenRegion& r : b.regions)
  {
    if (r.kind == GenRegion::Kind::Hall)
      furnishHall(r, zones, t, b.params.furniture_density, rng, b.items);
    if (r.kind != GenRegion::Kind::Room) continue;
    // Look-alike rooms draw their furniture from one seed, in the frame of their door wall.
    Rng room_rng(b.params.look_alike_rooms ? alike_seed : rng.next());
    furnishRoom(frameOf(r, b, t), zones, r.name, b.params.furniture_density, room_rng, b.items);
  }
}

}  // namespace voxplore::sim::worldgen_detail
