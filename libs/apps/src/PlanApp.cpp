#include <mrpt/3rdparty/tclap/CmdLine.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <octomap/OcTree.h>
#include <voxplore/apps/PlanApp.h>
#include <voxplore/apps/app_common.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/plan_inputs.h>

#include <voxplore/exploration/footprint.h>
#include <voxplore/mission/ExplorationLoopParams.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <utility>
#include <vector>

namespace voxplore::apps
{
namespace
{
const char* kDescription =
    "voxplore-plan: plans one step of a voxplore-explore run again, from the inputs the run saved "
    "(plans/step_NNN.txt and its .ot map, written with [explore] keep_plan_inputs = N) and the "
    "run's params.ini, and prints every stage: the frontiers (length, the opening they face, "
    "travel distance, room), why each one tried was skipped, the known floor cut off from the "
    "robot, the target and its path, the timings. Change a key in a copy of params.ini to see "
    "what it would have planned.";

char groundChar(exploration::GroundState s)
{
  switch (s)
  {
    case exploration::GroundState::Occupied: return '#';
    case exploration::GroundState::Free: return '.';
    default: return '?';
  }
}

char spaceChar(exploration::SpaceState s)
{
  switch (s)
  {
    case exploration::SpaceState::Occupied: return '#';
    case exploration::SpaceState::Collision: return 'C';
    case exploration::SpaceState::MaybeCollision: return 'm';
    case exploration::SpaceState::Free: return '.';
    default: return '?';
  }
}

/// The grid round one point, row by row from north to south, as text: what a
/// step image shows, cell by cell, with the footprint's states of one bin.
void printProbe(const exploration::PlanResult& r, const std::array<double, 3>& p, int radius,
                std::ostream& out)
{
  using namespace exploration;
  if (!r.ground || !r.space)
  {
    out << "probe: the step stopped before the collision space\n";
    return;
  }
  const auto& G = r.ground->state;
  Cell c;
  if (!cellOf(G, Eigen::Vector2d(p[0], p[1]), c))
  {
    out << mrpt::format("probe (%.3f, %.3f): outside the grid\n", p[0], p[1]);
    return;
  }
  const FootprintSpace* fs = r.footprint.get();
  const int bin = fs ? fs->binOf(mrpt::DEG2RAD(p[2])) : 0;
  out << mrpt::format("probe (%.3f, %.3f): cell (%d, %d) centre (%.3f, %.3f)", p[0], p[1], c.cx,
                      c.cy, G.idx2x(c.cx), G.idx2y(c.cy));
  if (fs)
    out << mrpt::format(", bin %d (%.1f deg) of %d", bin, mrpt::RAD2DEG(fs->binYaw(bin)), fs->bins);
  out << "\n  columns from x = " << mrpt::format("%.3f", G.idx2x(std::max(0, c.cx - radius)))
      << ", rows from y = " << mrpt::format("%.3f", G.idx2y(c.cy + radius)) << " down; "
      << "G | collision space" << (fs ? " | footprint bin (R reached, c clear, u clear of "
                                       "occupied only, x blocked; * = the probe)"
                                    : "")
      << "\n";
  const auto bit = YawMask{1} << bin;
  for (int cy = c.cy + radius; cy >= c.cy - radius; --cy)
  {
    std::string a, b, f;
    for (int cx = c.cx - radius; cx <= c.cx + radius; ++cx)
    {
      if (!inGrid(G, cx, cy))
      {
        a += ' ', b += ' ', f += ' ';
        continue;
      }
      const bool centre = cx == c.cx && cy == c.cy;
      a += centre ? '*' : groundChar(*G.cellByIndex(cx, cy));
      b += centre ? '*' : spaceChar(*r.space->state.cellByIndex(cx, cy));
      if (fs)
      {
        char ch = 'x';
        if (*fs->reach.cellByIndex(cx, cy) & bit)
          ch = 'R';
        else if (*fs->clear.cellByIndex(cx, cy) & bit)
          ch = 'c';
        else if (*fs->clear_occ.cellByIndex(cx, cy) & bit)
          ch = 'u';
        f += centre ? '*' : ch;
      }
    }
    out << "  " << a << " | " << b << (fs ? " | " + f : std::string()) << "\n";
  }
  if (fs)
  {
    const auto bits = [&](const Grid<YawMask>& g) {
      std::string s;
      for (int k = 0; k < fs->bins; ++k) s += (*g.cellByIndex(c.cx, c.cy) >> k) & 1 ? '1' : '0';
      return s;
    };
    out << "  bins at the probe (0 .. " << fs->bins - 1 << "): clear_occ " << bits(fs->clear_occ)
        << ", clear " << bits(fs->clear) << ", clear_turn " << bits(fs->clear_turn)
        << ", reach " << bits(fs->reach) << "\n";
  }
}

/// The planner's stages in the order the timing lines print them.
const std::pair<const char*, double exploration::PlanTimings::*> kStages[] = {
    {"projection", &exploration::PlanTimings::projection},
    {"collision", &exploration::PlanTimings::collision},
    {"frontiers", &exploration::PlanTimings::frontiers},
    {"rooms", &exploration::PlanTimings::rooms},
    {"tour", &exploration::PlanTimings::tour},
    {"sampling", &exploration::PlanTimings::sampling},
    {"rating", &exploration::PlanTimings::rating},
    {"path", &exploration::PlanTimings::path},
    {"total", &exploration::PlanTimings::total}};

/// "ms: projection 1.0, ..., total 9.0" of one plan.
void printTimes(const exploration::PlanTimings& ms, std::ostream& out)
{
  out << "ms:";
  for (const auto& [name, field] : kStages)
    out << mrpt::format(" %s %.1f%s", name, ms.*field,
                        field == &exploration::PlanTimings::total ? "\n" : ",");
}

/// The stages' times over `n` plans (r's and n - 1 more from `again`):
/// median and minimum of each [ms].
template <typename Again>
void printRepeatedTimes(const exploration::PlanResult& r, int n, std::ostream& out, Again again)
{
  std::vector<exploration::PlanTimings> t{r.ms};
  for (int k = 1; k < n; ++k) t.push_back(again());
  out << "ms over " << n << " plans (median / min):";
  for (const auto& [name, field] : kStages)
  {
    std::vector<double> v;
    for (const auto& x : t) v.push_back(x.*field);
    std::sort(v.begin(), v.end());
    out << mrpt::format(" %s %.1f / %.1f%s", name, v[v.size() / 2], v.front(),
                        field == &exploration::PlanTimings::total ? "\n" : ",");
  }
}
}  // namespace

int PlanApp::run(int argc, const char* const* argv)
{
  return runGuarded("voxplore-plan", [&]() {
    TCLAP::CmdLine cmd(kDescription, ' ', "0.1");
    TCLAP::ValueArg<std::string> inputs("i", "inputs", "plans/step_NNN.txt of a run", true, "",
                                        "FILE", cmd);
    TCLAP::ValueArg<std::string> config("c", "config", "The run's params.ini (planner sections)",
                                        true, "", "INI", cmd);
    TCLAP::ValueArg<std::string> png("p", "png", "Write the step image here", false, "", "PNG", cmd);
    TCLAP::ValueArg<int> scale("", "scale", "Pixels per grid cell of the image (default 4)", false,
                               4, "N", cmd);
    TCLAP::SwitchArg no_bl("", "ignore-blacklist", "Plan as if no target had been given up", cmd);
    TCLAP::SwitchArg no_so("", "ignore-sensed", "Plan without the points the driver sensed", cmd);
    TCLAP::MultiArg<std::string> probe(
        "", "probe",
        "Print the grid round X,Y [m] (and the footprint's states in the bin of YAW [deg], "
        "default 0): G (# occupied, ? unknown, . free), the collision space, and per cell "
        "whether the rectangle in that bin is reached (R), clear but not reached (c), clear of "
        "occupied cells only (u), or blocked (x). Repeatable.",
        false, "X,Y[,YAW]", cmd);
    TCLAP::ValueArg<int> probe_r("", "probe-radius", "Cells each side of a probe (default 12)",
                                 false, 12, "N", cmd);
    TCLAP::ValueArg<int> repeat("", "repeat",
                                "Plan the step N times in one process and print each stage's "
                                "median and minimum time (default 1)",
                                false, 1, "N", cmd);
    if (!cmd.parse(argc, const_cast<const char**>(argv)))
      return exitCodeAfterFailedParse(argc, argv);
    PlanOptions o;
    o.inputs = inputs.getValue();
    o.config = config.getValue();
    o.png = png.getValue();
    o.scale = scale.getValue();
    o.ignore_blacklist = no_bl.getValue();
    o.ignore_sensed = no_so.getValue();
    if (o.scale < 1) throw std::runtime_error("--scale must be >= 1");
    o.probe_radius = probe_r.getValue();
    o.repeat = repeat.getValue();
    if (o.repeat < 1 || o.repeat > 1000) throw std::runtime_error("--repeat must be in 1..1000");
    if (o.probe_radius < 1 || o.probe_radius > 200)
      throw std::runtime_error("--probe-radius must be in 1..200");
    for (const auto& p : probe.getValue())
    {
      std::array<double, 3> v{0, 0, 0};
      char c1 = 0, c2 = 0;
      const int n = std::sscanf(p.c_str(), "%lf%c%lf%c%lf", &v[0], &c1, &v[1], &c2, &v[2]);
      if ((n != 3 && n != 5) || c1 != ',' || (n == 5 && c2 != ','))
        throw std::runtime_error("--probe '" + p + "': expected X,Y or X,Y,YAW (metres, degrees)");
      o.probes.push_back(v);
    }
    execute(o, std::cout);
    return 0;
  });
}

exploration::PlanResult PlanApp::execute(const PlanOptions& o, std::ostream& out)
{
  const auto cfg = common::openIniFile(o.config);
  exploration::PlannerParams params;
  // The footprint is not a planner key: voxplore-explore sets it (and r_coll,
  // unless [collision] r_coll_m is given) from the robot profile, and its
  // params.ini holds the profile in [robot]. Without it, G lacked the swept
  // footprint's columns and the step planned again to another target.
  if (cfg->sectionExists("robot"))
  {
    const double l = common::readDoubleStrict(*cfg, "robot", "length_m", 0.0);
    const double w = common::readDoubleStrict(*cfg, "robot", "width_m", 0.0);
    common::requireValid(l > 0 && w > 0, *cfg, "robot", "length_m",
                         "length_m and width_m must be > 0 (the footprint the run planned with)");
    params.setFootprint(l, w);
  }
  else
    out << "note: no [robot] section in " << o.config
        << ": planning with the default footprint (omniRob), without the swept footprint in G\n";
  params.load(*cfg);
  // [path] turn_on_the_way_deg auto: as the run resolved it, by its
  // [explore] scan_mode (read and checked as voxplore-explore does).
  mission::ExplorationLoopParams run;
  run.loadFromConfigFile(*cfg, "explore");
  params.path.turn_on_the_way_deg = mission::ExplorationLoopParams::turnOnTheWayDegInForce(
      params.path.turn_on_the_way_deg, run.scan_mode);
  std::unique_ptr<octomap::OcTree> V;
  exploration::PlanInputs in = exploration::readPlanInputs(o.inputs, V);
  if (!in.region.empty()) params.projection.region = in.region;
  if (o.ignore_blacklist) in.blacklist.clear();
  if (o.ignore_sensed) in.sensed_obstacles.clear();
  // plan() judges the pending looks: each call takes its own copy.
  const auto looksCopy = [&in] { return in.looks ? *in.looks : exploration::FrontierLooks(); };
  exploration::FrontierLooks looks = looksCopy();
  const auto r = exploration::plan(*V, in.robot, params, in.blacklist, in.step, in.swept,
                                   in.sensed_obstacles, in.approach, in.low_obstacles, nullptr,
                                   &looks);
  out << mrpt::format("step %llu: robot (%.3f, %.3f, %.1f deg), %zu blacklisted, %zu sensed, %zu "
                      "low obstacle cells, %zu to approach, %zu swept poses; model %s\n",
                      static_cast<unsigned long long>(in.step + 1), in.robot.x(), in.robot.y(),
                      mrpt::RAD2DEG(in.robot.phi()), in.blacklist.size(), in.sensed_obstacles.size(),
                      in.low_obstacles.size(), in.approach.size(), in.swept.size(), r.footprint ? "footprint" : "circle");
  if (r.footprint && (r.footprint->escape_boxed_in || r.footprint->escape_ignored_occupied ||
                      r.footprint->escape_margin_m < r.footprint->margin_m))
    out << mrpt::format("footprint escape from the robot's state: %s, margin %.3f m (planned with %.3f m)\n",
                        r.footprint->escape_ignored_occupied ? "occupied cells under the body ignored"
                        : r.footprint->escape_boxed_in       ? "boxed in"
                                                             : "start within the margin",
                        r.footprint->escape_margin_m, r.footprint->margin_m);
  if (r.rooms)
    out << mrpt::format("rooms: %zu, the robot's %d\n", r.rooms->area_m2.size(),
                        static_cast<int>(r.robot_room));
  if (r.frontiers)
  {
    const auto& fs = r.frontiers->frontiers;
    out << fs.size() << " frontier(s):\n";
    for (std::size_t i = 0; i < fs.size(); ++i)
    {
      std::string skipped;
      for (std::size_t k = 0; k < r.skipped_frontiers.size(); ++k)
        if (r.skipped_frontiers[k] == i)
          skipped = std::string(", skipped: ") + exploration::toString(r.skip_reasons[k]);
      out << mrpt::format("  %3zu (%.3f, %.3f): %.2f m, opening %.2f m, unknown %.1f m^2, %.2f m away, room %d%s%s%s\n",
                          i, fs[i].center.x(), fs[i].center.y(), fs[i].size_m, fs[i].opening_m, fs[i].unknown_m2,
                          fs[i].distance_m, i < r.frontier_rooms.size() ? r.frontier_rooms[i] : -1,
                          fs[i].unreached ? ", unreached" : "", skipped.c_str(),
                          r.frontier && r.frontier->id == fs[i].id ? ", chosen" : "");
    }
    if (r.retired_m2 > 0)
      out << mrpt::format("open unknown looked at and left unknown (no frontier source): %.2f m^2\n",
                          r.retired_m2);
    if (r.ground && r.space)
      out << mrpt::format("known floor cut off from the robot: %.1f m^2\n",
                          exploration::cutOffFloorM2(*r.ground, *r.space, *r.frontiers));
  }
  out << (r.ok() ? "plan: " : std::string("done (") + exploration::toString(r.done) + "): ")
      << r.message << "\n";
  if (r.ok())
    out << mrpt::format("target (%.3f, %.3f, %.1f deg), %zu waypoints, %zu samples\n", r.target.x(),
                        r.target.y(), mrpt::RAD2DEG(r.target.phi()), r.waypoints.size(),
                        r.samples.size());
  printTimes(r.ms, out);
  if (o.repeat > 1) printRepeatedTimes(r, o.repeat, out, [&]() {
      exploration::FrontierLooks again = looksCopy();
      return exploration::plan(*V, in.robot, params, in.blacklist, in.step, in.swept,
                               in.sensed_obstacles, in.approach, in.low_obstacles, nullptr, &again)
          .ms;
    });
  for (const auto& p : o.probes) printProbe(r, p, o.probe_radius, out);
  if (!o.png.empty()) exploration::renderPlan(r, in.robot, o.png, {}, o.scale);
  return r;
}

}  // namespace voxplore::apps
