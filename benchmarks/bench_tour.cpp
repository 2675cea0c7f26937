// The frontier tour and the rooms (issue 12): the tour alone, the room
// segmentation alone and a whole planning step with frontier_order = nearest,
// = tour and with [rooms] finish_room, the compact robot (the thesis'
// circle) on a building map. Target: the whole step under 100 ms median on
// one core on a 500 m^2 map (run under taskset -c 1, Release).
//
// Map: --map=<file.bt> (a voxplore-explore map.bt), robot pose --pose=x,y,yaw_deg,
// planner settings --config=<ini> (config/explore.ini).
#include <benchmark/benchmark.h>
#include <mrpt/core/bits_math.h>
#include <octomap/OcTree.h>
#include <voxplore/common/camera_mounts.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/Planner.h>

#include <cmath>
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
  CollisionSpace space;
  FrontierMap fm;
  std::vector<std::size_t> tier1;
};

const Fixture& fixture()
{
  static std::unique_ptr<Fixture> f;
  if (f) return *f;
  f = std::make_unique<Fixture>();
  f->tree = std::make_unique<octomap::OcTree>(g_map_path);
  if (f->tree->size() == 0) throw std::runtime_error("bench_tour: empty map " + g_map_path);
  f->robot = mrpt::poses::CPose2D(g_x, g_y, mrpt::DEG2RAD(g_yaw));
  // The compact robot, as voxplore-explore --robot compact sets it up.
  constexpr double kLength = 0.50, kWidth = 0.36;
  f->params.collision.r_coll_m = std::hypot(kLength / 2, kWidth / 2);
  f->params.collision.footprint_length_m = kLength;
  f->params.collision.footprint_width_m = kWidth;
  if (!g_config_path.empty())
  {
    // openIniFile: a wrong path is an error, not the defaults.
    f->params.load(*voxplore::common::openIniFile(g_config_path));
  }
  f->params.projection.footprint_length_m = kLength;
  f->params.projection.footprint_width_m = kWidth;
  f->params.rating.mounts = voxplore::common::cameraRing(kLength, kWidth, 0.60, mrpt::DEG2RAD(30.0));
  f->ground = projectToGround(*f->tree, f->robot,
                              f->params.projectionInForce(f->tree->getResolution()));
  f->space = computeCollisionSpace(f->ground, f->params.collision);
  f->fm = findFrontiers(f->ground, f->space);
  double free_m2 = 0;
  for (const auto s : f->ground.state.data())
    free_m2 += s == GroundState::Free ? f->ground.state.getResolution() * f->ground.state.getResolution() : 0.0;
  for (std::size_t i = 0; i < f->fm.frontiers.size(); ++i)
    if (f->fm.frontiers[i].size_m > f->params.sampling.th_f1_m) f->tier1.push_back(i);
  std::cerr << "bench_tour: " << g_map_path << ": grid " << f->ground.state.getSizeX() << " x "
            << f->ground.state.getSizeY() << ", free floor " << free_m2 << " m^2, "
            << f->fm.frontiers.size() << " frontiers, " << f->tier1.size() << " longer than "
            << f->params.sampling.th_f1_m << " m\n";
  return *f;
}

void BM_Tour(benchmark::State& st)
{
  const Fixture& f = fixture();
  double len = 0;
  for (auto _ : st) len = frontierTour(f.fm, f.ground.robot, f.tier1, f.params.tour_cell_m).length_m;
  st.counters["stops"] = static_cast<double>(f.tier1.size());
  st.counters["length_m"] = len;
}

void BM_Rooms(benchmark::State& st)
{
  const Fixture& f = fixture();
  std::size_t rooms = 0;
  for (auto _ : st) rooms = segmentRooms(f.ground, f.space, f.params.rooms).area_m2.size();
  st.counters["rooms"] = static_cast<double>(rooms);
}

void planStep(benchmark::State& st, FrontierOrder order, bool finish_room = false)
{
  const Fixture& f = fixture();
  PlannerParams p = f.params;
  p.strategy = Strategy::NextBestView;
  p.frontier_order = order;
  p.rooms.finish_room = finish_room;
  PlanTimings last;
  for (auto _ : st)
  {
    const PlanResult r = plan(*f.tree, f.robot, p);
    last = r.ms;
    benchmark::DoNotOptimize(r.ok());
  }
  st.counters["tour_ms"] = last.tour;
  st.counters["rooms_ms"] = last.rooms;
  st.counters["rating_ms"] = last.rating;
}

void BM_PlanStepNearestOrder(benchmark::State& st) { planStep(st, FrontierOrder::Nearest); }
void BM_PlanStepTour(benchmark::State& st) { planStep(st, FrontierOrder::Tour); }
void BM_PlanStepFinishRoom(benchmark::State& st) { planStep(st, FrontierOrder::Nearest, true); }

BENCHMARK(BM_Tour)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanStepNearestOrder)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanStepTour)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Rooms)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanStepFinishRoom)->Unit(benchmark::kMillisecond);
}  // namespace

int main(int argc, char** argv)
{
  voxplore::bench::MapArgs a;
  if (!voxplore::bench::parseMapArgs(argc, argv, "bench_tour", a)) return 2;
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
    std::cerr << "bench_tour: " << e.what() << "\n";
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
