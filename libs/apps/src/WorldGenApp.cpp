#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/bits_math.h>
#include <voxplore/apps/WorldGenApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/CollisionChecker.h>
#include <voxplore/sim/RayCaster.h>
#include <voxplore/sim/Robot.h>
#include <voxplore/sim/ground_truth.h>
#include <voxplore/sim/world_loading.h>
#include <voxplore/sim/worldgen.h>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace voxplore::apps
{
namespace
{
const char* kDescription =
    "voxplore-worldgen: draws a procedural office building from a seed and writes "
    "DIR/building.world (loads in mrpt-sim, voxplore-explore and every app taking --world; the "
    "start pose is inside, in a corridor, free for the omniRob), DIR/building.json (ground "
    "truth: layout, floor area, regions with their rectangles, doors with their widths, the "
    "parameters) and DIR/topview.png. Layouts: a straight corridor with rooms on both sides, a "
    "ring corridor round an inner block of rooms (a loop), branching corridors, an open-plan "
    "hall; [worldgen] in the ini (config/worldgen.ini documents every key) sets sizes, door "
    "widths (0.85-1.0 m by default), furniture, a featureless corridor stretch and look-alike "
    "rooms. The same seed and ini give the same files byte for byte.";

sim::WorldGenParams loadParams(const WorldGenOptions& o)
{
  sim::WorldGenParams p;
  if (!o.config.empty())
  {
    const auto cfg = common::openIniFile(o.config);
    common::assertKnownSections(*cfg, {"worldgen"});
    common::loadChecked(p, *cfg, "worldgen");
  }
  if (o.layout)
  {
    p.layout = *o.layout;
    if (const auto [key, why] = p.firstInvalid(); key == "layout")
      throw std::runtime_error("--layout '" + *o.layout + "': " + why);
  }
  return p;
}

void writeText(const std::filesystem::path& path, const std::string& text)
{
  std::ofstream f(path, std::ios::binary);
  if (!(f << text)) throw std::runtime_error("cannot write '" + path.string() + "'");
}
}  // namespace

int WorldGenApp::run(int argc, const char* const* argv)
{
  return runGuarded("voxplore-worldgen", [&]() {
    TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
    TCLAP::ValueArg<uint64_t> seed("s", "seed", "Seed: fixes every random draw", true, 0, "N", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "Output directory (created)", true, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> config(
        "c", "config", "ini file with a [worldgen] section (default: built-in defaults)", false, "",
        "INI", cmd);
    TCLAP::ValueArg<std::string> layout(
        "l", "layout", "corridor | ring | branching | hall | mixed (overrides [worldgen] layout)",
        false, "", "NAME", cmd);
    TCLAP::SwitchArg no_topview("", "no-topview", "Do not write DIR/topview.png", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "Print nothing on success", cmd);
    if (!cmd.parse(argc, const_cast<const char**>(argv)))
      return exitCodeAfterFailedParse(argc, argv);
    WorldGenOptions o;
    o.seed = seed.getValue();
    o.out_dir = out.getValue();
    o.config = config.getValue();
    if (layout.isSet()) o.layout = layout.getValue();
    o.topview = !no_topview.getValue();
    o.quiet = quiet.getValue();
    const WorldGenSummary s = execute(o);
    if (!o.quiet)
      std::cout << mrpt::format("voxplore-worldgen: %s layout, %zu rooms, %zu doors, %.1f m2 of floor -> %s\n",
                                s.layout.c_str(), s.rooms, s.doors, s.floor_area_m2,
                                s.world_path.c_str());
    return 0;
  });
}

WorldGenSummary WorldGenApp::execute(const WorldGenOptions& o)
{
  const sim::WorldGenParams params = loadParams(o);
  const sim::GeneratedBuilding b = sim::generateBuilding(params, o.seed);
  prepareOutputDir(o.out_dir);
  const std::filesystem::path dir(o.out_dir);
  WorldGenSummary s;
  s.world_path = (dir / "building.world").string();
  s.truth_path = (dir / "building.json").string();
  s.layout = b.layout;
  s.floor_area_m2 = b.floor_area_m2;
  s.doors = b.doors.size();
  s.rooms = b.roomCount();
  writeText(s.world_path, sim::buildingWorldJson(b));
  writeText(s.truth_path, sim::buildingGroundTruthJson(b));

  // Read back as every app will; the start must be free for the larger robot.
  const sim::World world = sim::loadWorld(s.world_path);
  const sim::RobotParams omnirob = sim::RobotParams::omnirob();
  const sim::CollisionChecker checker(world, 0.03, omnirob.height_m);
  if (checker.collides(world.start, omnirob.footprint()))
    throw std::runtime_error(s.world_path + ": the generated start pose is not free for the omniRob "
                             "(a generator bug; seed " + std::to_string(o.seed) + ")");
  if (o.topview)
  {
    const sim::RayCaster caster(world.mesh);
    sim::writeTopView(world, caster, (dir / "topview.png").string(), 20.0, {world.start});
  }
  return s;
}

}  // namespace voxplore::apps
