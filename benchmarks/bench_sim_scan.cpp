// One 8-camera scan (8 x 64 x 48 = 24,576 rays) of the simulated O3D100 ring,
// on our dlr_test_room and on ../shared/worlds/aws_small_house (and
// turtlebot3_house). Target (issue 2): under 5 ms on one core, Release.
//
//   BM_Scan/<world>        full DepthCameraRig::scan: ray casting, noise,
//                          quantisation, 8 CObservation3DRangeScan objects
//   BM_RaysPacket/<world>  Embree 16-wide packets only (RayCaster::castFan)
//   BM_RaysSingle/<world>  the same rays one rtcIntersect1 at a time
#include <benchmark/benchmark.h>
#include <voxplore/sim/DepthCameraRig.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/world_loading.h>

#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

using namespace voxplore;

namespace
{
struct Scene
{
  sim::World world;
  std::unique_ptr<sim::RayCaster> caster;
  mrpt::poses::CPose3D pose;
};

// Robot poses with free space around them in each world.
const std::map<std::string, std::pair<std::string, mrpt::poses::CPose2D>> kWorlds = {
    {"dlr_test_room",
     {std::string(VOXPLORE_SOURCE_DIR) + "/simulated_worlds/dlr_test_room.world",
      mrpt::poses::CPose2D(2.0, 4.0, 0.0)}},
    {"aws_small_house",
     {std::string(VOXPLORE_SHARED_WORLDS_DIR) + "/aws_small_house/small_house_flat_collision.obj",
      mrpt::poses::CPose2D(0.0, 0.0, 0.0)}},
    {"turtlebot3_house",
     {std::string(VOXPLORE_SHARED_WORLDS_DIR) + "/turtlebot3_house/turtlebot3_house_flat.obj",
      mrpt::poses::CPose2D(0.0, 0.0, 0.0)}},
};

Scene* scene(const std::string& name)
{
  static std::map<std::string, std::unique_ptr<Scene>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second.get();
  const auto& [path, start] = kWorlds.at(name);
  if (!std::filesystem::exists(path)) return nullptr;
  auto s = std::make_unique<Scene>();
  s->world = sim::loadWorld(path, start);
  s->caster = std::make_unique<sim::RayCaster>(s->world.mesh);
  s->pose = mrpt::poses::CPose3D(start);
  return (cache[name] = std::move(s)).get();
}

void BM_Scan(benchmark::State& state, const std::string& world)
{
  Scene* s = scene(world);
  if (!s) return state.SkipWithError(("world missing: " + world).c_str());
  sim::DepthCameraRig rig{sim::CameraRigParams{}};
  std::mt19937_64 rng(1);
  std::size_t valid = 0;
  for (auto _ : state)
  {
    auto scans = rig.scan(*s->caster, s->pose, mrpt::Clock::fromDouble(0), rng, true);
    benchmark::DoNotOptimize(scans.data());
    valid = 0;
    for (const auto& o : scans)
      for (int v = 0; v < 48; v++)
        for (int u = 0; u < 64; u++) valid += o->rangeImage(v, u) != 0;
  }
  state.counters["rays"] = 8 * 3072;
  state.counters["valid_px"] = static_cast<double>(valid);
  state.SetItemsProcessed(state.iterations() * 8 * 3072);
}

std::vector<Eigen::Vector3f> worldDirections(const Scene& s, std::vector<Eigen::Vector3f>& origins)
{
  sim::CameraRigParams p;
  sim::DepthCameraRig rig(p);
  std::vector<Eigen::Vector3f> dirs;
  for (const auto& m : p.mounts)
  {
    const auto T = s.pose + m;
    const Eigen::Matrix3f R = T.getRotationMatrix().asEigen().cast<float>();
    for (const auto& d : rig.pixelDirections()) dirs.push_back(R * d);
    origins.emplace_back(T.x(), T.y(), T.z());
  }
  return dirs;
}

void BM_Rays(benchmark::State& state, const std::string& world, bool packets)
{
  Scene* s = scene(world);
  if (!s) return state.SkipWithError(("world missing: " + world).c_str());
  std::vector<Eigen::Vector3f> origins;
  const auto dirs = worldDirections(*s, origins);
  std::vector<float> t(dirs.size());
  for (auto _ : state)
  {
    for (std::size_t c = 0; c < origins.size(); c++)
    {
      if (packets)
        s->caster->castFan(origins[c], &dirs[c * 3072], 3072, 0.0f, 7.1f, &t[c * 3072]);
      else
        for (std::size_t i = c * 3072; i < (c + 1) * 3072; i++)
          t[i] = s->caster->cast(origins[c], dirs[i], 0.0f, 7.1f);
    }
    benchmark::DoNotOptimize(t.data());
  }
  state.SetItemsProcessed(state.iterations() * dirs.size());
}
}  // namespace

int main(int argc, char** argv)
{
  for (const auto& [name, _] : kWorlds)
  {
    if (!scene(name))
    {
      std::cerr << "bench_sim_scan: SKIPPING " << name << " (not found: " << kWorlds.at(name).first
                << ")\n";
      continue;
    }
    benchmark::RegisterBenchmark(("BM_Scan/" + name).c_str(), BM_Scan, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_RaysPacket/" + name).c_str(), BM_Rays, name, true)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("BM_RaysSingle/" + name).c_str(), BM_Rays, name, false)
        ->Unit(benchmark::kMillisecond);
  }
  std::cout << "Reference (issue 2): one 8-camera scan, 24,576 rays, target < 5 ms on one core\n";
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
