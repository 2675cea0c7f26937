// voxplore-bench: end-to-end benchmark tables beside the thesis' figures
// (chapter 5). One table set per name; `voxplore-bench --help` lists them.
//
//   slam              table 5.1 (d_min sweep) and the table 5.2 row "integration into V"
//   slam-dmin         table 5.1 only
//   slam-integration  the table 5.2 row only (poses: ICP replay at d_min 20 mm, or --poses gt)
//   registration      each stop's ICP alone: against the ground-truth map of the stops before it
//   loops             loop closure (issue 11): detection, relaxation and map rebuild time and
//                     memory against the number of keyframes (all stops of --rawlog)
//   planner           table 5.2's planner rows (projection ... path) beside the naive scan rating
//   all               every set above
//   strategies        exploration end to end, nbv beside nearest on every world (issue 5;
//                     minutes, so not part of 'all')
//
// Later tables register in tables() below.
#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/config.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>

#include "bench_loops.h"
#include "bench_planner.h"
#include "bench_registration.h"
#include "bench_slam.h"
#include "bench_strategies.h"
#include "bench_table.h"

using namespace voxplore;

namespace
{
const char* kDescription =
    "voxplore-bench: end-to-end benchmark tables, ours beside stock OctoMap and the "
    "thesis' figures (Xeon W3520 2.66 GHz) in the same run. Tables: 'slam' = table 5.1 "
    "(metaview point reduction d_min: integration into M, ICP, points in M, ATE against "
    "ground truth) and table 5.2's row 'integration into V' (l_res sweep, "
    "OctoMapLayer::insertScan vs OcTree::insertPointCloud); 'slam-dmin' and "
    "'slam-integration' run one of them; 'planner' = table 5.2's planner rows; 'strategies' = "
    "voxplore-explore on every world with --strategy nbv beside nearest (steps, travel, "
    "coverage, compute time; shared worlds from simulated_worlds/shared_world_starts.txt); "
    "'registration' = each stop's ICP alone, against the ground-truth map of the stops before "
    "it (--rawlog, --gt, --stops, --config); 'loops' = issue 11's loop closure cost against the "
    "number of keyframes (--keyframes, default 100,500,1000,2000, keyframe k = stop k mod M of "
    "--rawlog at its ground-truth pose): detection against all old keyframes, the pose graph's "
    "relaxation, the metaview + OctoMap rebuild, memory per keyframe (reads every stop: -n is "
    "ignored; --revisits loop closures per column; --repeat). Run it "
    "pinned to one core in a Release build: "
    "taskset -c 1 build/bin/voxplore-bench";

/// Everything the command line sets (each table reads its part).
struct BenchOptions
{
  bench::SlamBenchOptions slam;
  bench::StrategyBenchOptions strategies;
  bench::LoopBenchOptions loops;
};

/// A named set of tables.
struct TableSet
{
  std::string name;
  std::function<void(const BenchOptions&, std::ostream&)> run;
};

void runSlam(const bench::SlamBenchOptions& o, bool dmin, bool integration, std::ostream& out)
{
  const auto data = bench::loadSlamBenchData(o);
  if (!o.quiet)
  {
    mrpt::config::CConfigFileMemory used;
    data.params.save(used);
    std::cerr << "voxplore-bench: " << data.stops.size() << " stops of " << o.rawlog
              << "\n--- SlamIcp parameters in force ([metaview] d_min_m and [octomap] l_res_m "
                 "are swept) ---\n"
              << used.getContent() << "---\n";
  }
  if (!o.csv_dir.empty())
  {
    mrpt::config::CConfigFileMemory used;
    data.params.save(used);
    std::ofstream(std::filesystem::path(o.csv_dir) / "params.ini")
        << "# voxplore-bench SlamIcp parameters in force (d_min_m and l_res_m are swept)\n"
        << used.getContent();
  }
  std::vector<mrpt::poses::CPose3D> icp_poses;
  if (dmin) icp_poses = bench::runDminTable(data, o, out);
  out << std::flush;
  if (integration)
    bench::runIntegrationTable(data, o, bench::integrationPoses(data, o, icp_poses), out);
  out << std::flush;
}

std::vector<TableSet> tables()
{
  return {
      {"slam", [](const BenchOptions& o, std::ostream& out) { runSlam(o.slam, true, true, out); }},
      {"slam-dmin",
       [](const BenchOptions& o, std::ostream& out) { runSlam(o.slam, true, false, out); }},
      {"slam-integration",
       [](const BenchOptions& o, std::ostream& out) { runSlam(o.slam, false, true, out); }},
      {"planner",
       [](const BenchOptions& o, std::ostream& out) { bench::runPlannerTable(o.slam, out); }},
      {"all",
       [](const BenchOptions& o, std::ostream& out)
       {
         runSlam(o.slam, true, true, out);
         bench::runPlannerTable(o.slam, out);
       }},
      {"strategies", [](const BenchOptions& o, std::ostream& out)
       { bench::runStrategiesTable(o.strategies, out); }},
      {"registration", [](const BenchOptions& o, std::ostream& out)
       { bench::runRegistrationTable(bench::loadSlamBenchData(o.slam), o.slam, out); }},
      {"loops",
       [](const BenchOptions& o, std::ostream& out)
       {
         auto all = o.slam;
         all.stops = std::numeric_limits<std::size_t>::max();  // every stop of the rawlog
         bench::runLoopsTable(bench::loadSlamBenchData(all), all, o.loops, out);
       }},
  };
}

/// A list of millimetres ("0,5,10") as metres; each must be >= min_mm.
std::vector<double> millimetres(const std::string& text, const std::string& what, double min_mm)
{
  std::vector<double> m;
  for (const double mm : common::parseNumberList(text, what))
  {
    if (!(mm >= min_mm))
      throw std::runtime_error(what + ": " + bench::fixed(mm, 3) + " mm is below " +
                               bench::fixed(min_mm, 3) + " mm");
    m.push_back(mm * 1e-3);
  }
  if (m.empty()) throw std::runtime_error(what + ": empty list");
  return m;
}

std::string joinMm(const std::vector<double>& metres)
{
  std::ostringstream os;
  for (std::size_t i = 0; i < metres.size(); i++) os << (i ? "," : "") << metres[i] * 1e3;
  return os.str();
}

void printHeader(const std::string& table, std::ostream& out)
{
  const int cpus = bench::allowedCpus();
  out << "voxplore-bench '" << table << "', " << bench::nowString() << "\n"
      << "CPU: " << bench::cpuModel() << "; CPUs allowed: " << cpus
      << "; build: " << VOXPLORE_BUILD_TYPE << "\n";
  if (cpus != 1)
    std::cerr << "voxplore-bench: warning: not pinned to one core; the tables compare "
                 "one-core times (run under taskset -c 1)\n";
  if (std::string(VOXPLORE_BUILD_TYPE) != "Release")
    std::cerr << "voxplore-bench: warning: build type '" << VOXPLORE_BUILD_TYPE
              << "', not Release: timings mean little\n";
}

int run(int argc, char** argv)
{
  const auto sets = tables();
  std::vector<std::string> names;
  for (const auto& s : sets) names.push_back(s.name);
  TCLAP::ValuesConstraint<std::string> table_names(names);
  std::vector<std::string> pose_sources{"icp", "gt"};
  TCLAP::ValuesConstraint<std::string> pose_names(pose_sources);
  const std::string src = VOXPLORE_SOURCE_DIR;

  TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
  TCLAP::UnlabeledValueArg<std::string> table_pos("table_set", "Table set to run (default slam)",
                                                  false, "", &table_names, cmd);
  TCLAP::ValueArg<std::string> table_opt("t", "table", "Table set to run (same as the positional)",
                                         false, "", &table_names, cmd);
  TCLAP::ValueArg<std::string> rawlog("r", "rawlog", "Input rawlog (plain or gzip)", false,
                                      src + "/rawlogs/dlr_test_room/run.rawlog", "FILE", cmd);
  TCLAP::ValueArg<std::string> gt("g", "gt",
                                  "Ground-truth TUM trajectory (default: "
                                  "trajectory_gt.tum beside the rawlog, if any)",
                                  false, "", "TUM", cmd);
  TCLAP::ValueArg<std::string> config("c", "config",
                                      "SlamIcp ini, e.g. config/replay.ini "
                                      "(default: built-in thesis defaults)",
                                      false, "", "INI", cmd);
  TCLAP::ValueArg<std::size_t> stops("n", "stops", "Replay the first N stops", false, 10, "N", cmd);
  TCLAP::ValueArg<std::string> dmin("", "dmin", "Table 5.1 d_min values [mm]", false,
                                    joinMm(bench::thesisDminSweep()), "LIST", cmd);
  TCLAP::ValueArg<std::string> lres("", "lres", "Table 5.2 l_res values [mm]", false,
                                    joinMm(bench::thesisLresSweep()), "LIST", cmd);
  TCLAP::ValueArg<std::string> poses("", "poses",
                                     "Table 5.2 poses: ICP replay at d_min 20 mm "
                                     "or ground truth",
                                     false, "icp", &pose_names, cmd);
  TCLAP::ValueArg<unsigned> repeat("", "repeat", "Run each column R times; report the median",
                                   false, 1, "R", cmd);
  TCLAP::ValueArg<std::string> csv("", "csv", "Write the tables as CSV into DIR (created)", false,
                                   "", "DIR", cmd);
  TCLAP::ValueArg<int> max_steps("", "max-steps",
                                 "strategies: planning steps at most per run (overrides "
                                 "[explore] max_steps of config/explore.ini)",
                                 false, 0, "N", cmd);
  TCLAP::ValueArg<std::string> keyframes("", "keyframes", "loops: keyframe counts, one column each",
                                         false, "100,500,1000,2000", "LIST", cmd);
  TCLAP::ValueArg<std::size_t> revisits("", "revisits",
                                        "loops: loop closures per column (revisits are tried until "
                                        "this many closed, at most 4x as many)",
                                        false, bench::LoopBenchOptions{}.queries, "N", cmd);
  TCLAP::SwitchArg quiet("q", "quiet", "No progress or parameters on stderr", cmd);
  if (!cmd.parse(argc, argv)) return apps::exitCodeAfterFailedParse(argc, argv);

  if (!table_pos.getValue().empty() && !table_opt.getValue().empty() &&
      table_pos.getValue() != table_opt.getValue())
    throw std::runtime_error("two different tables asked for: '" + table_pos.getValue() +
                             "' and --table '" + table_opt.getValue() + "'");
  std::string table = table_pos.getValue().empty() ? table_opt.getValue() : table_pos.getValue();
  if (table.empty()) table = "slam";
  if (repeat.getValue() == 0) throw std::runtime_error("--repeat must be at least 1");

  BenchOptions o;
  o.slam.rawlog = rawlog.getValue();
  o.slam.ground_truth = gt.getValue();
  o.slam.config = config.getValue();
  o.slam.stops = stops.getValue();
  o.slam.d_min_m = millimetres(dmin.getValue(), "--dmin", 0.0);
  o.slam.l_res_m = millimetres(lres.getValue(), "--lres", 1.0);
  o.slam.poses_from_gt = poses.getValue() == "gt";
  o.slam.repeat = repeat.getValue();
  o.slam.csv_dir = csv.getValue();
  o.slam.quiet = quiet.getValue();
  if (!o.slam.csv_dir.empty()) apps::prepareOutputDir(o.slam.csv_dir);
  o.strategies.config = src + "/config/explore.ini";
  o.strategies.source_dir = src;
  o.strategies.shared_worlds_dir = VOXPLORE_SHARED_WORLDS_DIR;
  o.strategies.starts_file = src + "/simulated_worlds/shared_world_starts.txt";
  if (max_steps.isSet()) o.strategies.max_steps = max_steps.getValue();
  o.strategies.csv_dir = o.slam.csv_dir;
  o.strategies.quiet = o.slam.quiet;

  o.loops.keyframes.clear();
  for (const double n : common::parseNumberList(keyframes.getValue(), "--keyframes"))
  {
    if (!(n >= 2) || n != std::floor(n))
      throw std::runtime_error("--keyframes: " + bench::fixed(n, 3) +
                               " is not a whole number >= 2");
    o.loops.keyframes.push_back(static_cast<std::size_t>(n));
  }
  if (o.loops.keyframes.empty()) throw std::runtime_error("--keyframes: empty list");
  if (revisits.getValue() == 0) throw std::runtime_error("--revisits must be at least 1");
  o.loops.queries = revisits.getValue();

  printHeader(table, std::cout);
  for (const auto& s : sets)
    if (s.name == table) s.run(o, std::cout);
  if (!o.slam.csv_dir.empty()) std::cout << "\nCSV written to " << o.slam.csv_dir << std::endl;
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  return apps::runGuarded("voxplore-bench", [&]() { return run(argc, argv); });
}
