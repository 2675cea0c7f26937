#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/core/format.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <voxplore/apps/ReplayApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/Progress.h>
#include <voxplore/common/config.h>
#include <voxplore/common/rawlog_io.h>
#include <voxplore/eval/trajectory_error.h>
#include <voxplore/mapping/SlamIcp.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace voxplore::apps
{
namespace fs = std::filesystem;

namespace
{
const char* kDescription =
    "voxplore-replay: offline SlamIcp (thesis 4.4) over a rawlog holding "
    "CObservation3DRangeScan depth images and odometry (CObservationOdometry or "
    "CActionRobotMovement2D) per entry: odometry prediction, planar ICP of the merged "
    "cloud against the metaview, point reduction, OctoMap integration. Writes "
    "DIR/map.bt, DIR/map.simplemap, DIR/metaview.ply, DIR/trajectory_est.tum, DIR/trajectory_online.tum, "
    "DIR/stops.csv (per-stop timings and ICP quality), DIR/params.ini and DIR/summary.json. "
    "With ground truth (--gt, or trajectory_gt.tum beside the rawlog) it reports the "
    "trajectory error. Faulty depth images (NaN/inf/zero/negative units, bad intrinsics or "
    "pose, impossible ranges) are skipped with a warning naming the stop and camera. SIGINT "
    "or SIGTERM stops after the current stop, writes every output (termination_reason "
    "\"interrupted\") and exits with 130; a second one kills at once. A corrupt or truncated "
    "rawlog (even bytes that crash MRPT's deserialisation: each object is parsed in a child "
    "process first) ends in one error line naming the file, the entry and its byte offset, "
    "exit code 1, with every output of the stops before it written (termination_reason "
    "\"rawlog error\"); --verbose adds MRPT's whole message.";

mapping::SlamIcpParams loadParams(const std::string& path)
{
  mapping::SlamIcpParams p;
  if (path.empty()) return p;
  const auto cfg = common::openIniFile(path);
  const auto secs = mapping::SlamIcpParams::sections();
  common::assertKnownSections(*cfg, {secs.begin(), secs.end()});
  p.load(*cfg);
  return p;
}

std::string classCounts(const std::map<std::string, std::size_t>& counts)
{
  std::ostringstream os;
  bool first = true;
  for (const auto& [name, n] : counts)
  {
    os << (first ? "" : ", ") << name << " x " << n;
    first = false;
  }
  return counts.empty() ? "nothing" : os.str();
}

void writeSummary(const ReplaySummary& s, const std::string& path)
{
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  f << "{\n  \"termination_reason\": \"" << s.termination_reason << "\",\n  \"entries\": "
    << s.entries << ",\n  \"stops\": " << s.stops << ",\n  \"flagged\": " << s.flagged
    << ",\n  \"integrated\": " << s.integrated << ",\n  \"relocalized\": " << s.relocalized << ",\n  \"skipped_cameras\": "
    << s.skipped_cameras << ",\n  \"warnings\": " << s.warnings
    << ",\n  \"degenerate\": " << s.degenerate
    << ",\n  \"missing_odometry\": " << s.missing_odometry
    << ",\n  \"metaview_points\": " << s.metaview_points
    << ",\n  \"loop_closures\": " << s.loop_closures << ",\n  \"loop_edges\": " << s.loop_edges
    << ",\n  \"loop_max_shift_m\": " << s.loop_max_shift_m << ",\n  \"loop_stops\": [";
  for (std::size_t i = 0; i < s.loop_stops.size(); i++) f << (i ? ", " : "") << s.loop_stops[i];
  f << "]"
    << ",\n  \"mean_stop_ms\": " << s.mean_stop_ms;
  if (s.has_ground_truth)
    f << ",\n  \"ate_rmse_m\": " << s.ate_rmse_m << ",\n  \"ate_online_rmse_m\": " << s.ate_online_rmse_m
      << ",\n  \"ate_max_m\": " << s.ate_max_m
      << ",\n  \"final_xy_error_m\": " << s.final_xy_error_m
      << ",\n  \"final_yaw_error_deg\": " << s.final_yaw_error_deg;
  f << "\n}\n";
}
}  // namespace

int ReplayApp::run(int argc, const char* const* argv)
{
  return runGuarded("voxplore-replay", [&]() {
    TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
    TCLAP::ValueArg<std::string> config("c", "config", "ini file ([cloud] [metaview] [icp] [octomap])",
                                        false, "", "INI", cmd);
    TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "Input rawlog", true, "", "FILE", cmd);
    TCLAP::ValueArg<std::string> out("o", "out", "Output directory (created)", true, "", "DIR", cmd);
    TCLAP::ValueArg<std::string> gt("g", "gt", "Ground-truth TUM trajectory", false, "", "TUM", cmd);
    TCLAP::SwitchArg no_icp("", "no-icp", "Odometry only (overrides [icp] enabled)", cmd);
    TCLAP::ValueArg<std::size_t> max_stops("n", "max-stops", "Process at most N stops", false, 0,
                                           "N", cmd);
    TCLAP::SwitchArg quiet("q", "quiet", "No progress bar", cmd);
    TCLAP::SwitchArg verbose("v", "verbose",
                             "On a corrupt rawlog, print MRPT's whole message (with its backtrace) "
                             "before the one-line error",
                             cmd);
    if (!cmd.parse(argc, const_cast<const char**>(argv))) return exitCodeAfterFailedParse(argc, argv);
    installInterruptHandler();
    ReplayOptions o;
    o.config = config.getValue();
    o.rawlog = rawlog.getValue();
    o.out_dir = out.getValue();
    o.ground_truth = gt.getValue();
    if (no_icp.getValue()) o.icp = false;
    o.max_stops = max_stops.getValue();
    o.quiet = quiet.getValue();
    o.verbose = verbose.getValue();
    ReplaySummary s;
    try
    {
      s = execute(o);
    }
    catch (const common::RawlogError& e)
    {
      if (o.verbose && !e.details().empty())
        std::cerr << "voxplore-replay: details of the error below:\n" << e.details() << std::endl;
      throw;
    }
    std::cout << "voxplore-replay: " << s.stops << " stops (" << s.flagged << " flagged, "
              << s.degenerate << " degenerate), metaview " << s.metaview_points << " points, "
              << s.mean_stop_ms << " ms per stop";
    if (s.has_ground_truth)
      std::cout << "; ATE RMSE " << s.ate_rmse_m << " m, final yaw error "
                << s.final_yaw_error_deg << " deg";
    std::cout << " -> " << o.out_dir << std::endl;
    if (s.termination_reason == "interrupted")
    {
      std::cerr << "voxplore-replay: interrupted after " << s.stops
                << " stops; the outputs of those stops are complete in " << o.out_dir
                << " (exit code " << kExitInterrupted << ")" << std::endl;
      return kExitInterrupted;
    }
    return 0;
  });
}

ReplaySummary ReplayApp::execute(const ReplayOptions& opts)
{
  auto params = loadParams(opts.config);
  if (opts.icp) params.icp.enabled = *opts.icp;
  if (!fs::is_regular_file(opts.rawlog))
    throw std::runtime_error("rawlog file not found: '" + opts.rawlog + "'");
  prepareOutputDir(opts.out_dir);
  mrpt::config::CConfigFileMemory used;
  params.save(used);
  std::ofstream(fs::path(opts.out_dir) / "params.ini")
      << "# voxplore-replay parameters in force\n" << used.getContent();
  if (!opts.quiet)
    std::cout << "voxplore-replay: " << opts.rawlog << "\n--- parameters in force ---\n"
              << used.getContent() << "---------------------------" << std::endl;

  mapping::SlamIcp slam(params);
  ReplaySummary s;
  std::map<std::string, std::size_t> other_classes;
  // The number of stops is unknown before the end: a count, no bar.
  common::Progress progress("voxplore-replay", 0, !opts.quiet, "stops");
  auto visit = [&](const common::RawlogEntry& e) {
    if (interruptRequested())  // SIGINT / SIGTERM: stop between two stops, write everything
    {
      s.termination_reason = "interrupted";
      return false;
    }
    s.entries++;
    // Every entry's odometry counts (action increments accumulate) even when
    // the entry is not a stop.
    auto odo = slam.odometryOf(e.actions.get(), *e.observations);
    const auto depth = mapping::allDepthObservationsOf(*e.observations);
    if (depth.empty())
    {
      for (const auto& o : *e.observations) other_classes[o->GetRuntimeClass()->className]++;
      return true;
    }
    if (!odo)
    {
      s.missing_odometry++;
      std::cerr << "\nvoxplore-replay: warning: " << opts.rawlog << " entry " << e.index
                << ": no odometry (CObservationOdometry or CActionRobotMovement2D); assuming no "
                   "motion since the previous stop\n";
      odo = slam.reports().empty() ? mrpt::poses::CPose2D() : slam.reports().back().odometry;
    }
    // The stop's time: its odometry reading's, else the last exposure's (a
    // scan taken while driving exposes its cameras one after another and is
    // delivered with the odometry at the last one).
    auto t_stop = depth.front()->timestamp;
    for (const auto& d : depth) t_stop = std::max(t_stop, d->timestamp);
    if (const auto o = e.observations->getObservationByClass<mrpt::obs::CObservationOdometry>())
      t_stop = o->timestamp;
    const auto rep = slam.processStop(*e.observations, *odo, t_stop);
    for (const auto& w : rep.warnings)
    {
      s.warnings++;
      std::cerr << "\nvoxplore-replay: warning: " << opts.rawlog << " entry " << e.index
                << ", stop " << rep.index << ": " << w << "\n";
    }
    if (rep.cloud_points == 0 && rep.cameras_used > 0)
      std::cerr << "\nvoxplore-replay: warning: " << opts.rawlog << " entry " << e.index
                << ": no valid depth above the floor in " << rep.cameras_used << " images\n";
    if (rep.loop.closed && !opts.quiet)
      std::cout << "\nvoxplore-replay: stop " << rep.index << ": " << rep.loop.message
                << (rep.loop.rebuilt ? mrpt::format(" (maps corrected in %.0f ms; OctoMap: %zu "
                                                    "keyframes left to re-insert)",
                                                    rep.loop.t_rebuild_ms, rep.octomap_rebuild_left)
                                     : std::string())
                << "\n";
    s.stops++;
    progress.update(s.stops, "stop " + std::to_string(rep.index) + (rep.flagged ? " FLAGGED: " + rep.icp.reason : ""));
    if (opts.max_stops != 0 && s.stops >= opts.max_stops)
    {
      s.termination_reason = "max_stops";
      return false;
    }
    return true;
  };
  // A corrupt or truncated rawlog, even one that crashes MRPT (the reader
  // parses each object in a child process first), ends in one error line
  // naming the file and entry, after every output of the stops before it.
  std::optional<common::RawlogError> read_error;
  common::RawlogReadOptions read_opts;
  read_opts.child_output = opts.verbose;
  try
  {
    common::forEachRawlogEntry(opts.rawlog, visit, read_opts);
  }
  catch (const common::RawlogError& e)
  {
    read_error = e;
    s.termination_reason = "rawlog error";
  }
  catch (const std::exception& e)
  {
    progress.finish();
    if (slam.numStops() == 0) throw;
    slam.saveOutputs(opts.out_dir);
    throw std::runtime_error(std::string(e.what()) + " (the map of the " +
                             std::to_string(slam.numStops()) + " stops before it was written to " +
                             opts.out_dir + ")");
  }
  progress.finish();
  // The reader's error, with what was written before it.
  const auto rethrowReadError = [&](const std::string& what_was_written) {
    throw common::RawlogError(std::string(read_error->what()) + what_was_written,
                              read_error->details(), read_error->entry(), read_error->byteOffset());
  };
  if (read_error && s.stops == 0) rethrowReadError("; no stop before it, nothing written");
  if (s.stops == 0 && s.termination_reason == "interrupted")
    throw std::runtime_error("interrupted before the first stop of " + opts.rawlog +
                             "; nothing written");
  if (s.stops == 0)
    throw std::runtime_error(opts.rawlog + ": no CObservation3DRangeScan with a range image in " +
                             std::to_string(s.entries) + " entries (found: " +
                             classCounts(other_classes) + "); voxplore needs depth images");
  slam.saveOutputs(opts.out_dir);

  double total_ms = 0;
  for (const auto& r : slam.reports())
  {
    total_ms += r.t_total_ms;
    s.flagged += r.flagged;
    s.integrated += r.integrated;
    s.relocalized += r.relocalized;
    for (const auto& i : r.camera_issues) s.skipped_cameras += i.skipped;
    s.degenerate += r.icp.degenerate;
    if (r.loop.closed) s.loop_stops.push_back(r.index);
  }
  s.loop_closures = slam.loopClosures();
  s.loop_edges = slam.loopCloser().numLoopEdges();
  s.loop_max_shift_m = slam.maxGraphShift();
  s.mean_stop_ms = total_ms / double(s.stops);
  s.metaview_points = slam.metaview().size();

  std::string gt = opts.ground_truth;
  const auto beside = fs::path(opts.rawlog).parent_path() / "trajectory_gt.tum";
  if (gt.empty() && fs::is_regular_file(beside)) gt = beside.string();
  if (!gt.empty())
  {
    const auto gt_poses = common::readTum(gt);
    const auto err = eval::trajectoryError(
        common::readTum((fs::path(opts.out_dir) / "trajectory_est.tum").string()), gt_poses);
    s.has_ground_truth = true;
    s.ate_rmse_m = err.ate_rmse_m;
    s.ate_online_rmse_m =
        eval::trajectoryError(
            common::readTum((fs::path(opts.out_dir) / "trajectory_online.tum").string()), gt_poses)
            .ate_rmse_m;
    s.ate_max_m = err.ate_max_m;
    s.final_xy_error_m = err.final_xy_error_m;
    s.final_yaw_error_deg = mrpt::RAD2DEG(err.final_yaw_error_rad);
  }
  writeSummary(s, (fs::path(opts.out_dir) / "summary.json").string());
  if (read_error)
    rethrowReadError(" (the outputs of the " +
                     (s.stops == 1 ? std::string("stop") : std::to_string(s.stops) + " stops") +
                     " before it are in " + opts.out_dir + ")");
  return s;
}

}  // namespace voxplore::apps
