#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>
#include <voxplore/common/config.h>
#include <voxplore/sim/Simulator.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <sstream>
#include <vector>

namespace voxplore::sim
{
using mrpt::poses::CPose2D;

void SimulatorParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(dt_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(scan_every_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(goal_tolerance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(goal_tolerance_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(floor_clearance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(segment_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(sensor_noise, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(camera_stagger_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(start_time_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(seed, int, c, s);
  using common::requireValid;
  requireValid(dt_s > 0 && dt_s <= 1.0, c, s, "dt_s", "must be in (0, 1] s");
  requireValid(scan_every_m > 0, c, s, "scan_every_m", "must be positive");
  requireValid(goal_tolerance_m > 0, c, s, "goal_tolerance_m", "must be positive");
  requireValid(goal_tolerance_yaw > 0, c, s, "goal_tolerance_yaw", "must be positive");
  requireValid(floor_clearance_m >= 0, c, s, "floor_clearance_m", "must be >= 0");
  requireValid(segment_timeout_s > 0, c, s, "segment_timeout_s", "must be positive");
  requireValid(camera_stagger_s >= 0 && camera_stagger_s <= 0.1, c, s, "camera_stagger_s",
               "must be in [0, 0.1] s");
}

void SimulatorParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(dt_s, c, s);
  MRPT_SAVE_CONFIG_VAR(scan_every_m, c, s);
  MRPT_SAVE_CONFIG_VAR(goal_tolerance_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(goal_tolerance_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(floor_clearance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(segment_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(sensor_noise, c, s);
  MRPT_SAVE_CONFIG_VAR(camera_stagger_s, c, s);
  MRPT_SAVE_CONFIG_VAR(start_time_s, c, s);
  MRPT_SAVE_CONFIG_VAR(seed, c, s);
}

const char* toString(DriveOutcome o)
{
  switch (o)
  {
    case DriveOutcome::Reached:
      return "reached";
    case DriveOutcome::Blocked:
      return "blocked";
    case DriveOutcome::Timeout:
      return "timeout";
  }
  return "?";
}

namespace
{
std::mt19937_64 makeRng(int seed, uint32_t stream)
{
  std::seed_seq seq{static_cast<uint32_t>(seed), stream, 0x766f78u};
  return std::mt19937_64(seq);
}
}  // namespace

Simulator::Simulator(
    World world, const RobotParams& robot, const CameraRigParams& cameras,
    const SimulatorParams& sim)
    : world_(std::move(world)),
      caster_(std::make_unique<RayCaster>(world_.mesh)),
      checker_(std::make_unique<CollisionChecker>(world_, sim.floor_clearance_m, robot.height_m)),
      params_(sim),
      robot_(robot, world_.start),
      rig_(cameras),
      rng_motion_(makeRng(sim.seed, 1)),
      rng_odo_(makeRng(sim.seed, 2)),
      rng_sensor_(makeRng(sim.seed, 3))
{
  if (checker_->collides(world_.start, robot.footprint()))
  {
    std::ostringstream os;
    os << world_.source_path << ": the robot start pose (x=" << world_.start.x()
       << ", y=" << world_.start.y() << ", yaw=" << mrpt::RAD2DEG(world_.start.phi())
       << " deg) is inside an obstacle or its " << robot.length_m << " x " << robot.width_m
       << " m footprint touches the world geometry; choose another start (--start x,y,yaw_deg)";
    throw std::runtime_error(os.str());
  }
}

mrpt::Clock::time_point Simulator::now() const
{
  return mrpt::Clock::fromDouble(params_.start_time_s + sim_time_s_);
}

OmniRobot::StepResult Simulator::step(double vx_mps, double vy_mps, double w_radps)
{
  sim_time_s_ += params_.dt_s;
  const auto r = robot_.step(vx_mps, vy_mps, w_radps, params_.dt_s, rng_motion_, checker_.get());
  history_.emplace_back(sim_time_s_, robot_.groundTruth());
  // Enough for eight exposures 0.1 s apart.
  while (history_.size() > 2 && history_.front().first < sim_time_s_ - 1.0) history_.pop_front();
  return r;
}

CPose2D Simulator::trueposeAt(double t) const
{
  if (history_.empty() || t >= history_.back().first) return robot_.groundTruth();
  if (t <= history_.front().first) return history_.front().second;
  auto hi = std::lower_bound(history_.begin(), history_.end(), t,
                             [](const auto& e, double v) { return e.first < v; });
  const auto lo = std::prev(hi);
  const double a = (t - lo->first) / (hi->first - lo->first);
  const CPose2D& p = lo->second;
  const CPose2D& q = hi->second;
  return CPose2D(p.x() + a * (q.x() - p.x()), p.y() + a * (q.y() - p.y()),
                 mrpt::math::wrapToPi(p.phi() + a * mrpt::math::wrapToPi(q.phi() - p.phi())));
}

DriveOutcome Simulator::driveTo(double x, double y, std::optional<double> yaw_rad)
{
  constexpr double kGainLin = 1.5;  // [1/s] proportional approach: smooth stop at the goal
  constexpr double kGainAng = 2.0;  // [1/s]
  const double t_end = sim_time_s_ + params_.segment_timeout_s;
  while (sim_time_s_ < t_end)
  {
    const CPose2D& p = robot_.groundTruth();
    const double ex = x - p.x(), ey = y - p.y();
    const double dist = std::hypot(ex, ey);
    const double eyaw = yaw_rad ? mrpt::math::wrapToPi(*yaw_rad - p.phi()) : 0.0;
    if (dist < params_.goal_tolerance_m && std::abs(eyaw) < params_.goal_tolerance_yaw)
      return DriveOutcome::Reached;
    const double speed = std::min(robot_.params().max_v_mps, kGainLin * dist);
    const double vx_w = dist > 1e-12 ? ex / dist * speed : 0.0;
    const double vy_w = dist > 1e-12 ? ey / dist * speed : 0.0;
    // World-frame velocity into the robot frame (rotation by -yaw).
    const double c = std::cos(p.phi()), s = std::sin(p.phi());
    const auto r = step(c * vx_w + s * vy_w, -s * vx_w + c * vy_w, kGainAng * eyaw);
    if (r.collided) return DriveOutcome::Blocked;
  }
  return DriveOutcome::Timeout;
}

ScanStop Simulator::scan(bool moving)
{
  // A standing scan takes one sensor period (20 Hz) of standing still; a
  // moving one was exposed while the robot drove up to now.
  if (!moving) sim_time_s_ += 0.05;
  ScanStop stop;
  stop.index = stops_++;
  stop.timestamp = now();
  stop.T_world_robot_gt = robot_.groundTruth();
  stop.odometry = robot_.readOdometry(rng_odo_);

  auto move = mrpt::obs::CActionRobotMovement2D::Create();
  move->computeFromOdometry(stop.odometry - odo_at_last_stop_, robot_.params().motionModel());
  move->timestamp = stop.timestamp;
  stop.actions = mrpt::obs::CActionCollection::Create();
  stop.actions->insert(*move);
  odo_at_last_stop_ = stop.odometry;

  stop.observations = mrpt::obs::CSensoryFrame::Create();
  auto odo = mrpt::obs::CObservationOdometry::Create();
  odo->sensorLabel = "ODOMETRY";
  odo->timestamp = stop.timestamp;
  odo->odometry = stop.odometry;
  if (!moving)
  {
    stop.observations->insert(odo);
    const auto scans = rig_.scan(*caster_, mrpt::poses::CPose3D(stop.T_world_robot_gt),
                                 stop.timestamp, rng_sensor_, params_.sensor_noise);
    for (const auto& o : scans) stop.observations->insert(o);
    return stop;
  }
  // The velocity the wheels executed over the last step, robot frame.
  const double dt = params_.dt_s;
  const CPose2D d = stop.T_world_robot_gt - trueposeAt(sim_time_s_ - dt);
  odo->hasVelocities = true;
  odo->velocityLocal = mrpt::math::TTwist2D(d.x() / dt, d.y() / dt, d.phi() / dt);
  stop.observations->insert(odo);
  const int n = rig_.params().num_cameras;
  std::vector<mrpt::poses::CPose3D> poses;
  std::vector<mrpt::Clock::time_point> times;
  for (int c = 0; c < n; c++)
  {
    const double t = sim_time_s_ - (n - 1 - c) * params_.camera_stagger_s;
    poses.emplace_back(trueposeAt(t));
    times.push_back(mrpt::Clock::fromDouble(params_.start_time_s + t));
  }
  const auto scans = rig_.scan(*caster_, poses, times, rng_sensor_, params_.sensor_noise);
  for (const auto& o : scans) stop.observations->insert(o);
  return stop;
}

}  // namespace voxplore::sim
