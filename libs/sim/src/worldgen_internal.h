/* voxplore — internals shared by the building generator's translation units. */
#pragma once

#include <voxplore/sim/worldgen.h>

#include <cmath>
#include <cstdint>
#include <random>

namespace voxplore::sim::worldgen_detail
{
/// The layout lattice: every region edge lies on a multiple of it [m].
constexpr double kLattice = 0.05;

inline double snap(double v) { return std::round(v / kLattice) * kLattice; }

/// @brief The generator's only source of randomness. The draws are our own
///        arithmetic on std::mt19937_64 (whose sequence the standard fixes),
///        not std::uniform_*_distribution (implementation-defined), so a
///        seed gives the same building with any standard library.
class Rng
{
 public:
  explicit Rng(uint64_t seed) : g_(seed) {}
  double uniform(double a, double b) { return a + (b - a) * (double(g_() >> 11) * 0x1.0p-53); }
  /// An integer in [a, b].
  int integer(int a, int b) { return a + static_cast<int>(g_() % static_cast<uint64_t>(b - a + 1)); }
  bool chance(double p) { return uniform(0, 1) < p; }
  uint64_t next() { return g_(); }

 private:
  std::mt19937_64 g_;
};

inline bool overlaps(const Rect2& a, const Rect2& b, double gap = 0)
{
  return a.x0 < b.x1 + gap && b.x0 < a.x1 + gap && a.y0 < b.y1 + gap && b.y0 < a.y1 + gap;
}

inline bool contains(const Rect2& outer, const Rect2& inner, double eps = 1e-9)
{
  return inner.x0 >= outer.x0 - eps && inner.x1 <= outer.x1 + eps && inner.y0 >= outer.y0 - eps &&
         inner.y1 <= outer.y1 + eps;
}

/// @brief Walls: the edges between cells of different regions (or a region and
///        the outside) on the lattice, merged into runs and cut at the doors;
///        sets `b.walls` and `b.bounds`. `t` is the wall thickness.
void buildWalls(GeneratedBuilding& b, double t);

/// @brief Free floor inside the walls [m^2] (furniture not subtracted).
double floorArea(const GeneratedBuilding& b, double t);

/// @brief Furniture for every room and hall of `b` (doors already placed).
void furnish(GeneratedBuilding& b, Rng& rng);

}  // namespace voxplore::sim::worldgen_detail
