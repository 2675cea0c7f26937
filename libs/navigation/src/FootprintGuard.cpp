/* voxplore — FootprintGuard: velocity commands that keep the footprint's margin. */
#include "FootprintGuard.h"

#include <voxplore/common/velocity_ramp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_set>

namespace voxplore::navigation::detail
{
using mrpt::poses::CPose2D;

double rectangleClearance(const std::vector<Eigen::Vector2d>& points, double hl, double hw,
                          const CPose2D& pose)
{
  const double c = std::cos(pose.phi()), s = std::sin(pose.phi());
  double best2 = std::numeric_limits<double>::infinity();
  for (const auto& p : points)
  {
    const double dx = p.x() - pose.x(), dy = p.y() - pose.y();
    // The point in the rectangle's frame, folded into its first quadrant.
    const double qx = std::abs(c * dx + s * dy) - hl, qy = std::abs(-s * dx + c * dy) - hw;
    const double ex = std::max(qx, 0.0), ey = std::max(qy, 0.0);
    best2 = std::min(best2, ex * ex + ey * ey);
    if (best2 == 0.0) break;
  }
  return std::sqrt(best2);
}

CPose2D poseAfter(double vx, double vy, double w, double t)
{
  const double mid = 0.5 * w * t, c = std::cos(mid), s = std::sin(mid);
  return CPose2D((c * vx - s * vy) * t, (s * vx + c * vy) * t, w * t);
}

FootprintGuard::FootprintGuard(RobotInterface& inner, const GuardParams& params)
    : inner_(inner), params_(params)
{
}

bool FootprintGuard::refreshPoints()
{
  const auto t = inner_.now();
  if (raw_time_ && *raw_time_ == t) return raw_ok_;
  raw_time_ = t;
  raw_ok_ = inner_.obstacles(raw_);
  near_.clear();
  if (!raw_ok_) return false;
  // The points in the height band, one per 1 mm XY cell: the layers of a
  // vertical surface fall on the same spot.
  const auto& xs = raw_.getPointsBufferRef_x();
  const auto& ys = raw_.getPointsBufferRef_y();
  const auto& zs = raw_.getPointsBufferRef_z();
  const double reach = std::hypot(0.5 * params_.length_m, 0.5 * params_.width_m) + 1.0;
  std::unordered_set<std::int64_t> seen;
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    if (zs[i] < params_.z_min_m || zs[i] > params_.z_max_m) continue;
    if (std::hypot(xs[i], ys[i]) > reach) continue;
    const auto kx = static_cast<std::int64_t>(std::lround(xs[i] * 1000.0));
    const auto ky = static_cast<std::int64_t>(std::lround(ys[i] * 1000.0));
    if (seen.insert(kx * 4000003 + ky).second) near_.emplace_back(xs[i], ys[i]);
  }
  return true;
}

bool FootprintGuard::obstacles(mrpt::maps::CSimplePointsMap& out_robot_frame)
{
  const bool ok = refreshPoints();
  out_robot_frame = raw_;
  return ok;
}

double FootprintGuard::commandClearance(double vx, double vy, double w) const
{
  if (accelerationLimited()) return rampedClearance(vx, vy, w);
  const double hl = 0.5 * params_.length_m, hw = 0.5 * params_.width_m;
  const double H = params_.horizon_s;
  // Sub-steps of at most 1 cm of any footprint point's travel.
  const double travel = std::hypot(vx, vy) * H + std::abs(w) * H * std::hypot(hl, hw);
  const int n = std::max(1, static_cast<int>(std::ceil(travel / 0.01)));
  double best = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= n; k++)
    best = std::min(best, rectangleClearance(relevant_, hl, hw, poseAfter(vx, vy, w, H * k / n)));
  return best;
}

double FootprintGuard::rampedClearance(double vx, double vy, double w) const
{
  // The base's motion as the simulator executes it (common::rampedVelocity):
  // towards the command for horizon_s, then braking to a stand; the rectangle
  // is tested every 1 cm of any footprint point's travel and where it stops.
  const double hl = 0.5 * params_.length_m, hw = 0.5 * params_.width_m, r = std::hypot(hl, hw);
  const double a = params_.max_accel_mps2, alpha = params_.max_angular_accel;
  constexpr double kDt = 0.01;  // integration step [s]
  constexpr int kMaxSteps = 10000;
  mrpt::math::TTwist2D u = inner_.velocity();
  const mrpt::math::TTwist2D cmd{vx, vy, w}, halt{0, 0, 0};
  CPose2D pose(0, 0, 0);
  double best = std::numeric_limits<double>::infinity(), since = 0;
  const int ramp_steps = std::max(1, static_cast<int>(std::lround(params_.horizon_s / kDt)));
  for (int k = 0; k < kMaxSteps; k++)
  {
    const bool braking = k >= ramp_steps;
    if (braking && u.vx == 0 && u.vy == 0 && u.omega == 0) break;
    u = common::rampedVelocity(u, braking ? halt : cmd, a, alpha, kDt);
    pose = pose + poseAfter(u.vx, u.vy, u.omega, kDt);
    since += (std::hypot(u.vx, u.vy) + std::abs(u.omega) * r) * kDt;
    if (since < 0.01) continue;
    since = 0;
    best = std::min(best, rectangleClearance(relevant_, hl, hw, pose));
  }
  return std::min(best, rectangleClearance(relevant_, hl, hw, pose));
}

void FootprintGuard::setVelocity(double vx_mps, double vy_mps, double w_radps)
{
  const bool moving = std::abs(vx_mps) + std::abs(vy_mps) + std::abs(w_radps) > 1e-9;
  if (!refreshPoints())
  {
    // No obstacle points: no command is known to be safe.
    inner_.stop();
    held_now_ = moving;
    return;
  }
  const double hl = 0.5 * params_.length_m, hw = 0.5 * params_.width_m;
  last_clearance_m_ = rectangleClearance(near_, hl, hw, CPose2D());
  held_now_ = false;
  if (!moving)
  {
    inner_.setVelocity(vx_mps, vy_mps, w_radps);
    return;
  }
  // Never below the margin, and never closer when already below it.
  const double floor_m = std::min(params_.margin_m, last_clearance_m_) - 1e-4;
  // Only points within the circumcircle + the centre's travel + floor_m
  // can come nearer than floor_m to the rectangle at any scaled command.
  double travel = std::hypot(vx_mps, vy_mps) * params_.horizon_s;
  if (accelerationLimited())
  {
    // Ramping and braking: at most the faster of the held and the commanded
    // speed, for horizon_s and then its braking distance.
    const auto u = inner_.velocity();
    const double v = std::max(std::hypot(u.vx, u.vy), std::hypot(vx_mps, vy_mps));
    travel = v * params_.horizon_s +
             (params_.max_accel_mps2 > 0 ? v * v / (2 * params_.max_accel_mps2) : 0.0);
  }
  const double reach = std::hypot(hl, hw) + travel + std::max(floor_m, 0.0) + 1e-3;
  relevant_.clear();
  for (const auto& q : near_)
    if (q.squaredNorm() <= reach * reach) relevant_.push_back(q);
  double scale = 1.0;
  if (commandClearance(vx_mps, vy_mps, w_radps) < floor_m)
  {
    double lo = 0.0, hi = 1.0;  // scale 0 keeps the clearance as it is
    for (int i = 0; i < 10; i++)
    {
      const double mid = 0.5 * (lo + hi);
      (commandClearance(mid * vx_mps, mid * vy_mps, mid * w_radps) >= floor_m ? lo : hi) = mid;
    }
    scale = lo;
    scaled_++;
    held_now_ = scale < 0.05;
    held_ += held_now_;
  }
  inner_.setVelocity(scale * vx_mps, scale * vy_mps, scale * w_radps);
}

void FootprintGuard::stop()
{
  held_now_ = false;
  held_s_ = 0;  // a new drive starts unheld
  inner_.stop();
}

void FootprintGuard::step(double dt_s)
{
  inner_.step(dt_s);
  held_s_ = held_now_ ? held_s_ + dt_s : 0.0;
}

}  // namespace voxplore::navigation::detail
