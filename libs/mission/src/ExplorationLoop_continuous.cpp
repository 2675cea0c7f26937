// The exploration loop's scans (SlamIcp at once, or beside the driving:
// scan_latency_s) and its scanning while driving ([explore] scan_mode =
// continuous, issue 15): which waypoints are passed without stopping, when
// a scan is due on the way, and whether the scans on the way have seen the
// plan's frontier (replan_on_the_way). Split from ExplorationLoop.cpp. Our
// own code: the thesis stops at every waypoint.
#include <mrpt/core/bits_math.h>
#include <mrpt/core/format.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/exploration/footprint.h>
#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include "pending_scan.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

namespace voxplore::mission
{
namespace
{
/// Turns on the way are on ([path] turn_on_the_way_deg) and the plan is a
/// footprint plan whose per-waypoint vectors are consistent.
bool turnsOnTheWay(const exploration::PlanResult& plan, const exploration::PathParams& path)
{
  const std::size_t n = plan.waypoints.size();
  return path.turn_on_the_way_deg > 0 && plan.footprint && plan.waypoint_narrow.size() == n &&
         plan.waypoint_turn_on_way.size() == n && plan.waypoint_yaws.size() == n;
}
}  // namespace

void ExplorationLoop::scanAndIntegrate(bool beside)
{
  if (!beside) standStill();
  settleScan();  // SlamIcp integrates one stop after the other
  const Scan scan = scans_.scan();
  if (!scan.observations)
    throw std::runtime_error("ExplorationLoop: the scan source delivered no observations");
  if (listener_) listener_->onScan(scan);
  const mrpt::poses::CPose2D odo = robot_.odometry();
  odo_at_scan_ = odo;
  t_last_scan_s_ = mrpt::Clock::toDouble(robot_.now());
  t_last_step_s_ = t_last_scan_s_;
  if (beside && params_.scan_latency_s > 0)
  {
    // Nothing else touches slam_ until settleScan() (the loop settles before
    // every read of the map); the scan's observations are the worker's.
    pending_ = std::make_unique<PendingScan>();
    pending_->scan = scan;
    pending_->odometry = odo;
    pending_->t_s = t_last_scan_s_;
    pending_->result = std::async(std::launch::async, [this, scan]() {
      mrpt::system::CTicTac tic;
      auto rep = slam_.processStop(*scan.observations, scan.odometry, scan.timestamp);
      return std::make_pair(std::move(rep), tic.Tac());
    });
    return;
  }
  mrpt::system::CTicTac tic;
  const auto rep = slam_.processStop(*scan.observations, scan.odometry, scan.timestamp);
  applyScan(scan, rep, tic.Tac(), odo);
}

void ExplorationLoop::standStill()
{
  // A base with acceleration limits ([robot] max_accel_mps2) still moves
  // after a drive's stop(): a standing scan waits until it stands (the
  // guard checked that braking keeps its margin). Without limits it stands.
  if (!navigation::isMoving(robot_)) return;
  robot_.stop();
  constexpr int kMaxSteps = 200;
  for (int k = 0; k < kMaxSteps; k++)
  {
    robot_.step(driver_->params().dt_s);
    if (!navigation::isMoving(robot_)) break;
  }
}

bool ExplorationLoop::pendingDue() const
{
  return pending_ &&
         mrpt::Clock::toDouble(robot_.now()) >= pending_->t_s + params_.scan_latency_s - 1e-9;
}

void ExplorationLoop::settleScan()
{
  if (!pending_) return;
  const std::unique_ptr<PendingScan> p = std::move(pending_);
  const auto [rep, compute_s] = p->result.get();  // a worker's exception comes out here
  applyScan(p->scan, rep, compute_s, p->odometry);
}

void ExplorationLoop::applyScan(const Scan& scan, const mapping::StopReport& rep,
                                double compute_s, const mrpt::poses::CPose2D& odometry)
{
  status_.compute_s += compute_s;
  status_.slam_ms_step += compute_s * 1e3;
  pose_at_stop_ = rep.pose;
  odo_at_stop_ = odometry;
  // Taken late, the robot has driven on since the scan: the estimate from here.
  const bool late = !(robot_.odometry() == odometry);
  last_estimate_ = late ? poseEstimate() : rep.pose;
  if (rep.loop.closed)
  {
    // The poses so far were corrected: the swept path follows them.
    swept_.clear();
    for (const auto& r : slam_.reports()) addSwept(r.pose);
    message("stop " + std::to_string(rep.index) + ": " + rep.loop.message +
            (rep.loop.rebuilt ? mrpt::format("; maps corrected in %.0f ms (OctoMap: %zu keyframes "
                                             "left to re-insert over the next stops)",
                                             rep.loop.t_rebuild_ms, rep.octomap_rebuild_left)
                              : std::string()));
  }
  addSwept(rep.pose);
  if (late) addSwept(last_estimate_);
  // A stop whose scan is in the map, every camera used, looked at what it saw.
  if (rep.integrated && std::none_of(rep.camera_issues.begin(), rep.camera_issues.end(),
                                     [](const mapping::CameraIssue& c) { return c.skipped; }))
    looks_->addStop(rep.pose);
  if (listener_) listener_->onStop(scan, rep);
}

mrpt::poses::CPose2D ExplorationLoop::planPose() const
{
  // A robot still moving (a drive ended on the way, replan_on_the_way) is
  // where odometry took it since the last scan; a standing one at that scan.
  return navigation::isMoving(robot_) ? poseEstimate() : slam_.currentPose();
}

bool ExplorationLoop::targetSeen(const exploration::PlanResult& plan)
{
  const auto rev = slam_.octomap().revision();
  if (!plan.frontier || (rev.map == checked_at_.map && rev.rev == checked_at_.rev)) return false;
  checked_at_ = rev;
  mrpt::system::CTicTac tic;
  // The frontiers only (a plan's views are rated only when it is taken).
  const auto& V = slam_.octomap().tree();
  const mrpt::poses::CPose2D pose = planPose();
  exploration::GroundGrid g = exploration::projectToGround(
      V, pose, planner_.projectionInForce(slam_.octomap().params().l_res_m), swept_,
      projectionCache());
  status_.seen_checks++;
  // seen_gate: while enough of the frontier's cells still border unknown,
  // it is there; the collision space and the reachability are not needed.
  const bool verify = params_.seen_gate_verify;
  bool gate_there = false;
  std::size_t left = 0;
  if ((params_.seen_gate || verify) && plan.ground)
  {
    const double n = static_cast<double>(plan.frontier->cells.size());
    left = exploration::frontierCellsLeft(*plan.frontier, *plan.ground, g,
                                          planner_.collision.ignore_unknown_beside_obstacles);
    gate_there = n > 0 && static_cast<double>(left) >= params_.seen_gate_fraction * n;
  }
  if (gate_there && !verify)
  {
    status_.seen_gated++;
    status_.seen_check_s += tic.Tac();
    return false;
  }
  const auto now = exploration::planLayersOn(std::move(g), pose, planner_, swept_,
                                             sensed_obstacles_, slam_.octomap().lowObstacles(),
                                             nullptr);
  status_.seen_check_s += tic.Tac();
  if (!now.frontiers) return false;
  const double r = planner_.sampling.blacklist_radius_m;
  const bool seen = std::none_of(now.frontiers->frontiers.begin(), now.frontiers->frontiers.end(),
                                 [&](const exploration::Frontier& f)
                                 { return (f.center - plan.frontier->center).norm() <= r; });
  if (gate_there && seen) status_.seen_gate_misses++;
  if (verify)
    message(mrpt::format("seen gate: %zu of %zu frontier cells border open unknown; the "
                         "frontier is %s%s",
                         left, plan.frontier->cells.size(), seen ? "seen" : "there",
                         gate_there && seen ? " (a miss)" : ""));
  return seen;
}

std::optional<ExplorationLoop::Pass> ExplorationLoop::passTolerance(const exploration::PlanResult& plan,
                                                     std::size_t i) const
{
  const auto& wps = plan.waypoints;
  auto narrowAt = [&](std::size_t k)
  { return k < plan.waypoint_narrow.size() && plan.waypoint_narrow[k]; };
  const auto& p = driver_->params();
  constexpr double kCornerTolerance_m = 0.005;
  if (i + 1 >= wps.size())
  {
    // The plan's end, a footprint drive already in the view's yaw (or its
    // half turn, half_turn_views; within half a bin, the planner's yaws):
    // landed on at half speed, no turn there; the scan is taken moving and
    // the next plan starts from the moving robot (a velocity jump of at most
    // 1.5 max_v, as a plan that ends on the way has: no acceleration limit).
    if (i >= wps.size() || !narrowAt(i) || i >= plan.waypoint_yaws.size() || !plan.footprint)
      return std::nullopt;
    double off = mrpt::math::wrapToPi(plan.waypoint_yaws[i] - plan.target.phi());
    if (view_period_ > 0) off -= view_period_ * std::round(off / view_period_);
    if (std::abs(off) > p.yaw_tolerance + 0.5 * plan.footprint->binWidth()) return std::nullopt;
    return Pass{kCornerTolerance_m, 0.5 * p.max_v_mps};
  }
  // Circle to circle: MRPT's reactive drive goes on from anywhere near; so
  // does a lead-in (the rectangle may hold any yaw all along it).
  const auto turnAt = [&](std::size_t k)
  { return k < plan.waypoint_turn_on_way.size() ? plan.waypoint_turn_on_way[k] : uint8_t(0); };
  if (!narrowAt(i))
    return narrowAt(i + 1) && turnAt(i + 1) != exploration::Path::kTurnFromAnyYaw
               ? std::nullopt
               : std::optional(Pass{params_.pass_tolerance_m});
  // From a footprint waypoint (in or at a passage the circle does not fit):
  // to another, the same yaw or a turn on the way there (no turn in place);
  // a way that bends little is passed within a tolerance, cutting the corner
  // by at most tolerance x sin(bend) (a door leaves the body 2-5 cm a side);
  // one that bends more, on the waypoint itself (no corner cut).
  constexpr double kPassBendDeg = 20;
  const bool turn_next = turnAt(i + 1) != 0;
  if (narrowAt(i + 1) && !turn_next &&
      (i + 1 >= plan.waypoint_yaws.size() ||
       std::abs(mrpt::math::wrapToPi(plan.waypoint_yaws[i + 1] - plan.waypoint_yaws[i])) >
           p.yaw_tolerance))
    return std::nullopt;
  const Eigen::Vector2d from = i > 0 ? wps[i - 1] : Eigen::Vector2d(pose_at_stop_.x(), pose_at_stop_.y());
  const Eigen::Vector2d a = wps[i] - from, b = wps[i + 1] - wps[i];
  if (a.norm() < 1e-6 || b.norm() < 1e-6) return std::nullopt;
  const double bend = std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0));
  if (bend > mrpt::DEG2RAD(kPassBendDeg))
  {
    // Into MRPT's reactive drive, which blends from the robot's velocity
    // over t_ramp_max_s and would cut the corner: stop.
    if (!narrowAt(i + 1)) return std::nullopt;
    // A corner between two straight footprint drives: the velocity turns by
    // `bend` at the waypoint, a jump of 2 v sin(bend / 2), kept no larger
    // than the simulated robot's own start from standstill (0 -> max_v in
    // one period; it has no acceleration limit): full speed up to 60 deg.
    const double corner_v = std::min(p.max_v_mps, p.max_v_mps / (2.0 * std::sin(0.5 * bend)));
    return Pass{kCornerTolerance_m, corner_v};
  }
  // One navigation period's travel at most: the drive checks once a period.
  const double tolerance = std::min(params_.pass_tolerance_m, p.max_v_mps * p.dt_s);
  // A turn on the way is made in proportion to the whole way: passed that
  // far off the waypoint it leaves tolerance / way of the turn undone, and
  // more than yaw_tolerance of it would be turned in place at the start of
  // the next drive. Landed on instead (a short piece with a large turn).
  if (narrowAt(i) && i < plan.waypoint_turn_on_way.size() && plan.waypoint_turn_on_way[i] != 0 &&
      i < plan.waypoint_yaws.size())
  {
    const mrpt::poses::CPose2D at = poseEstimate();
    const double left = std::abs(mrpt::math::wrapToPi(plan.waypoint_yaws[i] - at.phi())) * tolerance /
                        std::max((wps[i] - Eigen::Vector2d(at.x(), at.y())).norm(), 1e-9);
    if (left > p.yaw_tolerance) return Pass{kCornerTolerance_m, p.max_v_mps};
  }
  return Pass{tolerance};
}

void ExplorationLoop::leadInOnTheWay(exploration::PlanResult& plan, std::size_t i) const
{
  auto& w = plan.waypoints;
  if (!turnsOnTheWay(plan, planner_.path) || !plan.space || i + 1 >= w.size() || plan.waypoint_narrow[i])
    return;
  const std::size_t m = exploration::nextTranslation(w, i);
  if (m == w.size() || !plan.waypoint_narrow[m]) return;
  const mrpt::poses::CPose2D p = poseEstimate();
  const Eigen::Vector2d from(p.x(), p.y());
  // (About) there already: the footprint drive turns in place.
  if ((w[i] - from).norm() <= params_.pass_tolerance_m) return;
  const double yaw = plan.waypoint_yaws[m];
  if (!exploration::turnClearAlong(*plan.space, *plan.footprint, from, w[i], p.phi(),
                                   p.phi() + mrpt::math::wrapToPi(yaw - p.phi()), true))
    return;
  exploration::makeLeadIn(w, plan.waypoint_yaws, plan.waypoint_narrow, plan.waypoint_turn_on_way, i,
                          m, yaw);
}

void ExplorationLoop::turnFirstOnTheWay(exploration::PlanResult& plan, std::size_t i) const
{
  auto& w = plan.waypoints;
  if (!turnsOnTheWay(plan, planner_.path) || !plan.space || i >= w.size() || !plan.waypoint_narrow[i] ||
      plan.waypoint_turn_on_way[i] != 0)
    return;
  const mrpt::poses::CPose2D p = poseEstimate();
  const double turn = mrpt::math::wrapToPi(plan.waypoint_yaws[i] - p.phi());
  if (std::abs(turn) <= driver_->params().yaw_tolerance ||
      std::abs(turn) > mrpt::DEG2RAD(planner_.path.turn_on_the_way_deg))
    return;
  const auto s = exploration::turnFirstSplit(*plan.space, *plan.footprint, Eigen::Vector2d(p.x(), p.y()),
                                             w[i], p.phi(), p.phi() + turn);
  if (!s) return;
  exploration::insertWaypoint(w, plan.waypoint_yaws, plan.waypoint_narrow, plan.waypoint_turn_on_way, i,
                              *s, plan.waypoint_yaws[i], exploration::Path::kTurnFromPrevious);
}

std::optional<double> ExplorationLoop::faceYaw(const exploration::PlanResult& plan,
                                               std::size_t i) const
{
  const auto& w = plan.waypoints;
  if (params_.scan_mode != ExplorationLoopParams::ScanMode::Continuous ||
      !turnsOnTheWay(plan, planner_.path))
    return std::nullopt;
  for (std::size_t m = i + 1; m < w.size(); ++m)
    if (plan.waypoint_narrow[m])  // a turn on its way starts from the yaw before
      return plan.waypoint_turn_on_way[m] == exploration::Path::kTurnFromPrevious
                 ? plan.waypoint_yaws[m - 1]
                 : plan.waypoint_yaws[m];
  return plan.target.phi();
}

bool ExplorationLoop::scanDue() const
{
  if (mrpt::Clock::toDouble(robot_.now()) - t_last_scan_s_ < 1.0 / params_.scan_rate_hz - 1e-9)
    return false;
  const mrpt::poses::CPose2D d = robot_.odometry() - odo_at_scan_;
  return std::hypot(d.x(), d.y()) >= params_.scan_every_m ||
         std::abs(d.phi()) >= mrpt::DEG2RAD(params_.scan_every_deg);
}

}  // namespace voxplore::mission
