// voxplore-explore: command line, configuration and the exploration loop
// (thesis fig. 4.4: scan -> SlamIcp -> plan -> stop-and-scan driving, 4.6).
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <voxplore/apps/ExploreApp.h>
#include <voxplore/apps/SimRobot.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/mapping/SlamIcp.h>
#include <voxplore/navigation/StopAndScanDriver.h>
#include <voxplore/sim/SimConfig.h>
#include <voxplore/sim/world_loading.h>

#include <filesystem>
#include <fstream>
#include <iostream>

#include "ExploreRun.h"

namespace voxplore::apps
{
namespace fs = std::filesystem;

namespace
{
const char* kDescription =
    "voxplore-explore: autonomous exploration and 3D voxel mapping (thesis fig. 4.4). In a "
    "simulated world the robot scans with all depth cameras, localises and maps with SlamIcp, "
    "plans the next best view (or drives to the nearest frontier with --strategy nearest) and "
    "drives the planned waypoints one at a time with MRPT's reactive navigator, stopping to "
    "scan at each, until no frontier is left or a step/time limit. Writes DIR/map.bt, "
    "DIR/map.simplemap, DIR/metaview.ply, DIR/run.rawlog (replayable by voxplore-replay), "
    "DIR/trajectory_gt.tum, DIR/trajectory_est.tum, DIR/trajectory_online.tum (each stop's estimate "
    "before later loop-closure relaxations), DIR/stops.csv, DIR/coverage.csv, "
    "DIR/steps/step_NNN.png, DIR/params.ini and DIR/summary.json (coverage, map precision, "
    "collisions, clearance, trajectory error against the world's ground truth). [explore] "
    "max_steps and max_sim_time_s always hold (the time limit also inside a drive). SIGINT or "
    "SIGTERM stops at the next robot step or stop, writes every output (termination_reason "
    "\"interrupted\") and exits with 130; a second one kills at once.";

std::set<std::string> knownSections()
{
  std::set<std::string> s = {"robot", "cameras", "simulator", ExploreParams::section()};
  for (const auto& n : mapping::SlamIcpParams::sections()) s.insert(n);
  for (const auto& n : exploration::PlannerParams::sections()) s.insert(n);
  for (const auto& n : navigation::DriverParams::sections()) s.insert(n);
  return s;
}

exploration::Strategy parseStrategy(const std::string& s)
{
  if (s == "nbv") return exploration::Strategy::NextBestView;
  if (s == "nearest") return exploration::Strategy::NearestFrontier;
  throw std::runtime_error("--strategy '" + s +
                           "': expected nbv or nearest (overrides [planner] strategy)");
}

ExploreConfig loadConfig(const ExploreOptions& opts)
{
  std::unique_ptr<mrpt::config::CConfigFileBase> owned;
  mrpt::config::CConfigFileMemory empty;
  const mrpt::config::CConfigFileBase* cfg = &empty;
  if (!opts.config.empty())
  {
    owned = common::openIniFile(opts.config);
    common::assertKnownSections(*owned, knownSections());
    cfg = owned.get();
  }
  ExploreConfig c;
  c.sim = sim::SimConfig::load(*cfg, opts.robot);
  if (const auto w = c.sim.profileOverrideWarning(opts.config); !w.empty())
    std::cerr << "voxplore-explore: warning: " << w << "\n";
  // The registration's body check uses the robot's footprint unless
  // [icp] body_length_m / body_width_m are set.
  c.slam.icp.body_length_m = c.sim.robot.length_m;
  c.slam.icp.body_width_m = c.sim.robot.width_m;
  c.slam.load(*cfg);
  // r_coll follows the robot footprint unless [collision] r_coll_m is set.
  c.planner.setFootprint(c.sim.robot.length_m, c.sim.robot.width_m);
  c.planner.load(*cfg);
  // The low obstacle cells stand in for G's voxel columns below their
  // z_min: a band between the two would be seen by neither.
  const auto& oc = c.slam.octomap;
  if (oc.low_obstacle_min_z_m > 0 && oc.low_obstacle_max_z_m < c.planner.projection.z_min_m - 1e-9)
    throw std::runtime_error(mrpt::format(
        "%s: [octomap] low_obstacle_max_z_m = %.3f is below [projection] z_min_m = %.3f: "
        "obstacles between the two heights would be in neither the low obstacle cells nor G's "
        "voxel columns; set low_obstacle_max_z_m to at least z_min_m (or low_obstacle_min_z_m "
        "= 0 to switch low obstacles off)",
        opts.config.empty() ? "built-in defaults" : opts.config.c_str(), oc.low_obstacle_max_z_m,
        c.planner.projection.z_min_m));
  // The scan rating's virtual cameras are the robot's, unless [scan_rating] places them.
  if (cfg->read_string("scan_rating", "cam0_pose", "").empty())
  {
    c.planner.rating.mounts = c.sim.cameras.mounts;
  }
  c.driver = navigation::DriverParams::forFootprint(c.sim.robot.length_m, c.sim.robot.width_m);
  c.driver.max_v_mps = c.sim.robot.max_v_mps;
  c.driver.max_w = c.sim.robot.max_w;
  c.driver.max_accel_mps2 = c.sim.robot.max_accel_mps2;
  c.driver.max_angular_accel = c.sim.robot.max_angular_accel;
  common::loadChecked(c.driver, *cfg, "navigation");
  common::loadChecked(c.explore, *cfg, ExploreParams::section());
  if (opts.seed)
  {
    c.sim.sim.seed = *opts.seed;
    c.planner.seed = *opts.seed;
  }
  if (opts.strategy) c.planner.strategy = parseStrategy(*opts.strategy);
  if (opts.max_steps) c.explore.max_steps = *opts.max_steps;
  return c;
}
}  // namespace

void ExploreParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  mission::ExplorationLoopParams::loadFromConfigFile(c, s);
  MRPT_LOAD_CONFIG_VAR(write_step_images, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(keep_plan_inputs, int, c, s);
  common::requireValid(keep_plan_inputs >= 0, c, s, "keep_plan_inputs", "must be >= 0");
  MRPT_LOAD_CONFIG_VAR(step_image_scale, int, c, s);
  MRPT_LOAD_CONFIG_VAR(gt_floor_res_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(coverage_yaw_bins, int, c, s);
  MRPT_LOAD_CONFIG_VAR(coverage_view_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(band_z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(band_z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(region_from_world, bool, c, s);
  common::requireValid(step_image_scale >= 1, c, s, "step_image_scale", "must be >= 1");
  common::requireValid(gt_floor_res_m > 0, c, s, "gt_floor_res_m", "must be > 0");
  common::requireValid(coverage_yaw_bins >= 2 && coverage_yaw_bins <= 128, c, s,
                       "coverage_yaw_bins", "must be in 2..128");
  common::requireValid(coverage_view_range_m >= 0, c, s, "coverage_view_range_m", "must be >= 0");
  common::requireValid(band_z_max_m > band_z_min_m, c, s, "band_z_max_m",
                       "must be above band_z_min_m");
}

void ExploreParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  mission::ExplorationLoopParams::saveToConfigFile(c, s);
  MRPT_SAVE_CONFIG_VAR(write_step_images, c, s);
  MRPT_SAVE_CONFIG_VAR(keep_plan_inputs, c, s);
  MRPT_SAVE_CONFIG_VAR(step_image_scale, c, s);
  MRPT_SAVE_CONFIG_VAR(gt_floor_res_m, c, s);
  MRPT_SAVE_CONFIG_VAR(coverage_yaw_bins, c, s);
  MRPT_SAVE_CONFIG_VAR(coverage_view_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(band_z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(band_z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(region_from_world, c, s);
}

int ExploreApp::run(int argc, const char* const* argv)
{
  return runGuarded("voxplore-explore", [&]() {
    TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
    TCLAP::ValueArg<std::string> config("c", "config", "ini file (e.g. config/explore.ini)", false,
                                        "", "INI", cmd);
    TCLAP::ValueArg<std::string> world("w", "world", "World: .world, mesh or floor-plan file",
                                       false, "simulated_worlds/dlr_test_room.world", "FILE", cmd);
    TCLAP::ValueArg<std::string> start(
        "", "start", "Start pose x,y,yaw_deg (default: the world file's)", false, "", "x,y,yaw",
        cmd);
    TCLAP::ValueArg<std::string> robot("r", "robot", "Robot profile: omnirob | compact", false, "",
                                       "NAME", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "Output directory (created)", false,
                                     "out/explore", "DIR", cmd);
    TCLAP::ValueArg<int> seed("s", "seed", "Seed (overrides [simulator] and [planner] seed)",
                              false, 1, "N", cmd);
    TCLAP::ValueArg<std::string> strategy(
        "", "strategy", "nbv | nearest (overrides [planner] strategy)", false, "", "NAME", cmd);
    TCLAP::ValueArg<int> max_steps("n", "max-steps", "Planning steps at most (overrides "
                                   "[explore] max_steps)", false, 0, "N", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "No per-step lines and no parameter dump", cmd);
    if (!cmd.parse(argc, const_cast<const char**>(argv)))
      return exitCodeAfterFailedParse(argc, argv);
    installInterruptHandler();
    ExploreOptions o;
    o.config = config.getValue();
    o.world = world.getValue();
    o.out_dir = out.getValue();
    if (start.isSet()) o.start = start.getValue();
    if (robot.isSet()) o.robot = robot.getValue();
    if (seed.isSet()) o.seed = seed.getValue();
    if (strategy.isSet()) o.strategy = strategy.getValue();
    if (max_steps.isSet()) o.max_steps = max_steps.getValue();
    o.quiet = quiet.getValue();
    const auto s = execute(o);
    std::cout << "voxplore-explore: " << s.termination_reason << " after " << s.steps
              << " steps, " << s.stops << " stops; path " << s.path_length_m
              << " m; coverage 2D " << s.coverage_2d << ", 3D " << s.coverage_3d
              << "; map precision " << s.map_precision << "; collisions " << s.collisions
              << "; ATE " << s.ate_rmse_m << " m -> " << o.out_dir << std::endl;
    if (s.termination_reason == "interrupted")
    {
      std::cerr << "voxplore-explore: interrupted; the maps and logs of the " << s.stops
                << " stops so far are complete in " << o.out_dir << " (exit code "
                << kExitInterrupted << ")" << std::endl;
      return kExitInterrupted;
    }
    return 0;
  });
}

ExploreSummary ExploreApp::execute(const ExploreOptions& opts)
{
  ExploreConfig cfg = loadConfig(opts);
  // A relative navlog_dir lives in the run's output directory (one run's
  // navigation logs beside its maps; parallel campaign runs never share it).
  if (!cfg.driver.navlog_dir.empty() && fs::path(cfg.driver.navlog_dir).is_relative())
    cfg.driver.navlog_dir = (fs::path(opts.out_dir) / cfg.driver.navlog_dir).string();
  std::optional<mrpt::poses::CPose2D> start;
  if (opts.start) start = sim::parseStartPose(*opts.start);
  if (opts.world.empty()) throw std::runtime_error("no world file given (--world)");
  auto world = sim::loadWorld(opts.world, start);
  prepareOutputDir(opts.out_dir);

  mrpt::config::CConfigFileMemory used;
  cfg.sim.save(used);
  cfg.slam.save(used);
  cfg.planner.save(used);
  cfg.driver.saveToConfigFile(used, "navigation");
  cfg.explore.saveToConfigFile(used, ExploreParams::section());
  std::ofstream(fs::path(opts.out_dir) / "params.ini")
      << "# voxplore-explore parameters in force\n" << used.getContent();
  if (!opts.quiet)
    std::cout << "voxplore-explore: world '" << world.source_path << "', start " << world.start
              << "\n--- parameters in force ---\n" << used.getContent()
              << "---------------------------" << std::endl;
  if (!opts.quiet)
  {
    const auto& col = cfg.planner.collision;
    const double l_res = cfg.slam.octomap.l_res_m;
    std::cout << "voxplore-explore: planner model " << col.toString(col.modelInForce(l_res))
              << (col.model == exploration::CollisionParams::Model::Auto
                      ? mrpt::format(" ([collision] model = auto: the planner circle is %.2f m, "
                                     "auto_footprint_above_m %.2f m)",
                                     col.plannerCircleDiameter(l_res), col.auto_footprint_above_m)
                      : std::string())
              << (col.usesFootprint(l_res)
                      ? mrpt::format("; footprint margin %.3f m, squares %.2f of a cell, "
                                     "lateral slack %.3f m "
                                     "(auto: %s, the rectangle with whole squares needs %.3f m, "
                                     "auto_door_m %.2f m)",
                                     col.marginInForce(l_res), col.squareShareInForce(l_res),
                                     col.lateralInForce(l_res),
                                     col.footprintTrimmed(l_res) ? "trimmed" : "exact",
                                     col.exactDoorM(l_res), col.auto_door_m)
                      : std::string())
              << "; low obstacles seen on the way "
              << (cfg.explore.lowObstacleReplanInForce(col, l_res) ? "end a drive" : "do not end a drive")
              << (cfg.explore.low_obstacle_replan == mission::ExplorationLoopParams::Switch::Auto
                      ? " ([explore] low_obstacle_replan = auto: on with exact footprint margins)"
                      : "");
    const double ob_z = cfg.planner.projectionInForce(l_res).obstacle_z_max_m;
    const auto& proj = cfg.planner.projection;
    std::cout << "; occupied voxels "
              << (ob_z > proj.z_max_m
                      ? mrpt::format("up to %.2f m close their column", ob_z)
                      : mrpt::format("above %.2f m are not obstacles", proj.z_max_m))
              << (proj.obstacle_z_max_m == exploration::ProjectionParams::kAuto
                      ? " ([projection] obstacle_z_max_m = auto: auto_obstacle_z_max_m with exact "
                        "footprint margins)"
                      : "")
              << std::endl;
  }

  sim::Simulator simulator(std::move(world), cfg.sim.robot, cfg.sim.cameras, cfg.sim.sim);
  ExploreRun run(simulator, cfg, opts.out_dir, opts.quiet);
  return run.execute();
}

}  // namespace voxplore::apps
