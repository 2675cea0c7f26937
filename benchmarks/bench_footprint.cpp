// Footprint planning (issue 13): the orientation collision space and the
// SE(2) path on a building map, beside the circle's collision space and A*
// on the same map. Target: under 30 ms each on a 500 m^2 map at 5 cm, one
// core (run under taskset -c 1, Release).
//
// Map: --map=<file.bt> (a voxplore-explore map.bt), planner keys --config=<ini>
// (optional; the code's defaults without it), robot pose --pose=x,y,yaw_deg
// (default: the map's first free cell found from the middle), goal: the reached
// cell farthest (straight line) from the robot.
#include <benchmark/benchmark.h>
#include <mrpt/core/bits_math.h>
#include <octomap/OcTree.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/footprint.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_map_args.h"

using namespace voxplore::exploration;

namespace
{
std::string g_map_path, g_config_path;
double g_x = 0, g_y = 0, g_yaw = 0;

struct Fixture
{
  std::unique_ptr<octomap::OcTree> tree;
  mrpt::poses::CPose2D robot;
  PlannerParams params;
  GroundGrid ground;
  CollisionSpace circle;
  CollisionSpace space;  // footprint
  FootprintSpace fs;
  Eigen::Vector2d goal{0, 0};
  double free_m2 = 0;
};

/// FNV-1a over every layer of the footprint space: a speed-up of
/// computeFootprintSpace must leave it unchanged on the same map and keys.
uint64_t layersDigest(const FootprintSpace& fs)
{
  uint64_t h = 1469598103934665603ull;
  for (const Grid<YawMask>* layer : {&fs.clear_occ, &fs.clear, &fs.clear_turn, &fs.reach, &fs.escape})
    for (const YawMask m : layer->data())
      for (int b = 0; b < 8; ++b)
      {
        h ^= (m >> (8 * b)) & 0xff;
        h *= 1099511628211ull;
      }
  return h;
}

const Fixture& fixture()
{
  static std::unique_ptr<Fixture> f;
  if (f) return *f;
  f = std::make_unique<Fixture>();
  f->tree = std::make_unique<octomap::OcTree>(g_map_path);
  if (f->tree->size() == 0) throw std::runtime_error("bench_footprint: empty map " + g_map_path);
  f->robot = mrpt::poses::CPose2D(g_x, g_y, mrpt::DEG2RAD(g_yaw));
  if (!g_config_path.empty())
  {
    // The planner's keys (e.g. footprint_bin_span and footprint_lateral_m of
    // [collision]); the robot stays the omniRob.
    // openIniFile: a wrong path is an error, not the defaults.
    f->params.load(*voxplore::common::openIniFile(g_config_path));
  }
  f->params.collision.model = CollisionParams::Model::Footprint;
  f->params.projection.footprint_length_m = f->params.collision.footprint_length_m;
  f->params.projection.footprint_width_m = f->params.collision.footprint_width_m;
  f->ground = projectToGround(*f->tree, f->robot,
                              f->params.projectionInForce(f->tree->getResolution()));
  f->circle = computeCollisionSpace(f->ground, f->params.collision);
  f->space = f->circle;
  f->fs = computeFootprintSpace(f->ground, f->space, f->params.collision, f->robot);
  applyFootprint(f->space, f->fs);
  const auto& g = f->ground.state;
  double best = -1;
  for (int cy = 0; cy < static_cast<int>(g.getSizeY()); ++cy)
    for (int cx = 0; cx < static_cast<int>(g.getSizeX()); ++cx)
    {
      if (*g.cellByIndex(cx, cy) == GroundState::Free)
        f->free_m2 += g.getResolution() * g.getResolution();
      if (*f->space.state.cellByIndex(cx, cy) != SpaceState::Free) continue;
      const Eigen::Vector2d c = cellCenter(g, Cell{cx, cy});
      const double d = (c - Eigen::Vector2d(g_x, g_y)).norm();
      if (d > best)
      {
        best = d;
        f->goal = c;
      }
    }
  std::cerr << "bench_footprint: " << g_map_path << ": grid " << g.getSizeX() << " x "
            << g.getSizeY() << " at " << g.getResolution() << " m, free floor " << f->free_m2
            << " m^2, goal (" << f->goal.x() << ", " << f->goal.y() << ") " << best
            << " m from the robot, layers digest " << std::hex << layersDigest(f->fs) << std::dec
            << "\n";
  return *f;
}

void BM_CollisionSpaceCircle(benchmark::State& st)
{
  const Fixture& f = fixture();
  for (auto _ : st) benchmark::DoNotOptimize(computeCollisionSpace(f.ground, f.params.collision));
}

void BM_FootprintSpace(benchmark::State& st)
{
  const Fixture& f = fixture();
  for (auto _ : st)
  {
    // The planner applies the footprint to the circle's space it has just
    // computed; the copy here is the benchmark's, not timed.
    st.PauseTiming();
    CollisionSpace cs = f.circle;
    st.ResumeTiming();
    FootprintSpace fs = computeFootprintSpace(f.ground, cs, f.params.collision, f.robot);
    applyFootprint(cs, fs);
    benchmark::DoNotOptimize(fs);
    // As the planner does when a step's plan is let go (its layers are the
    // next space's): spares, not fresh pages.
    recycleFootprintSpace(std::move(fs));
  }
}

void BM_PathCircle(benchmark::State& st)
{
  const Fixture& f = fixture();
  std::size_t ok = 0;
  for (auto _ : st)
    ok += planPath(f.circle, {f.robot.x(), f.robot.y()}, f.goal, f.params.path).has_value();
  st.counters["found"] = static_cast<double>(ok) / static_cast<double>(st.iterations());
}

void BM_PathFootprint(benchmark::State& st)
{
  const Fixture& f = fixture();
  std::size_t ok = 0;
  double len = 0;
  for (auto _ : st)
  {
    const auto p = planFootprintPath(f.space, f.fs, f.robot, f.goal, 0.0, f.params.path);
    ok += p.has_value();
    if (p) len = p->length_m;
  }
  st.counters["found"] = static_cast<double>(ok) / static_cast<double>(st.iterations());
  st.counters["length_m"] = len;
}

void BM_FootprintCostFromStart(benchmark::State& st)
{
  const Fixture& f = fixture();
  for (auto _ : st)
  {
    auto d = footprintCostFromStart(f.space, f.fs, f.params.path);
    benchmark::DoNotOptimize(d);
  }
}

// A further candidate goal of the same planning step: the heuristic is shared.
void BM_PathFootprintSharedHeuristic(benchmark::State& st)
{
  const Fixture& f = fixture();
  const auto h = footprintCostFromStart(f.space, f.fs, f.params.path);
  std::size_t ok = 0;
  for (auto _ : st)
    ok += planFootprintPath(f.space, f.fs, f.robot, f.goal, 0.0, f.params.path, &h).has_value();
  st.counters["found"] = static_cast<double>(ok) / static_cast<double>(st.iterations());
}

BENCHMARK(BM_CollisionSpaceCircle)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FootprintSpace)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PathCircle)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PathFootprint)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FootprintCostFromStart)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PathFootprintSharedHeuristic)->Unit(benchmark::kMillisecond);
}  // namespace

int main(int argc, char** argv)
{
  voxplore::bench::MapArgs a;
  if (!voxplore::bench::parseMapArgs(argc, argv, "bench_footprint", a)) return 2;
  g_map_path = a.map;
  g_config_path = a.config;
  g_x = a.x;
  g_y = a.y;
  g_yaw = a.yaw_deg;
  std::vector<char*>& args = a.rest;
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  try
  {
    fixture();
  }
  catch (const std::exception& e)
  {
    std::cerr << "bench_footprint: " << e.what() << "\n";
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
