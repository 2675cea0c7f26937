// voxplore-explore: outputs (logs, coverage.csv, coverage.png, step images,
// summary.json) and the ground-truth evaluation of a finished run.
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <mrpt/img/CImage.h>
#include <mrpt/system/CTicTac.h>
#include <octomap/OcTree.h>
#include <voxplore/eval/map_accuracy.h>
#include <voxplore/eval/trajectory_error.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "ExploreApp_internal.h"
#include "ExploreRun.h"

namespace voxplore::apps
{
namespace fs = std::filesystem;

namespace
{
/// A memory figure of this process from /proc/self/status ("VmRSS:" now,
/// "VmHWM:" peak) in MiB; 0 where /proc is not available.
double processMemoryMb(const char* key)
{
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + std::strlen(key)) / 1024.0;
  return 0.0;
}

/// @brief The coverage_2d column of a coverage.csv, one value per step.
/// @return empty when the file cannot be read, has no such column or no rows
std::vector<double> readCoverageSeries(const fs::path& csv_path)
{
  std::ifstream f(csv_path);
  std::string line;
  if (!std::getline(f, line)) return {};
  std::size_t column = 0;
  {
    std::istringstream header(line);
    std::string name;
    while (std::getline(header, name, ',') && name != "coverage_2d") column++;
    if (name != "coverage_2d") return {};
  }
  std::vector<double> series;
  while (std::getline(f, line))
  {
    std::istringstream row(line);
    std::string cell;
    for (std::size_t i = 0; i <= column; i++) std::getline(row, cell, ',');
    series.push_back(std::stod(cell));
  }
  return series;
}

/// @brief Tick spacing (1, 2, 5, 10, 20, 50, ...) giving at most `max_ticks` ticks over `span`.
int tickStep(std::size_t span, int max_ticks)
{
  for (int magnitude = 1;; magnitude *= 10)
    for (const int m : {1, 2, 5})
      if (static_cast<double>(span) / (m * magnitude) <= max_ticks) return m * magnitude;
}

/// @brief Coverage per planning step (thesis fig. 5.3): coverage_2d (0..1)
///        over steps 1..N as a polyline with a mark per step, y grid every
///        0.1, labelled step ticks, in a 640 x 400 RGB PNG.
/// @throws std::runtime_error naming the path when it cannot be written.
void writeCoveragePlot(const std::vector<double>& coverage, const std::string& png_path)
{
  using mrpt::img::TColor;
  constexpr int kW = 640, kH = 400, kLeft = 52, kRight = 20, kTop = 28, kBottom = 44;
  constexpr int kPlotW = kW - kLeft - kRight, kPlotH = kH - kTop - kBottom;
  mrpt::img::CImage img(kW, kH, mrpt::img::CH_RGB);
  img.filledRectangle(0, 0, kW - 1, kH - 1, TColor(255, 255, 255));
  img.selectTextFont("6x13");

  const std::size_t n_steps = std::max<std::size_t>(coverage.size(), 1);
  const auto px = [&](double step)
  { return kLeft + static_cast<int>(std::lround(step / static_cast<double>(n_steps) * kPlotW)); };
  const auto py = [&](double c)
  { return kTop + kPlotH - static_cast<int>(std::lround(std::clamp(c, 0.0, 1.0) * kPlotH)); };

  // y: grid and labels every 0.1 (coverage), x: ticks and labels (steps).
  for (int i = 0; i <= 10; i++)
  {
    const int y = py(i / 10.0);
    img.line(kLeft, y, kLeft + kPlotW, y, TColor(225, 225, 225));
    img.line(kLeft - 4, y, kLeft, y, TColor(0, 0, 0));
    if (i % 2 == 0) img.textOut(kLeft - 30, y - 6, mrpt::format("%.1f", i / 10.0), TColor(0, 0, 0));
  }
  const int every = tickStep(n_steps, 20);
  for (std::size_t s = 0; s <= n_steps; s += every)
  {
    const int x = px(static_cast<double>(s));
    img.line(x, kTop + kPlotH, x, kTop + kPlotH + 4, TColor(0, 0, 0));
    const auto label = std::to_string(s);
    img.textOut(x - 3 * static_cast<int>(label.size()), kTop + kPlotH + 7, label, TColor(0, 0, 0));
  }
  img.line(kLeft, kTop, kLeft, kTop + kPlotH, TColor(0, 0, 0));
  img.line(kLeft, kTop + kPlotH, kLeft + kPlotW, kTop + kPlotH, TColor(0, 0, 0));
  img.textOut(kLeft + kPlotW / 2 - 42, kH - 16, "planning step", TColor(0, 0, 0));
  img.textOut(kLeft, 8,
              coverage.empty() ? std::string("coverage_2d per step (no step yet)")
                               : mrpt::format("coverage_2d per step: %.3f after %zu steps",
                                              coverage.back(), coverage.size()),
              TColor(0, 0, 0));

  // The series: step k (1-based) at x = k.
  const TColor blue(30, 90, 200);
  for (std::size_t k = 0; k < coverage.size(); k++)
  {
    const int x = px(static_cast<double>(k + 1)), y = py(coverage[k]);
    if (k > 0) img.line(px(static_cast<double>(k)), py(coverage[k - 1]), x, y, blue, 2);
    img.drawMark(x, y, blue, '+', 3);
  }
  if (!img.saveToFile(png_path)) throw std::runtime_error("cannot write '" + png_path + "'");
}

std::string jsonPose(const std::array<double, 3>& p)
{
  return mrpt::format("[%.4f, %.4f, %.2f]", p[0], p[1], p[2]);
}

std::array<double, 3> poseArray(const mrpt::poses::CPose2D& p)
{
  return {p.x(), p.y(), mrpt::RAD2DEG(p.phi())};
}
}  // namespace

void writeExploreSummary(const ExploreSummary& s, const std::string& path)
{
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  f << std::setprecision(9);
  f << "{\n  \"termination_reason\": \"" << s.termination_reason << "\",\n  \"planner_model\": \""
    << s.planner_model << "\",\n  \"steps\": " << s.steps
    << ",\n  \"stops\": " << s.stops << ",\n  \"flagged_stops\": " << s.flagged_stops
    << ",\n  \"relocalized_stops\": " << s.relocalized_stops
    << ",\n  \"held_stops\": " << s.held_stops << ",\n  \"kept_stops\": " << s.kept_stops
    << ",\n  \"loop_closures\": " << s.loop_closures << ",\n  \"loop_edges\": " << s.loop_edges
    << ",\n  \"loop_max_shift_m\": " << s.loop_max_shift_m
    << ",\n  \"skipped_cameras\": " << s.skipped_cameras << ",\n  \"failed_drives\": " << s.failed_drives
    << ",\n  \"blacklisted\": " << s.blacklisted << ",\n  \"guard_scaled\": " << s.guard_scaled
    << ",\n  \"guard_held\": " << s.guard_held
    << ",\n  \"low_obstacle_replans\": " << s.low_obstacle_replans
    << ",\n  \"scans_moving\": " << s.scans_moving
    << ",\n  \"targets_seen_on_the_way\": " << s.targets_seen_on_the_way
    << ",\n  \"seen_checks\": " << s.seen_checks << ",\n  \"seen_check_s\": " << s.seen_check_s
    << ",\n  \"seen_gated\": " << s.seen_gated << ",\n  \"seen_gate_misses\": " << s.seen_gate_misses
    << ",\n  \"path_length_m\": " << s.path_length_m
    << ",\n  \"known_floor_m2\": " << s.known_floor_m2
    << ",\n  \"known_floor_cut_off_m2\": " << s.known_floor_cut_off_m2
    << ",\n  \"unobservable_m2\": " << s.unobservable_m2 << ",\n  \"frontiers_left_map\": [";
  double left_m = 0;
  for (std::size_t i = 0; i < s.frontiers_left.size(); i++)
  {
    const auto& fr = s.frontiers_left[i];
    f << (i ? ", " : "") << "[" << fr[0] << ", " << fr[1] << ", " << fr[2] << "]";
    left_m += fr[2];
  }
  f << "],\n  \"frontiers_left_m\": " << left_m
    << ",\n  \"coverage_2d\": " << s.coverage_2d
    << ",\n  \"coverage_2d_planner_circle\": " << s.coverage_2d_planner_circle
    << ",\n  \"coverage_2d_circumradius\": " << s.coverage_2d_circumradius
    << ",\n  \"floor_reachable_m2\": " << s.floor_reachable_m2
    << ",\n  \"floor_reachable_planner_circle_m2\": " << s.floor_reachable_planner_circle_m2
    << ",\n  \"floor_reachable_circumradius_m2\": " << s.floor_reachable_circumradius_m2
    << ",\n  \"coverage_3d\": " << s.coverage_3d
    << ",\n  \"map_precision\": " << s.map_precision
    << ",\n  \"map_precision_above_floor\": " << s.map_precision_above_floor << ",\n  \"collisions\": " << s.collisions
    << ",\n  \"min_clearance_m\": " << s.min_clearance_m
    << ",\n  \"min_clearance_pose\": " << jsonPose(s.min_clearance_pose)
    << ",\n  \"collision_poses\": [";
  for (std::size_t i = 0; i < s.collision_poses.size(); i++)
    f << (i ? ", " : "") << jsonPose(s.collision_poses[i]);
  f << "],\n  \"ate_rmse_m\": " << s.ate_rmse_m
    << ",\n  \"ate_online_rmse_m\": " << s.ate_online_rmse_m
    << ",\n  \"compute_s\": " << s.compute_s << ",\n  \"sim_time_s\": " << s.sim_time_s
    << ",\n  \"time_translating_s\": " << s.time_translating_s
    << ",\n  \"time_turning_s\": " << s.time_turning_s
    << ",\n  \"peak_rss_mb\": " << s.peak_rss_mb << "\n}\n";
}

void ExploreRun::openOutputs()
{
  const fs::path dir(out_dir_);
  rawlog_ = std::make_unique<common::RawlogWriter>((dir / "run.rawlog").string());
  gt_tum_ = std::make_unique<common::TumWriter>((dir / "trajectory_gt.tum").string());
  est_tum_ = std::make_unique<common::TumWriter>((dir / "trajectory_est.tum").string());
  coverage_csv_.open(dir / "coverage.csv");
  if (!coverage_csv_) throw std::runtime_error("cannot write '" + (dir / "coverage.csv").string() + "'");
  coverage_csv_ << "step,stops,sim_time_s,path_length_m,coverage_2d,frontiers,done,target_x,"
                   "target_y,waypoints,ms_slam,ms_projection,ms_collision,ms_frontiers,"
                   "ms_sampling,ms_rating,ms_path,ms_plan_total,metaview_points,octree_nodes,"
                   "rss_mb,coverage_2d_planner_circle,ms_tour,tour_length_m,ms_rooms,rooms,robot_room,"
                   "frontier_room,known_floor_m2,new_frontiers\n";
  if (cfg_.explore.write_step_images) fs::create_directories(dir / "steps");
}

double ExploreRun::coverageOf(const exploration::GroundGrid& g) const
{
  return explore_detail::coverage2d(g, gt_floor_.free_floor, T_world_map_);
}

namespace
{
/// The room of the frontier the plan chose (-1: none, or no plan).
int frontierRoom(const exploration::PlanResult& p)
{
  if (!p.ok() || !p.frontier || !p.frontiers) return -1;
  const auto& fs = p.frontiers->frontiers;
  for (std::size_t i = 0; i < fs.size() && i < p.frontier_rooms.size(); ++i)
    if (fs[i].id == p.frontier->id) return p.frontier_rooms[i];
  return -1;
}
}  // namespace

void ExploreRun::writeCoverageRow(const exploration::PlanResult& p, double coverage,
                                  double coverage_planner_circle, double slam_ms)
{
  coverage_csv_ << mrpt::format(
      "%zu,%zu,%.3f,%.4f,%.5f,%zu,%s,%.3f,%.3f,%zu,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%zu,%zu,"
      "%.1f,%.5f,%.1f,%.2f,%.1f,%zu,%d,%d,%.3f,%zu\n",
      s_.steps, s_.stops, sim_.simTime(), s_.path_length_m, coverage,
      p.frontiers ? p.frontiers->frontiers.size() : std::size_t(0),
      p.ok() ? "no" : exploration::toString(p.done), p.target.x(), p.target.y(),
      p.waypoints.size(), slam_ms, p.ms.projection, p.ms.collision, p.ms.frontiers,
      p.ms.sampling, p.ms.rating, p.ms.path, p.ms.total, slam().metaview().size(),
      slam().octomap().tree().size(), processMemoryMb("VmRSS:"), coverage_planner_circle,
      p.ms.tour, p.tour.length_m, p.ms.rooms, p.rooms ? p.rooms->area_m2.size() : std::size_t(0),
      static_cast<int>(p.robot_room), frontierRoom(p), s_.known_floor_m2, s_.new_frontiers);
  coverage_csv_.flush();
  // coverage.png follows coverage.csv at every step (a few ms), so a run cut
  // short still leaves it.
  const fs::path dir(out_dir_);
  writeCoveragePlot(readCoverageSeries(dir / "coverage.csv"), (dir / "coverage.png").string());
}

std::vector<mrpt::poses::CPose2D> ExploreRun::trajectoryInMap(double spacing_m) const
{
  const mrpt::poses::CPose2D T_map_world = -T_world_map_;
  std::vector<mrpt::poses::CPose2D> out;
  for (const auto& p : gt_path_)
  {
    const auto q = T_map_world + p;
    if (out.empty() || q.distanceTo(out.back()) >= spacing_m) out.push_back(q);
  }
  return out;
}

void ExploreRun::writeStepImage(const exploration::PlanResult& plan)
{
  if (!plan.ground) return;
  const auto path = fs::path(out_dir_) / "steps" / mrpt::format("step_%03zu.png", s_.steps);
  exploration::renderPlan(plan, slam().currentPose(), path.string(), trajectoryInMap(0.05),
                          cfg_.explore.step_image_scale);
}

void ExploreRun::saveMapsAfterFailure() noexcept
{
  try
  {
    est_tum_.reset();
    rawlog_.reset();
    if (slam().numStops() > 0) slam().saveOutputs(out_dir_);
  }
  catch (const std::exception& e)
  {
    std::cerr << "voxplore-explore: could not save the maps after the failure: " << e.what()
              << std::endl;
  }
}

void ExploreRun::finish()
{
  est_tum_.reset();  // saveOutputs() rewrites trajectory_est.tum with the same poses
  rawlog_.reset();
  gt_tum_.reset();
  slam().saveOutputs(out_dir_);
  const auto& status = loop_->status();
  s_.failed_drives = status.failed_drives;
  s_.blacklisted = status.blacklisted;
  s_.guard_scaled = status.guard_scaled;
  s_.guard_held = status.guard_held;
  s_.low_obstacle_replans = status.low_obstacle_replans;
  s_.scans_moving = status.scans_moving;
  s_.time_translating_s = status.time_translating_s;
  s_.time_turning_s = status.time_turning_s;
  s_.targets_seen_on_the_way = status.targets_seen_on_the_way;
  s_.seen_checks = status.seen_checks;
  s_.seen_check_s = status.seen_check_s;
  s_.seen_gated = status.seen_gated;
  s_.seen_gate_misses = status.seen_gate_misses;
  s_.known_floor_m2 = status.known_floor_m2;
  s_.known_floor_cut_off_m2 = status.known_floor_cut_off_m2;
  s_.unobservable_m2 = status.unobservable_m2;
  s_.frontiers_left.clear();
  for (const auto& [c, len] : status.frontiers_left) s_.frontiers_left.push_back({c.x(), c.y(), len});

  mrpt::system::CTicTac tic;
  const double res = cfg_.slam.octomap.l_res_m;
  const mrpt::poses::CPose3D T_world_map3(T_world_map_);
  const auto ground =
      exploration::projectToGround(slam().octomap().tree(), slam().currentPose(),
                                   cfg_.planner.projectionInForce(res), loop_->sweptPath());
  s_.coverage_2d = coverageOf(ground);
  s_.coverage_2d_planner_circle =
      explore_detail::coverage2d(ground, gt_floor_planner_.free_floor, T_world_map_);
  s_.coverage_2d_circumradius =
      explore_detail::coverage2d(ground, gt_floor_body_.free_floor, T_world_map_);
  const auto occupied = slam().octomap().occupiedVoxelCenters();
  const auto band = sim::occupiedVoxels(sim_.world().mesh, res, cfg_.explore.band_z_min_m,
                                        cfg_.explore.band_z_max_m);
  s_.coverage_3d = explore_detail::coverage3d(occupied, T_world_map3, band, res);
  const auto surface = sim::occupiedVoxels(sim_.world().mesh, res);
  s_.map_precision = eval::mapPrecision(occupied, T_world_map3, surface, res).precision;
  // The floor is most of the occupied voxels and matches the ground plane
  // whatever the pose error: report the precision without it as well.
  std::vector<Eigen::Vector3d> above_floor;
  for (const auto& c : occupied)
    if (c.z() > res) above_floor.push_back(c);
  s_.map_precision_above_floor =
      eval::mapPrecision(above_floor, T_world_map3, surface, res).precision;
  s_.collisions = sim_.robot().collisions();
  s_.loop_closures = slam().loopClosures();
  s_.loop_edges = slam().loopCloser().numLoopEdges();
  s_.loop_max_shift_m = slam().maxGraphShift();
  for (const auto& r : slam().reports())
  {
    s_.flagged_stops += r.flagged;
    s_.relocalized_stops += r.relocalized;
    s_.held_stops += r.held;
    s_.kept_stops += r.odometry_kept;
    for (const auto& i : r.camera_issues) s_.skipped_cameras += i.skipped;
  }
  const auto clear =
      explore_detail::minClearance(sim_.checker(), cfg_.sim.robot.footprint(), gt_path_);
  s_.min_clearance_m = clear.clearance_m;
  s_.min_clearance_pose = poseArray(clear.pose_world);
  s_.collision_poses.clear();
  for (const auto& p : sim_.robot().collisionPoses()) s_.collision_poses.push_back(poseArray(p));
  const fs::path dir(out_dir_);
  const auto gt = common::readTum((dir / "trajectory_gt.tum").string());
  s_.ate_rmse_m =
      eval::trajectoryError(common::readTum((dir / "trajectory_est.tum").string()), gt).ate_rmse_m;
  s_.ate_online_rmse_m =
      eval::trajectoryError(common::readTum((dir / "trajectory_online.tum").string()), gt).ate_rmse_m;
  s_.compute_s = status.compute_s;
  s_.sim_time_s = sim_.simTime();
  s_.peak_rss_mb = processMemoryMb("VmHWM:");
  writeCoveragePlot(readCoverageSeries(dir / "coverage.csv"), (dir / "coverage.png").string());
  writeExploreSummary(s_, (dir / "summary.json").string());
  if (!quiet_)
    std::cout << mrpt::format("voxplore-explore: evaluation against ground truth took %.1f s",
                              tic.Tac())
              << std::endl;
}

}  // namespace voxplore::apps
