// The exploration loop (thesis fig. 4.4) with stop-and-scan driving (thesis
// 4.6), over RobotInterface, ScanSource and Clock only. Our own code: the
// thesis' algorithm; MRPT's reactive navigator drives each waypoint
// (navigation::StopAndScanDriver).
#include <mrpt/core/format.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/common/camera_mounts.h>
#include <voxplore/mission/ExplorationLoop.h>
#include <voxplore/navigation/StopAndScanDriver.h>

#include "pending_scan.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>

namespace voxplore::mission
{
namespace
{
/// Thrown from a robot step to end the run there (mid-drive): a listener's
/// stop reason or the time limit. Not a std::exception, so that no error
/// handler on the way mistakes it for a failure.
struct RunStopped
{
  std::string reason;
};

/// exploration::cutOffFloorM2 of a plan's layers (0 without them) [m^2].
double cutOffFloorM2(const exploration::PlanResult& plan)
{
  if (!plan.ground || !plan.space || !plan.frontiers) return 0;
  return exploration::cutOffFloorM2(*plan.ground, *plan.space, *plan.frontiers);
}

}  // namespace

/// The robot as the navigator sees it: the user's robot, with pose() the
/// loop's estimate (SLAM pose at the last stop + odometry since) and every
/// step() reported to the loop (swept path, limits).
class ExplorationLoop::PosedRobot : public navigation::RobotInterface
{
 public:
  PosedRobot(navigation::RobotInterface& robot, ExplorationLoop& loop) : robot_(robot), loop_(loop)
  {
  }
  void setVelocity(double vx_mps, double vy_mps, double w_radps) override
  {
    robot_.setVelocity(vx_mps, vy_mps, w_radps);
  }
  void stop() override { robot_.stop(); }
  mrpt::poses::CPose2D pose() const override { return loop_.poseEstimate(); }
  mrpt::poses::CPose2D odometry() const override { return robot_.odometry(); }
  mrpt::math::TTwist2D velocity() const override { return robot_.velocity(); }
  bool obstacles(mrpt::maps::CSimplePointsMap& out_robot_frame) override
  {
    return robot_.obstacles(out_robot_frame);
  }
  mrpt::Clock::time_point now() const override { return robot_.now(); }
  void step(double dt_s) override
  {
    robot_.step(dt_s);
    loop_.onRobotStep();
  }
  std::optional<std::size_t> collisionCount() const override { return robot_.collisionCount(); }

 private:
  navigation::RobotInterface& robot_;
  ExplorationLoop& loop_;
};

ExplorationLoop::ExplorationLoop(
    navigation::RobotInterface& robot, ScanSource& scans, const Clock& clock,
    const mapping::SlamIcpParams& slam, const exploration::PlannerParams& planner,
    const navigation::DriverParams& driver, const ExplorationLoopParams& params,
    Listener* listener)
    : robot_(robot),
      scans_(scans),
      clock_(clock),
      planner_(planner),
      params_(params),
      listener_(listener),
      slam_(slam),
      posed_(std::make_unique<PosedRobot>(robot, *this)),
      driver_(std::make_unique<navigation::StopAndScanDriver>(*posed_, driver)),
      t_start_(clock.now()),
      odo_at_stop_(robot.odometry()),
      low_replan_(params.lowObstacleReplanInForce(planner.collision, slam.octomap.l_res_m)),
      replan_at_stops_(params.replanAtStopsInForce(planner.strategy ==
                                                   exploration::Strategy::NextBestView))
{
  // half_turn_views: the last turn of a circle drive goes to the nearer of
  // the target's yaw and its half turn when the cameras see the same from both.
  if (params.scan_mode == ExplorationLoopParams::ScanMode::Continuous && params.half_turn_views &&
      common::mountsSymmetricUnderHalfTurn(planner_.rating.mounts))
    view_period_ = M_PI;
  // [path] turn_on_the_way_deg auto: on when scanning while driving.
  planner_.path.turn_on_the_way_deg = ExplorationLoopParams::turnOnTheWayDegInForce(
      planner_.path.turn_on_the_way_deg, params.scan_mode);
}

ExplorationLoop::~ExplorationLoop() = default;

mrpt::poses::CPose2D ExplorationLoop::poseEstimate() const
{
  return pose_at_stop_ + (robot_.odometry() - odo_at_stop_);
}

const ExplorationStatus& ExplorationLoop::run()
{
  t_start_ = clock_.now();
  try
  {
    loop();
    robot_.stop();  // a plan ended on the way leaves the robot moving (replan_on_the_way)
  }
  catch (RunStopped& stop)  // between two robot steps of a drive
  {
    robot_.stop();
    status_.termination_reason = std::move(stop.reason);
  }
  settleScan();  // a scan integrated beside the driving is in the outputs too
  slam_.finishMapRebuild();  // whatever ended the run, slam() holds the corrected OctoMap
  status_.elapsed_s = elapsedSeconds();
  return status_;
}

double ExplorationLoop::elapsedSeconds() const
{
  return mrpt::Clock::toDouble(clock_.now()) - mrpt::Clock::toDouble(t_start_);
}

std::string ExplorationLoop::limitReached(bool between_steps)
{
  if (listener_)
  {
    std::string reason = listener_->stopReason();
    if (!reason.empty()) return reason;
  }
  if (between_steps && status_.steps >= static_cast<std::size_t>(params_.max_steps))
    return "max_steps";
  status_.elapsed_s = elapsedSeconds();
  if (status_.elapsed_s >= params_.max_sim_time_s) return "max_sim_time";
  return {};
}

exploration::ProjectionCache* ExplorationLoop::projectionCache()
{
  const mapping::OctoMapLayer& map = slam_.octomap();
  if (const auto changed = map.changedSince(projected_at_))
    projection_cache_.markChanged(*changed);
  else
    projection_cache_.markAllChanged();
  projected_at_ = map.revision();
  return &projection_cache_;
}

void ExplorationLoop::loop()
{
  scanAndIntegrate();
  for (std::size_t step = 0;; step++)
  {
    settleScan();  // the planner reads the map
    if (auto reason = limitReached(true); !reason.empty())
    {
      status_.termination_reason = std::move(reason);
      return;
    }
    mrpt::system::CTicTac tic;
    // A frontier planned before whose view did not clear it is approached
    // (next-best-view): a view from 1-3 m does not show what lies behind a
    // narrow opening, and the frontier used to be given up after its second
    // plan with a wing of the building behind it (b2, compact, nbv: 0.59).
    std::vector<Eigen::Vector2d> approach;
    if (params_.approach_replanned)
      for (const auto& [c, n] : plans_)
        if (n > 0) approach.push_back(c);
    std::vector<Eigen::Vector2d> low = slam_.octomap().lowObstacles();
    if (listener_)
      listener_->onPlanInputs(exploration::PlanInputs{planPose(), step, blacklist_,
                                                      sensed_obstacles_, low, approach, swept_,
                                                      planner_.projection.region, looks_},
                              slam_.octomap().tree());
    auto plan = planNow(step, approach, low);
    if (!plan.ok() && slam_.octomapRebuildPending() > 0)
    {
      // The OctoMap after a loop closure is still being rebuilt over the
      // stops: the end is decided on the corrected map, not the old one.
      slam_.finishMapRebuild();
      low = slam_.octomap().lowObstacles();
      plan = planNow(step, approach, low);
    }
    setLowAtPlan(low);
    double cut_off_m2 = 0;  // known floor cut off from the robot, when the planner found nothing
    if (!plan.ok())
    {
      cut_off_m2 = cutOffFloorM2(plan);
      if (params_.cut_off_replan_m2 > 0) replanShutIn(plan, cut_off_m2, step, approach);
    }
    const double plan_s = tic.Tac();
    status_.compute_s += plan_s;
    status_.steps = step + 1;
    noteFrontiers(plan);
    if (listener_) listener_->onPlan(plan, plan_s * 1e3, status_);
    status_.slam_ms_step = 0;
    if (!plan.ok())
    {
      status_.termination_reason = exploration::toString(plan.done);
      noteCutOff(cut_off_m2);
      endShutIn(status_.termination_reason +
                "; no frontier is reachable: the pose estimate left the map's free space, or the map "
                "closed round the robot",
                cut_off_m2);
      return;
    }
    if (stagnated()) return;
    // A frontier planned again and again without disappearing (an unseeable
    // hole, a target the robot already stands on) is given up, and a step
    // that does not move the robot counts as a failed drive.
    const Eigen::Vector2d target =
        plan.frontier ? plan.frontier->center : Eigen::Vector2d(plan.target.x(), plan.target.y());
    registerPlan(target);
    planned_.push_back(target);
    const double path_before = status_.path_length_m;
    const Drive drive = driveWaypoints(plan);
    if (drive == Drive::Reached && status_.path_length_m - path_before < params_.min_progress_m)
      registerFailure(target);
    if (drive == Drive::Interrupted && params_.max_plans_per_target > 0)
    {
      // Not this target's fault: its plan is not counted.
      auto it = countFor(plans_, target);
      if (it->second > 0) it->second--;
    }
  }
}

exploration::PlanResult ExplorationLoop::planNow(std::size_t step,
                                                const std::vector<Eigen::Vector2d>& approach,
                                                const std::vector<Eigen::Vector2d>& low)
{
  checked_at_ = slam_.octomap().revision();
  return exploration::plan(slam_.octomap().tree(), planPose(), planner_, blacklist_, step,
                           swept_, sensed_obstacles_, approach, low, projectionCache(),
                           looks_.get());
}

ExplorationLoop::TargetCounts::iterator ExplorationLoop::countFor(TargetCounts& counts,
                                                                   const Eigen::Vector2d& target)
{
  const double radius = planner_.sampling.blacklist_radius_m;
  auto it = std::find_if(counts.begin(), counts.end(),
                         [&](const auto& f) { return (f.first - target).norm() <= radius; });
  if (it != counts.end()) return it;
  counts.emplace_back(target, 0);
  return std::prev(counts.end());
}

void ExplorationLoop::registerFailure(const Eigen::Vector2d& target)
{
  auto it = countFor(failures_, target);
  if (++it->second >= params_.max_failures_per_target)
  {
    blacklist_.push_back(target);
    status_.blacklisted = blacklist_.size();
    message("target " + mrpt::format("(%.2f, %.2f)", target.x(), target.y()) + " failed " +
            std::to_string(it->second) + " times: blacklisted");
  }
}

void ExplorationLoop::registerPlan(const Eigen::Vector2d& target)
{
  if (params_.max_plans_per_target <= 0) return;
  auto it = countFor(plans_, target);
  if (++it->second >= params_.max_plans_per_target)
  {
    blacklist_.push_back(target);
    status_.blacklisted = blacklist_.size();
    it->second = std::numeric_limits<int>::min();  // once
    message("target " + mrpt::format("(%.2f, %.2f)", target.x(), target.y()) + " planned " +
            std::to_string(params_.max_plans_per_target) +
            " times without being explored: blacklisted");
  }
}

void ExplorationLoop::rememberObstacles(const std::vector<Eigen::Vector2d>& points)
{
  // One point per 5 cm cell: a drive blocked again at the same place adds nothing.
  constexpr double kCell = 0.05;
  std::size_t added = 0;
  for (const auto& q : points)
  {
    const Eigen::Vector2d key(std::floor(q.x() / kCell), std::floor(q.y() / kCell));
    const bool known = std::any_of(sensed_obstacles_.begin(), sensed_obstacles_.end(),
                                   [&](const Eigen::Vector2d& o) {
                                     return std::floor(o.x() / kCell) == key.x() &&
                                            std::floor(o.y() / kCell) == key.y();
                                   });
    if (known) continue;
    sensed_obstacles_.push_back(q);
    ++added;
  }
  if (added)
    message(std::to_string(added) + " sensed point(s) in the way the map did not hold: occupied for the planner");
}

void ExplorationLoop::addSwept(const mrpt::poses::CPose2D& e)
{
  // The swept path in the pose estimate, 5 cm and 5 deg apart and continuous
  // across the jump of a SLAM correction at a stop (the body's true path is
  // continuous; either side of the jump is within the pose error).
  const Eigen::Vector3d q(e.x(), e.y(), e.phi());
  if (swept_.empty())
  {
    swept_.push_back(q);
    return;
  }
  const Eigen::Vector3d from = swept_.back();
  const double d = std::hypot(q.x() - from.x(), q.y() - from.y());
  const double dyaw = mrpt::math::wrapToPi(q.z() - from.z());
  const double kYawStep = mrpt::DEG2RAD(5.0);
  if (d < 0.05 && std::abs(dyaw) < kYawStep) return;
  const int n = std::max(static_cast<int>(std::ceil(d / 0.05)),
                         static_cast<int>(std::ceil(std::abs(dyaw) / kYawStep)));
  for (int k = 1; k <= n; ++k)
  {
    const double t = double(k) / n;
    swept_.emplace_back(from.x() + (q.x() - from.x()) * t, from.y() + (q.y() - from.y()) * t,
                        mrpt::math::wrapToPi(from.z() + dyaw * t));
  }
}

void ExplorationLoop::onRobotStep()
{
  const auto est = poseEstimate();  // the estimate the navigator drives by
  addSwept(est);
  status_.path_length_m += std::hypot(est.x() - last_estimate_.x(), est.y() - last_estimate_.y());
  last_estimate_ = est;
  {
    // Where the mission time goes: the velocity held over the step just made.
    const double now = mrpt::Clock::toDouble(robot_.now());
    const double dt = std::isnan(t_last_step_s_) ? 0.0 : now - t_last_step_s_;
    t_last_step_s_ = now;
    const auto v = robot_.velocity();
    if (std::hypot(v.vx, v.vy) > 1e-3)
      status_.time_translating_s += dt;
    else if (std::abs(v.omega) > 1e-3)
      status_.time_turning_s += dt;
  }
  if (pendingDue()) settleScan();
  if (params_.scan_mode == ExplorationLoopParams::ScanMode::Continuous && scanDue())
  {
    status_.scans_moving++;
    scanAndIntegrate(true);
  }
  if (listener_) listener_->onRobotStep();
  stopIfLimitReached();  // the limits hold inside a drive too (a drive may last minutes)
}

void ExplorationLoop::stopIfLimitReached()
{
  if (auto reason = limitReached(false); !reason.empty()) throw RunStopped{std::move(reason)};
}

void ExplorationLoop::message(const std::string& line)
{
  if (listener_) listener_->onMessage(line);
}

}  // namespace voxplore::mission
