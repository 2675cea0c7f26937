// voxplore-bench: the exploration planner rows of thesis table 5.2 (issue 4),
// ours beside the thesis' figures and the naive scan rating in the same run.
#include "bench_planner.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <octomap/OcTree.h>
#include <voxplore/common/Progress.h>
#include <voxplore/exploration/Planner.h>
#include <voxplore/exploration/scan_rating.h>
#include <voxplore/mapping/SlamIcp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "bench_table.h"

namespace voxplore::bench
{
namespace fs = std::filesystem;
using exploration::PlannerParams;
using exploration::PlanResult;
using exploration::ScanRating;
using mrpt::poses::CPose2D;

namespace
{
/// Thesis table 5.2, planner rows [ms] (Xeon W3520 2.66 GHz), keyed by l_res [mm].
/// rating: one sample at beam_reduction 3.
struct ThesisPlanner
{
  double projection, collision, frontiers, sampling, rating, path;
};
const std::map<int, ThesisPlanner> kThesisPlanner = {
    {10, {1085, 84, 29, 3240, 1124, 15388}}, {20, {214, 12, 8.7, 201, 637, 1660}},
    {30, {84, 3.9, 3.5, 48, 458, 941}},      {40, {38, 1.7, 2.0, 34, 359, 737}},
    {50, {20, 0.9, 1.4, 11, 285, 674}},      {60, {15, 0.8, 0.9, 6, 236, 622}},
    {80, {8.1, 0.4, 0.6, 1.8, 172, 591}},    {100, {6.0, 0.2, 0.4, 1.2, 139, 589}},
    {120, {2.4, 0.1, 0.2, 0.8, 119, 590}}};

constexpr double kRatingTargetMs = 5.0;  ///< issue 4: one sample, beam_reduction 1, l_res 5 cm
constexpr double kStepTargetMs = 100.0;  ///< issue 4: a whole planning step, 15 samples
constexpr double kTargetLresM = 0.05;
constexpr double kMapDminM = 0.020;      ///< V is built as in table 5.2: d_min 20 mm
constexpr double kNaiveBudgetMs = 60e3;  ///< naive rating per l_res and beam setting

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Medians over the repetitions of one planner setting.
struct StageMs
{
  double projection = 0, collision = 0, frontiers = 0, sampling = 0, path = 0, total = 0;
  std::optional<double> rating_per_sample;  ///< empty when nothing was rated
};

/// The planner at one beam_reduction: medians and the last result.
struct PlannerRun
{
  StageMs ms;
  PlanResult last;
};

/// ours (rateScan) and naive (rateScanNaive) on the same sample poses.
struct RatingCheck
{
  std::size_t beams = 0, samples = 0, naive_samples = 0;
  double ours_ms = 0, naive_ms = 0;  ///< per sample (mean over the samples rated both ways)
  double max_rel_diff = 0;           ///< of the gains
  bool same_counts = true;           ///< voxels and unknown voxels equal for every sample
  double voxels = 0;                 ///< distinct voxels per sample (mean)
};

/// One l_res: the map, the pose planned from, both planner runs, both checks.
struct PlannerColumn
{
  double l_res_m = 0;
  double build_s = 0;
  std::size_t leaves = 0, memory = 0, stop_used = 0, stops = 0;
  std::size_t grid_x = 0, grid_y = 0, frontiers = 0;
  std::string outcome;           ///< PlanResult::message of the thesis setting
  std::size_t last_samples = 0;  ///< samples the plan from the last stop rated
  std::string last_outcome;      ///< why the plan from the last stop failed; empty if it did not
  bool ok = false;
  PlannerRun br3, br1;
  RatingCheck check3, check1;
};

std::unique_ptr<mapping::SlamIcp> buildMap(const SlamBenchData& data, double l_res_m,
                                           common::Progress& progress)
{
  auto params = data.params;
  params.metaview.d_min_m = kMapDminM;
  params.octomap.l_res_m = l_res_m;
  auto slam = std::make_unique<mapping::SlamIcp>(params);
  for (const auto& s : data.stops)  // as replay() in bench_slam.cpp and voxplore-replay
  {
    auto odo = slam->odometryOf(s.actions.get(), *s.observations);
    if (!odo) odo = slam->reports().empty() ? CPose2D() : slam->reports().back().odometry;
    slam->processStop(*s.observations, *odo, s.timestamp);
    progress.update(slam->numStops(), "building V");
  }
  return slam;
}

/// The stop to plan from: the last one whose plan rates a full set of
/// max_samples poses at its first frontier (the thesis' step; no frontier
/// skipped, so the rating time is that of the samples kept), else the last
/// with any sample and no skip, else the last with any sample, else the last
/// stop. Records what the last stop's plan gave in `c`.
std::size_t choosePose(const octomap::OcTree& V, const std::vector<mapping::StopReport>& reports,
                       const PlannerParams& params, PlannerColumn& c)
{
  std::size_t best = reports.size() - 1;
  int best_rank = 0;
  for (std::size_t i = reports.size(); i-- > 0;)
  {
    const PlanResult r = exploration::plan(V, reports[i].pose, params);  // also warms caches
    if (i + 1 == reports.size())
    {
      c.last_samples = r.samples.size();
      c.last_outcome = r.ok() ? "" : std::string(toString(r.done)) + ": " + r.message;
    }
    if (!r.ok() || r.samples.empty()) continue;
    const bool full = r.samples.size() >= static_cast<std::size_t>(params.sampling.max_samples);
    const int rank = !r.skipped_frontiers.empty() ? 1 : full ? 3 : 2;
    if (rank > best_rank)
    {
      best = i;
      best_rank = rank;
    }
    if (rank == 3) break;
  }
  return best;
}

PlannerRun runPlanner(const octomap::OcTree& V, const CPose2D& pose, const PlannerParams& p,
                      unsigned repeat)
{
  std::vector<double> proj, coll, front, samp, rating, path, total;
  PlannerRun run;
  for (unsigned rep = 0; rep < repeat; rep++)
  {
    run.last = exploration::plan(V, pose, p);
    const auto& ms = run.last.ms;
    proj.push_back(ms.projection);
    coll.push_back(ms.collision);
    front.push_back(ms.frontiers);
    samp.push_back(ms.sampling);
    path.push_back(ms.path);
    total.push_back(ms.total);
    if (!run.last.ratings.empty()) rating.push_back(ms.rating / double(run.last.ratings.size()));
  }
  run.ms = {
      median(proj), median(coll), median(front), median(samp), median(path), median(total), {}};
  if (!rating.empty()) run.ms.rating_per_sample = median(rating);
  return run;
}

/// Rates `samples` with rateScan and rateScanNaive back to back (the naive one
/// until kNaiveBudgetMs is spent, at least one sample) and compares the gains.
RatingCheck checkRatings(const octomap::OcTree& V, const std::vector<CPose2D>& samples,
                         const exploration::ScanRatingParams& p)
{
  RatingCheck c;
  c.samples = samples.size();
  double naive_total = 0, ours_total = 0;
  for (const auto& s : samples)
  {
    if (c.naive_samples > 0 && naive_total > kNaiveBudgetMs) break;
    auto t0 = Clock::now();
    const ScanRating ours = exploration::rateScan(V, s, p);
    ours_total += msSince(t0);
    t0 = Clock::now();
    const ScanRating naive = exploration::rateScanNaive(V, s, p);
    naive_total += msSince(t0);
    c.naive_samples++;
    c.beams = ours.beams;
    c.voxels += double(ours.voxels);
    c.max_rel_diff = std::max(
        c.max_rel_diff, std::abs(ours.gain - naive.gain) / std::max(std::abs(naive.gain), 1e-12));
    c.same_counts = c.same_counts && ours.voxels == naive.voxels &&
                    ours.unknown_voxels == naive.unknown_voxels && ours.beams == naive.beams;
  }
  if (c.naive_samples == 0) return c;
  c.ours_ms = ours_total / double(c.naive_samples);
  c.naive_ms = naive_total / double(c.naive_samples);
  c.voxels /= double(c.naive_samples);
  return c;
}

PlannerColumn measureLres(const SlamBenchData& data, const SlamBenchOptions& opts,
                          const PlannerParams& params, double l_res_m)
{
  PlannerColumn c;
  c.l_res_m = l_res_m;
  c.stops = data.stops.size();
  common::Progress progress("planner  l_res " + fixed(l_res_m * 1e3, 0) + " mm",
                            c.stops + 2 * opts.repeat + 3, !opts.quiet);
  const auto t0 = Clock::now();
  const auto slam = buildMap(data, l_res_m, progress);
  c.build_s = 1e-3 * msSince(t0);
  const auto& V = slam->octomap().tree();
  c.leaves = slam->octomap().numLeafNodes();
  c.memory = slam->octomap().memoryUsage();

  c.stop_used = choosePose(V, slam->reports(), params, c);
  progress.update(c.stops + 1, "pose chosen");
  const auto& reports = slam->reports();
  const CPose2D pose = reports[c.stop_used].pose;

  auto params1 = params;
  params1.rating.beam_reduction = 1;
  c.br3 = runPlanner(V, pose, params, opts.repeat);
  progress.update(c.stops + 1 + opts.repeat, "planning, beam_reduction 3");
  c.br1 = runPlanner(V, pose, params1, opts.repeat);
  progress.update(c.stops + 1 + 2 * opts.repeat, "planning, beam_reduction 1");
  const auto& r = c.br3.last;
  c.ok = r.ok();
  c.outcome = r.message;
  c.grid_x = r.ground ? r.ground->state.getSizeX() : 0;
  c.grid_y = r.ground ? r.ground->state.getSizeY() : 0;
  c.frontiers = r.frontiers ? r.frontiers->frontiers.size() : 0;
  c.check3 = checkRatings(V, r.samples, params.rating);
  progress.update(c.stops + 2 + 2 * opts.repeat, "naive rating, beam_reduction 3");
  c.check1 = checkRatings(V, r.samples, params1.rating);
  progress.finish();
  return c;
}

std::optional<double> thesis(double l_res_m, double ThesisPlanner::*field)
{
  const auto it = kThesisPlanner.find(static_cast<int>(std::lround(l_res_m * 1e3)));
  if (it == kThesisPlanner.end() || std::abs(l_res_m * 1e3 - it->first) > 1e-6) return std::nullopt;
  return it->second.*field;
}

/// Milliseconds with 2 decimals below 100, 1 below 1000, else none.
std::string ms(const std::optional<double>& v)
{
  if (!v) return "-";
  return fixed(*v, *v < 100 ? 2 : *v < 1000 ? 1 : 0);
}

TextTable stageTable(const std::vector<PlannerColumn>& cols)
{
  TextTable t({{"l_res [mm]", "l_res_mm"},
               {"projection", "projection_ms"},
               {"thesis", "projection_ms_thesis"},
               {"collision", "collision_ms"},
               {"thesis", "collision_ms_thesis"},
               {"frontiers", "frontiers_ms"},
               {"thesis", "frontiers_ms_thesis"},
               {"sampling", "sampling_ms"},
               {"thesis", "sampling_ms_thesis"},
               {"rating/sample br3", "rating_per_sample_ms_br3"},
               {"thesis", "rating_per_sample_ms_thesis"},
               {"rating/sample br1", "rating_per_sample_ms_br1"},
               {"path", "path_ms"},
               {"thesis", "path_ms_thesis"},
               {"step br3", "step_ms_br3"},
               {"step br1", "step_ms_br1"},
               {"samples", "samples"}});
  for (const auto& c : cols)
  {
    const auto& m = c.br3.ms;
    t.addRow({fixed(c.l_res_m * 1e3, 0), ms(m.projection),
              ms(thesis(c.l_res_m, &ThesisPlanner::projection)), ms(m.collision),
              ms(thesis(c.l_res_m, &ThesisPlanner::collision)), ms(m.frontiers),
              ms(thesis(c.l_res_m, &ThesisPlanner::frontiers)), ms(m.sampling),
              ms(thesis(c.l_res_m, &ThesisPlanner::sampling)), ms(m.rating_per_sample),
              ms(thesis(c.l_res_m, &ThesisPlanner::rating)), ms(c.br1.ms.rating_per_sample),
              ms(m.path), ms(thesis(c.l_res_m, &ThesisPlanner::path)), ms(m.total),
              ms(c.br1.ms.total), std::to_string(c.br3.last.samples.size())});
  }
  return t;
}

TextTable ratingTable(const std::vector<PlannerColumn>& cols)
{
  TextTable t({{"l_res [mm]", "l_res_mm"},
               {"beams br3", "beams_br3"},
               {"ours br3", "ours_ms_br3"},
               {"naive br3", "naive_ms_br3"},
               {"naive/ours", "speedup_br3"},
               {"max rel. diff", "max_rel_gain_diff_br3"},
               {"beams br1", "beams_br1"},
               {"ours br1", "ours_ms_br1"},
               {"naive br1", "naive_ms_br1"},
               {"naive/ours", "speedup_br1"},
               {"max rel. diff", "max_rel_gain_diff_br1"},
               {"voxels br1", "voxels_per_sample_br1"},
               {"rated br3", "samples_rated_br3"},
               {"rated br1", "samples_rated_br1"},
               {"same counts", "same_voxel_counts"}});
  const auto sci = [](double v)
  {
    std::ostringstream os;
    os << std::scientific << std::setprecision(1) << v;
    return os.str();
  };
  for (const auto& c : cols)
  {
    const auto& a = c.check3;
    const auto& b = c.check1;
    const bool any = a.naive_samples > 0 && b.naive_samples > 0;
    t.addRow({fixed(c.l_res_m * 1e3, 0), std::to_string(a.beams), any ? ms(a.ours_ms) : "-",
              any ? ms(a.naive_ms) : "-", any ? fixed(a.naive_ms / a.ours_ms, 1) : "-",
              any ? sci(a.max_rel_diff) : "-", std::to_string(b.beams), any ? ms(b.ours_ms) : "-",
              any ? ms(b.naive_ms) : "-", any ? fixed(b.naive_ms / b.ours_ms, 1) : "-",
              any ? sci(b.max_rel_diff) : "-", fixed(b.voxels, 0), std::to_string(a.naive_samples),
              std::to_string(b.naive_samples),
              !any                             ? "-"
              : a.same_counts && b.same_counts ? "yes"
                                               : "NO"});
  }
  return t;
}

TextTable mapTable(const std::vector<PlannerColumn>& cols)
{
  TextTable t({{"l_res [mm]", "l_res_mm"},
               {"build V [s]", "build_v_s"},
               {"leaves", "leaves"},
               {"MiB", "memory_mib"},
               {"grid G", "grid_cells"},
               {"frontiers", "frontiers"},
               {"last stop: samples", "last_stop_samples"},
               {"pose: stop", "pose_stop"},
               {"sample space", "sample_space_cells"},
               {"skipped", "frontiers_skipped"},
               {"chosen [m]", "frontier_size_m"},
               {"path [m]", "path_length_m"},
               {"best gain", "best_gain_br3"}});
  for (const auto& c : cols)
  {
    const auto& r = c.br3.last;
    double best = 0;
    for (const auto& g : r.ratings) best = std::max(best, g.gain);
    t.addRow({fixed(c.l_res_m * 1e3, 0), fixed(c.build_s, 1), std::to_string(c.leaves),
              fixed(double(c.memory) / (1 << 20), 1),
              std::to_string(c.grid_x) + "x" + std::to_string(c.grid_y),
              std::to_string(c.frontiers), std::to_string(c.last_samples),
              std::to_string(c.stop_used + 1) + "/" + std::to_string(c.stops),
              std::to_string(r.sample_space.size()), std::to_string(r.skipped_frontiers.size()),
              r.frontier ? fixed(r.frontier->size_m, 2) : "-",
              r.path ? fixed(r.path->length_m, 2) : "-", r.ratings.empty() ? "-" : fixed(best, 0)});
  }
  return t;
}

void printTargets(const std::vector<PlannerColumn>& cols, std::ostream& out)
{
  for (const auto& c : cols)
  {
    if (std::abs(c.l_res_m - kTargetLresM) > 1e-9) continue;
    const auto verdict = [](bool met) { return met ? "met" : "MISSED"; };
    const auto& r1 = c.br1.ms.rating_per_sample;
    out << "\nTargets (issue 4) at l_res 50 mm on one core:\n"
        << "  scan rating per sample, beam_reduction 1 (" << c.check1.beams << " beams) < "
        << kRatingTargetMs << " ms: ours " << ms(r1) << " ms -> "
        << (r1 ? verdict(*r1 < kRatingTargetMs) : "not measured (nothing rated)") << "\n"
        << "  whole planning step (all stages, " << c.br3.last.samples.size() << " samples) < "
        << kStepTargetMs << " ms: beam_reduction 3 (thesis setting) " << ms(c.br3.ms.total)
        << " ms -> " << verdict(c.br3.ms.total < kStepTargetMs) << "; beam_reduction 1 "
        << ms(c.br1.ms.total) << " ms -> " << verdict(c.br1.ms.total < kStepTargetMs) << "\n";
  }
}

void printNotes(const std::vector<PlannerColumn>& cols, std::ostream& out)
{
  for (const auto& c : cols)
  {
    const std::string at = "l_res " + fixed(c.l_res_m * 1e3, 0) + " mm: ";
    if (!c.last_outcome.empty())
      out << at << "the plan from the last stop found nothing to rate (" << c.last_outcome << ")\n";
    if (c.stop_used + 1 != c.stops)
      out << at << "the plan from the last stop rated " << c.last_samples << " sample(s)"
          << (c.last_samples ? " (not a full set, or after skipping a frontier)" : "")
          << "; planned from stop " << c.stop_used + 1 << " instead\n";
    if (!c.ok) out << at << "no plan (" << c.outcome << "); stage times up to where it ended\n";
    if (!c.br3.last.skipped_frontiers.empty())
      out << at << c.br3.last.skipped_frontiers.size()
          << " frontier(s) skipped before the plan: the rating time covers their samples too\n";
    if (c.check1.naive_samples < c.check1.samples)
      out << at << "naive rating at beam_reduction 1 on " << c.check1.naive_samples << " of "
          << c.check1.samples << " samples (time budget " << kNaiveBudgetMs / 1e3 << " s)\n";
  }
}
}  // namespace

void runPlannerTable(const SlamBenchOptions& opts, std::ostream& out)
{
  const auto data = loadSlamBenchData(opts);
  const PlannerParams params;  // the thesis' values
  mrpt::config::CConfigFileMemory used;
  data.params.save(used);
  params.save(used);
  const std::string note =
      "# voxplore-bench planner: SlamIcp ([metaview] d_min_m = 0.02 and [octomap] l_res_m are "
      "swept) and PlannerParams in force ([scan_rating] beam_reduction 3 and 1 both run)\n";
  if (!opts.quiet)
    std::cerr << "voxplore-bench: " << data.stops.size() << " stops of " << opts.rawlog << "\n"
              << note << used.getContent() << "---\n";
  if (!opts.csv_dir.empty())
    std::ofstream(fs::path(opts.csv_dir) / "planner_params.ini") << note << used.getContent();

  std::vector<PlannerColumn> cols;
  for (const double l_res : opts.l_res_m) cols.push_back(measureLres(data, opts, params, l_res));

  const auto stages = stageTable(cols);
  const auto rating = ratingTable(cols);
  const auto maps = mapTable(cols);
  const std::string med =
      opts.repeat > 1 ? "median of " + std::to_string(opts.repeat) + " plans" : "one plan";
  out << "\n== Table 5.2, exploration planner rows: exploration::plan on V [ms] ==\n"
      << "V: the first " << data.stops.size() << " stops of " << opts.rawlog
      << " through SlamIcp (d_min 20 mm) at each l_res;\nplan() from the last stop whose plan "
         "rates a full sample set (see the maps table), thesis\nPlannerParams (max_samples "
      << params.sampling.max_samples << ", seed " << params.seed << "), " << med
      << " per column.\nrating/sample = rating stage ms / samples rated; br3 = beam_reduction 3 "
         "(thesis setting),\nbr1 = beam_reduction 1 (all beams); step = the whole plan() call. "
         "thesis: Xeon W3520 2.66 GHz,\nrating at beam_reduction 3.\n\n"
      << stages.str();
  printTargets(cols, out);
  out << "\n== Scan rating on the plan's sample poses: ours (rateScan) vs naive (rateScanNaive) "
         "==\nms per sample, mean over the samples rated both ways, back to back in this run; "
         "max rel. diff:\nof the gains |ours - naive| / naive over those samples; same counts: "
         "distinct and unknown\nvoxels equal for every sample.\n\n"
      << rating.str()
      << "\n== Maps and plans (beam_reduction 3) ==\nbuild V: the SlamIcp replay of all stops "
         "at that l_res; leaves and memory of V; grid G in cells;\nlast stop: samples "
         "the plan from the last stop rated;\npose: the stop planned from; sample space: its "
         "cells; chosen: the "
         "frontier's size; best gain in nats.\n\n"
      << maps.str() << "\n";
  printNotes(cols, out);
  if (!opts.csv_dir.empty())
  {
    const fs::path dir(opts.csv_dir);
    stages.writeCsv((dir / "table_5_2_planner.csv").string());
    rating.writeCsv((dir / "planner_scan_rating.csv").string());
    maps.writeCsv((dir / "planner_maps.csv").string());
  }
  out << std::flush;
}

}  // namespace voxplore::bench
