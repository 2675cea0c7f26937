/* voxplore — procedural buildings: parameters, layouts, doors, walls. */

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "worldgen_internal.h"

namespace voxplore::sim
{
namespace
{
using namespace worldgen_detail;

/// A stretch of wall shared by two regions: on the line x = c (vertical) or
/// y = c (along_x), over [lo, hi] of the other coordinate.
struct SharedEdge
{
  bool along_x = true;
  double c = 0, lo = 0, hi = 0;
};

std::vector<SharedEdge> sharedEdges(const GenRegion& a, const GenRegion& b)
{
  constexpr double eps = 1e-6;
  std::vector<SharedEdge> out;
  for (const Rect2& r : a.rects)
    for (const Rect2& q : b.rects)
    {
      for (const auto& [ra, qb] : {std::pair{r.x1, q.x0}, std::pair{r.x0, q.x1}})
        if (std::abs(ra - qb) < eps)
        {
          const double lo = std::max(r.y0, q.y0), hi = std::min(r.y1, q.y1);
          if (hi > lo + eps) out.push_back({false, ra, lo, hi});
        }
      for (const auto& [ra, qb] : {std::pair{r.y1, q.y0}, std::pair{r.y0, q.y1}})
        if (std::abs(ra - qb) < eps)
        {
          const double lo = std::max(r.x0, q.x0), hi = std::min(r.x1, q.x1);
          if (hi > lo + eps) out.push_back({true, ra, lo, hi});
        }
    }
  return out;
}

/// Builds the regions of one layout.
class LayoutBuilder
{
 public:
  LayoutBuilder(const WorldGenParams& p, Rng& rng, GeneratedBuilding& b) : p_(p), rng_(rng), b_(b)
  {
    t_ = snap(p.wall_thickness_m);
    if (p.look_alike_rooms) fixed_room_width_ = regionSize(p.room_width_min_m, p.room_width_max_m);
  }

  /// A region size: a free size drawn in [lo, hi] plus one wall thickness, on the lattice.
  double regionSize(double lo, double hi) { return snap(rng_.uniform(lo, hi) + t_); }
  double corridorWidth() { return regionSize(p_.corridor_width_min_m, p_.corridor_width_max_m); }
  double roomDepth()
  {
    return p_.look_alike_rooms ? snap(0.5 * (p_.room_depth_min_m + p_.room_depth_max_m) + t_)
                               : regionSize(p_.room_depth_min_m, p_.room_depth_max_m);
  }
  double targetArea() { return rng_.uniform(p_.min_floor_m2, p_.max_floor_m2); }
  double clampSide(double v) const { return snap(std::clamp(v, p_.min_side_m, p_.max_side_m)); }

  int add(GenRegion::Kind kind, std::vector<Rect2> rects, const std::string& name)
  {
    GenRegion r;
    r.id = static_cast<int>(b_.regions.size()) + 1;
    r.kind = kind;
    r.rects = std::move(rects);
    r.name = name;
    b_.regions.push_back(std::move(r));
    return b_.regions.back().id;
  }

  /// Splits `band` into rooms along x (along_x) or y. `end_min` is the
  /// smallest width of the first and last room (so that corner rooms reach
  /// their corridor).
  void splitBand(const Rect2& band, bool along_x, const std::string& name, double end_min = 0)
  {
    const double len = along_x ? band.width() : band.height();
    const double wmin = snap(p_.room_width_min_m + t_);
    if (len < wmin - 1e-9) return;  // too short for a room: stays solid
    std::vector<double> widths;
    if (fixed_room_width_ > 0)
    {
      const int n = std::max(1, static_cast<int>(std::floor(len / fixed_room_width_)));
      widths.assign(static_cast<std::size_t>(n), fixed_room_width_);
      widths.back() += snap(len - n * fixed_room_width_);  // the rest joins the last room
    }
    else
    {
      double rest = len;
      while (rest > 1e-9)
      {
        double w = room_width_override_ > 0 ? room_width_override_
                                            : regionSize(p_.room_width_min_m, p_.room_width_max_m);
        if (widths.empty()) w = std::max(w, snap(end_min));
        if (rest - w < std::max(wmin, snap(end_min)) - 1e-9) w = rest;  // no sliver at the end
        widths.push_back(snap(w));
        rest = snap(rest - w);
      }
    }
    double pos = along_x ? band.x0 : band.y0;
    for (std::size_t i = 0; i < widths.size(); i++)
    {
      const double end = (i + 1 == widths.size()) ? (along_x ? band.x1 : band.y1) : pos + widths[i];
      const Rect2 r = along_x ? Rect2{pos, band.y0, end, band.y1} : Rect2{band.x0, pos, band.x1, end};
      add(GenRegion::Kind::Room, {r}, name + " " + std::to_string(i + 1));
      pos = end;
    }
  }

  /// Sets the room width (region size) that gives about `rooms` rooms over
  /// `band_length` metres of room bands (the `rooms` parameter).
  void planRoomCount(double band_length)
  {
    if (p_.rooms > 0 && !p_.look_alike_rooms)
      room_width_override_ = snap(std::max(band_length / p_.rooms, p_.room_width_min_m + t_));
  }

  double t() const { return t_; }

 private:
  const WorldGenParams& p_;
  Rng& rng_;
  GeneratedBuilding& b_;
  double t_ = 0.15;
  double fixed_room_width_ = 0;
  double room_width_override_ = 0;
};

using K = GenRegion::Kind;

void layoutCorridor(LayoutBuilder& lb, const WorldGenParams& p)
{
  const double w = lb.corridorWidth(), ds = lb.roomDepth(), dn = lb.roomDepth();
  const double len = lb.clampSide(lb.targetArea() / (ds + w + dn));
  const double f = snap(p.featureless_corridor_m);
  lb.add(K::Corridor, {{0, ds, len + f, ds + w}}, "corridor");
  lb.planRoomCount(2 * len);
  lb.splitBand({0, 0, len, ds}, true, "south room");
  lb.splitBand({0, ds + w, len, ds + w + dn}, true, "north room");
}

void layoutRing(LayoutBuilder& lb, const WorldGenParams& p, Rng& rng)
{
  const double w = lb.corridorWidth();
  double d = lb.roomDepth();
  const double area = lb.targetArea(), aspect = rng.uniform(1.0, 2.0);
  double h = lb.clampSide(std::sqrt(area / aspect));
  const double inner_min = snap(3.0 + lb.t());
  if (h < 2 * d + 2 * w + inner_min) h = snap(2 * d + 2 * w + inner_min);
  const double wd = lb.clampSide(std::max(area / h, h));
  const double x_in0 = d + w, x_in1 = wd - d - w, y_in0 = d + w, y_in1 = h - d - w;
  lb.add(K::Corridor,
         {{d, d, wd - d, d + w}, {d, h - d - w, wd - d, h - d}, {d, d, d + w, h - d},
          {wd - d - w, d, wd - d, h - d}},
         "ring corridor");
  lb.planRoomCount(2 * wd + 2 * h + 2 * (x_in1 - x_in0));
  const double corner = d + snap(p.room_width_min_m + lb.t());
  lb.splitBand({0, 0, wd, d}, true, "south room", corner);
  lb.splitBand({0, h - d, wd, h}, true, "north room", corner);
  lb.splitBand({0, d, d, h - d}, false, "west room");
  lb.splitBand({wd - d, d, wd, h - d}, false, "east room");
  // The inner block: two rows back to back, or one row, or solid when tiny.
  const double inner_h = y_in1 - y_in0;
  if (x_in1 - x_in0 < snap(p.room_width_min_m + lb.t()) || inner_h < inner_min) return;
  if (inner_h >= 2 * snap(p.room_depth_min_m + lb.t()))
  {
    const double ym = snap(0.5 * (y_in0 + y_in1));
    lb.splitBand({x_in0, y_in0, x_in1, ym}, true, "inner south room");
    lb.splitBand({x_in0, ym, x_in1, y_in1}, true, "inner north room");
  }
  else
    lb.splitBand({x_in0, y_in0, x_in1, y_in1}, true, "inner room");
}

void layoutBranching(LayoutBuilder& lb, const WorldGenParams& p, Rng& rng)
{
  const double w = lb.corridorWidth(), d = lb.roomDepth(), ds = lb.roomDepth();
  const double hb = snap(rng.uniform(8.0, 20.0));
  const double h = ds + w + hb, pitch = w + 2 * d;
  const int k_max = std::max(1, static_cast<int>(std::floor(p.max_side_m / pitch)));
  const int k = std::clamp(static_cast<int>(std::lround(lb.targetArea() / (pitch * h))), 1, k_max);
  const double wd = k * pitch, f = snap(p.featureless_corridor_m);
  // The main corridor and its branches are one region (no wall where they meet).
  std::vector<Rect2> corridors{{0, ds, wd + f, ds + w}};
  for (int i = 0; i < k; i++)
  {
    const double xb = d + i * pitch;
    corridors.push_back({xb, ds + w, xb + w, h});
  }
  lb.add(K::Corridor, corridors, "corridors");
  lb.planRoomCount(wd + 2 * k * hb);
  lb.splitBand({0, 0, wd, ds}, true, "south room");
  for (int i = 0; i < k; i++)
  {
    const double xb = d + i * pitch;  // branch i spans [xb, xb + w]
    // Rooms west of the branch (a half block) and east of it.
    lb.splitBand({xb - d, ds + w, xb, h}, false, "branch " + std::to_string(i + 1) + " west room");
    lb.splitBand({xb + w, ds + w, xb + w + d, h}, false, "branch " + std::to_string(i + 1) + " east room");
  }
}

void layoutHall(LayoutBuilder& lb, Rng& rng)
{
  const double w = lb.corridorWidth(), d = lb.roomDepth();
  const double hh = snap(rng.uniform(8.0, 16.0));
  const double wd = lb.clampSide(lb.targetArea() / (hh + w + d));
  lb.add(K::Hall, {{0, 0, wd, hh}}, "open-plan hall");
  lb.add(K::Corridor, {{0, hh, wd, hh + w}}, "corridor");
  lb.planRoomCount(wd);
  lb.splitBand({0, hh + w, wd, hh + w + d}, true, "north room");
}

/// Places a door of width `width` on a random (or, for look-alike rooms,
/// the middle) position of `e`, keeping `margin` of wall at both ends.
bool placeDoor(GeneratedBuilding& b, const SharedEdge& e, int ra, int rb, double width, bool wide,
               double margin, bool centred, Rng& rng)
{
  const double lo = e.lo + margin + 0.5 * width, hi = e.hi - margin - 0.5 * width;
  if (hi < lo) return false;
  const double s = centred ? 0.5 * (lo + hi) : rng.uniform(lo, hi);
  GenDoor door;
  door.region_a = ra;
  door.region_b = rb;
  door.along_x = e.along_x;
  door.center = e.along_x ? Eigen::Vector2d(s, e.c) : Eigen::Vector2d(e.c, s);
  door.width_m = width;
  door.wide = wide;
  b.doors.push_back(door);
  return true;
}

/// Doors: hall openings, then every room to a corridor where it touches one,
/// else to a connected neighbour room; rooms left unconnected become solid.
void placeDoors(GeneratedBuilding& b, const WorldGenParams& p, double t, Rng& rng)
{
  const double margin = 0.5 * t + 0.3;
  const auto drawWidth = [&](bool& wide)
  {
    wide = rng.chance(p.wide_opening_share);
    return wide ? rng.uniform(p.wide_opening_min_m, p.wide_opening_max_m)
                : rng.uniform(p.door_width_min_m, p.door_width_max_m);
  };
  std::set<int> connected;
  for (const GenRegion& r : b.regions)
    if (r.kind != K::Room) connected.insert(r.id);
  // Hall <-> corridor: one wide opening per 10 m of shared wall (at least two).
  for (const GenRegion& h : b.regions)
  {
    if (h.kind != K::Hall) continue;
    for (const GenRegion& c : b.regions)
    {
      if (c.kind != K::Corridor) continue;
      for (const SharedEdge& e : sharedEdges(h, c))
      {
        const int n = std::max(2, static_cast<int>((e.hi - e.lo) / 10.0));
        const double seg = (e.hi - e.lo) / n;
        for (int i = 0; i < n; i++)
          placeDoor(b, {e.along_x, e.c, e.lo + i * seg, e.lo + (i + 1) * seg}, h.id, c.id,
                    rng.uniform(p.wide_opening_min_m, p.wide_opening_max_m), true, margin, false,
                    rng);
      }
    }
  }
  for (bool changed = true; changed;)
  {
    changed = false;
    for (const GenRegion& r : b.regions)
    {
      if (connected.count(r.id)) continue;
      // Longest shared edge with a corridor/hall, else with a connected room.
      const SharedEdge* best = nullptr;
      int best_other = 0, best_rank = 3;
      std::vector<std::pair<SharedEdge, int>> cands;
      for (const GenRegion& o : b.regions)
      {
        if (o.id == r.id || !connected.count(o.id)) continue;
        for (const SharedEdge& e : sharedEdges(r, o)) cands.emplace_back(e, o.id);
      }
      for (const auto& [e, oid] : cands)
      {
        const int rank = b.regions[static_cast<std::size_t>(oid - 1)].kind == K::Room ? 1 : 0;
        if (e.hi - e.lo < 2 * margin + p.door_width_max_m) continue;
        if (rank < best_rank || (rank == best_rank && e.hi - e.lo > best->hi - best->lo))
        {
          best = &e;
          best_other = oid;
          best_rank = rank;
        }
      }
      if (!best) continue;
      bool wide = false;
      const double width = drawWidth(wide);
      if (placeDoor(b, *best, best_other, r.id, width, wide, margin, p.look_alike_rooms, rng))
      {
        connected.insert(r.id);
        changed = true;
      }
    }
  }
  // Unreachable rooms (no wall long enough for a door) are left out of the building.
  std::vector<GenRegion> kept;
  std::map<int, int> renum;
  for (const GenRegion& r : b.regions)
    if (connected.count(r.id))
    {
      renum[r.id] = static_cast<int>(kept.size()) + 1;
      kept.push_back(r);
      kept.back().id = renum[r.id];
    }
  for (GenDoor& d : b.doors)
  {
    d.region_a = renum.at(d.region_a);
    d.region_b = renum.at(d.region_b);
  }
  b.regions = std::move(kept);
}

/// The start: on the first corridor's centre line, 2.5 m in from its west /
/// south end, facing along it (free for the omniRob in any corridor at least
/// 0.8 m wide).
Eigen::Vector3d startPose(const GeneratedBuilding& b)
{
  for (const GenRegion& r : b.regions)
  {
    if (r.kind != K::Corridor) continue;
    const Rect2& q = r.rects.front();
    if (q.width() >= q.height()) return {q.x0 + std::min(2.5, 0.5 * q.width()), q.center().y(), 0.0};
    return {q.center().x(), q.y0 + std::min(2.5, 0.5 * q.height()), 90.0};
  }
  throw std::logic_error("generated building without a corridor");
}

}  // namespace

std::size_t GeneratedBuilding::roomCount() const
{
  return static_cast<std::size_t>(std::count_if(regions.begin(), regions.end(), [](const GenRegion& r)
                                                { return r.kind == GenRegion::Kind::Room; }));
}

GeneratedBuilding generateBuilding(const WorldGenParams& params, uint64_t seed)
{
  if (const auto [key, why] = params.firstInvalid(); !key.empty())
    throw std::invalid_argument("[worldgen] " + key + ": " + why);
  Rng rng(seed * 0x9E3779B97F4A7C15ULL + 0x5EED);
  GeneratedBuilding b;
  b.seed = seed;
  b.params = params;
  b.layout = params.layout;
  if (b.layout == "mixed")
  {
    static const char* kLayouts[] = {"corridor", "ring", "branching", "hall"};
    b.layout = kLayouts[seed % 4];
  }
  LayoutBuilder lb(params, rng, b);
  if (b.layout == "corridor")
    layoutCorridor(lb, params);
  else if (b.layout == "ring")
    layoutRing(lb, params, rng);
  else if (b.layout == "branching")
    layoutBranching(lb, params, rng);
  else if (b.layout == "hall")
    layoutHall(lb, rng);
  else
    throw std::logic_error("[worldgen] layout '" + b.layout + "' passed firstInvalid()");
  placeDoors(b, params, lb.t(), rng);
  buildWalls(b, lb.t());
  if (params.furniture && params.furniture_density > 0) furnish(b, rng);
  b.start = startPose(b);
  b.floor_area_m2 = floorArea(b, lb.t());
  return b;
}

}  // namespace voxplore::sim
