#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/poses/CPose3D.h>
#include <voxplore/apps/SimApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/Progress.h>
#include <voxplore/common/config.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/sim/SimConfig.h>
#include <voxplore/sim/ground_truth.h>
#include <voxplore/sim/tour.h>
#include <voxplore/sim/world_loading.h>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace voxplore::apps
{
namespace
{
const char* kDescription =
    "mrpt-sim: voxplore's depth-camera robot simulator. Loads a world (a .world file, a "
    "triangle mesh .obj/.ply/.stl, or a HouseExpo .json floor plan), drives the robot "
    "(omnidirectional, default KUKA omniRob with 8 O3D100 ToF cameras) along straight "
    "segments through the waypoints, stopping to scan every [simulator] scan_every_m metres "
    "and at each waypoint. Writes DIR/run.rawlog (CActionCollection + CSensoryFrame pairs: "
    "8 x CObservation3DRangeScan + CObservationOdometry per stop), DIR/trajectory_gt.tum "
    "(ground truth at each scan), DIR/trajectory_odo.tum (odometry), DIR/topview.png and "
    "DIR/params.ini (parameters in force). Waypoints file: one 'x y [yaw_deg]' per line, "
    "world metres, '#' comments. Ctrl-C (SIGINT) or SIGTERM stops the tour after the current "
    "stop, writes every output for the stops so far (the rawlog closed and readable) and exits "
    "with 130; a second one kills at once.";

sim::SimConfig loadConfig(const SimOptions& opts)
{
  if (opts.config.empty())
  {
    mrpt::config::CConfigFileMemory empty;
    return sim::SimConfig::load(empty, opts.robot);
  }
  const auto cfg = common::openIniFile(opts.config);
  common::assertKnownSections(*cfg, {"robot", "cameras", "simulator"});
  return sim::SimConfig::load(*cfg, opts.robot);
}
}  // namespace

int SimApp::run(int argc, const char* const* argv)
{
  return runGuarded("mrpt-sim", [&]() {
    TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
    TCLAP::ValueArg<std::string> world("w", "world", "World: .world, mesh or floor-plan file",
                                       true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> wps("p", "waypoints", "Waypoints file ('x y [yaw_deg]' lines)",
                                     true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "Output directory (created)", true, "", "DIR",
                                     cmd);
    TCLAP::ValueArg<std::string> config(
        "c", "config", "ini file with [robot], [cameras], [simulator] (default: built-in)", false,
        "", "INI", cmd);
    TCLAP::ValueArg<int> seed("s", "seed", "Random seed (overrides [simulator] seed)", false, 1,
                              "N", cmd);
    TCLAP::ValueArg<std::string> start(
        "", "start", "Start pose x,y,yaw_deg (default: the world file's, else 0,0,0)", false, "",
        "x,y,yaw", cmd);
    TCLAP::ValueArg<std::string> robot("r", "robot", "Robot profile: omnirob | compact", false,
                                       "", "NAME", cmd);
    TCLAP::SwitchArg no_noise("", "no-noise", "Disable sensor, motion and odometry noise", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "No progress bar", cmd);
    if (!cmd.parse(argc, const_cast<const char**>(argv)))
      return exitCodeAfterFailedParse(argc, argv);

    SimOptions o;
    o.world = world.getValue();
    o.waypoints = wps.getValue();
    o.out_dir = out.getValue();
    o.config = config.getValue();
    if (seed.isSet()) o.seed = seed.getValue();
    if (start.isSet()) o.start = start.getValue();
    if (robot.isSet()) o.robot = robot.getValue();
    o.no_noise = no_noise.getValue();
    o.quiet = quiet.getValue();
    installInterruptHandler();
    const auto s = execute(o);
    if (s.interrupted)
    {
      std::cerr << "mrpt-sim: interrupted after " << s.stops << " scan stops; " << o.out_dir
                << "/run.rawlog and the trajectories hold those stops (exit " << kExitInterrupted
                << ")" << std::endl;
      return kExitInterrupted;
    }
    std::cout << "mrpt-sim: " << s.stops << " scan stops, path " << s.path_length_m << " m, "
              << s.sim_time_s << " s simulated, " << s.collisions << " collisions, "
              << s.blocked_segments << " blocked segments -> " << o.out_dir << std::endl;
    return 0;
  });
}

SimRunSummary SimApp::execute(const SimOptions& opts)
{
  namespace fs = std::filesystem;
  auto cfg = loadConfig(opts);
  if (const auto w = cfg.profileOverrideWarning(opts.config); !w.empty())
    std::cerr << "mrpt-sim: warning: " << w << "\n";
  if (opts.seed) cfg.sim.seed = *opts.seed;
  if (opts.no_noise)
  {
    cfg.sim.sensor_noise = false;
    cfg.robot.odometry_noise = false;
    cfg.robot.motion_noise_rel = 0.0;
  }
  std::optional<mrpt::poses::CPose2D> start;
  if (opts.start) start = sim::parseStartPose(*opts.start);
  auto world = sim::loadWorld(opts.world, start);
  const auto waypoints = sim::loadWaypointsFile(opts.waypoints);
  prepareOutputDir(opts.out_dir);

  mrpt::config::CConfigFileMemory used;
  cfg.save(used);
  {
    std::ofstream f(fs::path(opts.out_dir) / "params.ini");
    f << "# mrpt-sim parameters in force\n" << used.getContent();
  }
  if (!opts.quiet)
    std::cout << "mrpt-sim: world '" << world.source_path << "' (" << world.mesh.numTriangles()
              << " triangles), start " << world.start << ", " << waypoints.size()
              << " waypoints\n--- parameters in force ---\n"
              << used.getContent() << "---------------------------" << std::endl;

  sim::Simulator simulator(std::move(world), cfg.robot, cfg.cameras, cfg.sim);
  common::RawlogWriter rawlog((fs::path(opts.out_dir) / "run.rawlog").string());
  common::TumWriter gt_tum((fs::path(opts.out_dir) / "trajectory_gt.tum").string());
  common::TumWriter odo_tum((fs::path(opts.out_dir) / "trajectory_odo.tum").string());
  std::vector<mrpt::poses::CPose2D> trajectory;
  common::Progress progress("mrpt-sim", waypoints.size(), !opts.quiet);
  std::size_t waypoints_done = 0;

  const auto tour = sim::runTour(
      simulator, waypoints,
      [&](const sim::ScanStop& stop) {
        rawlog.write(*stop.actions, *stop.observations);
        const double t = mrpt::Clock::toDouble(stop.timestamp);
        gt_tum.write(t, mrpt::poses::CPose3D(stop.T_world_robot_gt));
        odo_tum.write(t, mrpt::poses::CPose3D(stop.odometry));
        trajectory.push_back(stop.T_world_robot_gt);
        progress.update(waypoints_done, "stop " + std::to_string(stop.index));
      },
      [&](std::size_t done, std::size_t) {
        waypoints_done = done;
        progress.update(done);
      },
      [] { return interruptRequested(); });
  progress.finish();

  sim::writeTopView(simulator.world(), simulator.caster(),
                    (fs::path(opts.out_dir) / "topview.png").string(), 50.0, trajectory,
                    cfg.robot.height_m);

  SimRunSummary s;
  s.stops = tour.stops;
  s.blocked_segments = tour.blocked_segments;
  s.collisions = simulator.robot().collisions();
  s.path_length_m = tour.path_length_m;
  s.sim_time_s = simulator.simTime();
  s.interrupted = tour.stopped_early;
  return s;
}

}  // namespace voxplore::apps
