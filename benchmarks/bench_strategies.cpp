// voxplore-bench: nbv (thesis) beside the nearest-frontier baseline, end to end
// through voxplore-explore's loop on every world (issue 5).
#include "bench_strategies.h"

#include <voxplore/apps/ExploreApp.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "bench_table.h"

namespace voxplore::bench
{
namespace fs = std::filesystem;

namespace
{
/// A world to explore: its file, the start override and the robot profile.
struct BenchWorld
{
  std::string name;
  std::string file;
  std::optional<std::string> start;  ///< "x,y,yaw_deg"; none: the world file's
  std::string robot;
};

std::vector<BenchWorld> benchWorlds(const StrategyBenchOptions& o)
{
  std::vector<BenchWorld> worlds;
  for (const char* n : {"dlr_test_room", "office"})
    worlds.push_back(
        {n, (fs::path(o.source_dir) / "simulated_worlds" / (std::string(n) + ".world")).string(),
         std::nullopt, "omnirob"});
  if (!fs::is_directory(o.shared_worlds_dir))
  {
    std::cerr << "voxplore-bench: WARNING: " << o.shared_worlds_dir
              << " is missing: the shared worlds are skipped\n";
    return worlds;
  }
  for (const auto& s : readSharedWorldStarts(o.starts_file))
  {
    const auto file = fs::path(o.shared_worlds_dir) / s.relative_path;
    if (!fs::is_regular_file(file))
    {
      std::cerr << "voxplore-bench: WARNING: " << file.string() << " is missing: skipped\n";
      continue;
    }
    std::ostringstream start;
    start << s.x_m << "," << s.y_m << "," << s.yaw_deg;
    worlds.push_back(
        {fs::path(s.relative_path).parent_path().string(), file.string(), start.str(), s.robot});
  }
  return worlds;
}

apps::ExploreSummary explore(const StrategyBenchOptions& o, const BenchWorld& w,
                             const std::string& strategy)
{
  apps::ExploreOptions e;
  e.config = o.config;
  e.world = w.file;
  e.start = w.start;
  e.robot = w.robot;
  e.strategy = strategy;
  e.max_steps = o.max_steps;
  e.out_dir = (fs::path(o.out_root) / (w.name + "_" + strategy)).string();
  e.quiet = true;
  if (!o.quiet)
    std::cerr << "voxplore-bench: exploring " << w.name << " with " << strategy << " ...";
  try
  {
    const auto s = apps::ExploreApp{}.execute(e);
    if (!o.quiet)
      std::cerr << " " << s.termination_reason << " after " << s.steps << " steps, coverage "
                << fixed(s.coverage_2d, 3) << " (" << e.out_dir << ")\n";
    return s;
  }
  catch (const std::exception& ex)
  {
    // A failed run is a result of the comparison: its row says so and the
    // table goes on with the other runs.
    std::cerr << "\nvoxplore-bench: ERROR: " << w.name << " with strategy " << strategy << ": "
              << ex.what() << "\n";
    apps::ExploreSummary failed;
    failed.termination_reason = "ERROR (see stderr)";
    return failed;
  }
}

double ratio(double a, double b)
{
  return b > 0 ? a / b : 0.0;
}
}  // namespace

std::vector<SharedWorldStart> readSharedWorldStarts(const std::string& path)
{
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read '" + path + "'");
  std::vector<SharedWorldStart> starts;
  std::string line;
  for (int n = 1; std::getline(f, line); n++)
  {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream is(line);
    SharedWorldStart s;
    if (!(is >> s.relative_path)) continue;  // blank or comment
    std::string extra;
    if (!(is >> s.x_m >> s.y_m >> s.yaw_deg >> s.robot) || (is >> extra))
      throw std::runtime_error(path + ":" + std::to_string(n) +
                               ": expected '<relative path> x y yaw_deg robot'");
    starts.push_back(s);
  }
  return starts;
}

void runStrategiesTable(const StrategyBenchOptions& opts, std::ostream& out)
{
  TextTable t({{"world", "world"},
               {"robot", "robot"},
               {"steps nbv", "steps_nbv"},
               {"steps nearest", "steps_nearest"},
               {"path nbv [m]", "path_nbv_m"},
               {"path nearest [m]", "path_nearest_m"},
               {"travel nbv/nearest", "travel_ratio"},
               {"per coverage", "travel_ratio_per_coverage"},
               {"coverage nbv", "coverage_2d_nbv"},
               {"coverage nearest", "coverage_2d_nearest"},
               {"compute nbv [s]", "compute_nbv_s"},
               {"compute nearest [s]", "compute_nearest_s"},
               {"end nbv", "termination_nbv"},
               {"end nearest", "termination_nearest"},
               {"collisions nbv/nearest", "collisions"},
               {"coverage circumradius nbv/nearest", "coverage_2d_circumradius"},
               {"min clearance nbv/nearest [m]", "min_clearance_m"},
               {"ATE nbv/nearest [m]", "ate_rmse_m"}});
  for (const auto& w : benchWorlds(opts))
  {
    const auto a = explore(opts, w, "nbv");
    const auto b = explore(opts, w, "nearest");
    // A failed run (ERROR) has no figures: its cells and the ratios show "-".
    const auto ok = [](const apps::ExploreSummary& s) { return s.steps > 0; };
    const auto cell = [&](const apps::ExploreSummary& s, double v, int decimals)
    { return ok(s) ? fixed(v, decimals) : std::string("-"); };
    const bool both = ok(a) && ok(b);
    const auto both_or = [&](double v) { return both ? fixed(v, 2) : std::string("-"); };
    t.addRow({w.name, w.robot, ok(a) ? std::to_string(a.steps) : "-",
              ok(b) ? std::to_string(b.steps) : "-", cell(a, a.path_length_m, 1),
              cell(b, b.path_length_m, 1), both_or(ratio(a.path_length_m, b.path_length_m)),
              both_or(ratio(ratio(a.path_length_m, a.coverage_2d),
                            ratio(b.path_length_m, b.coverage_2d))),
              cell(a, a.coverage_2d, 3), cell(b, b.coverage_2d, 3), cell(a, a.compute_s, 1),
              cell(b, b.compute_s, 1), a.termination_reason, b.termination_reason,
              std::to_string(a.collisions) + "/" + std::to_string(b.collisions),
              cell(a, a.coverage_2d_circumradius, 3) + "/" + cell(b, b.coverage_2d_circumradius, 3),
              cell(a, a.min_clearance_m, 3) + "/" + cell(b, b.min_clearance_m, 3),
              cell(a, a.ate_rmse_m, 3) + "/" + cell(b, b.ate_rmse_m, 3)});
  }
  out << "\nExploration strategies end to end (issue 5): voxplore-explore's loop with "
         "--strategy nbv (next best view, thesis) beside nearest (nearest frontier's "
         "centroid); config "
      << opts.config << (opts.max_steps ? ", max_steps " + std::to_string(*opts.max_steps) : "")
      << "\npath = ground-truth travel; travel nbv/nearest = path ratio (< 1: nbv travels "
         "less); per coverage = (path/coverage_2d) ratio; compute = SLAM + planning wall time\n"
      << t.str() << std::flush;
  if (!opts.csv_dir.empty()) t.writeCsv((fs::path(opts.csv_dir) / "strategies.csv").string());
}

}  // namespace voxplore::bench
