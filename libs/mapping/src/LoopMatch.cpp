// Loop detection (see LoopClosure.h): the submap of old keyframes, the
// match against it, and the anchor-pass check of a match.
#include <voxplore/mapping/LoopClosure.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_set>

#include "cell_key.h"
#include "pose_diff.h"

namespace voxplore::mapping
{
using detail::cellKey;
using detail::xyDist;
using detail::yawDiff;
using mrpt::poses::CPose2D;

mrpt::maps::CSimplePointsMap LoopCloser::submapAround(const CPose2D& around, Viewpoints& viewpoints,
                                                      double min_travel_m, double max_travel_m) const
{
  mrpt::maps::CSimplePointsMap out;
  viewpoints.clear();
  std::unordered_set<uint64_t> seen;
  const double inv = 1.0 / params_.submap_cell_m;
  for (const auto& kf : keyframes_)
  {
    if (kf.travel_m < min_travel_m || kf.travel_m > max_travel_m ||
        xyDist(kf.pose, around) > params_.submap_radius_m)
      continue;
    const double c = std::cos(kf.pose.phi()), s = std::sin(kf.pose.phi());
    const auto& xs = kf.cloud.getPointsBufferRef_x();
    const auto& ys = kf.cloud.getPointsBufferRef_y();
    for (std::size_t i = 0; i < xs.size(); i++)
    {
      const double x = kf.pose.x() + c * xs[i] - s * ys[i];
      const double y = kf.pose.y() + s * xs[i] + c * ys[i];
      const auto k = cellKey(static_cast<int64_t>(std::floor(x * inv)),
                             static_cast<int64_t>(std::floor(y * inv)), 0);
      if (seen.insert(k).second)
      {
        out.insertPointFast(static_cast<float>(x), static_cast<float>(y), 0.f);
        viewpoints.emplace_back(static_cast<float>(kf.pose.x()), static_cast<float>(kf.pose.y()));
      }
    }
  }
  out.mark_as_modified();
  return out;
}

std::optional<IcpResult> LoopCloser::chainRegistration(const Keyframe& kf) const
{
  const Keyframe& prev = keyframes_.back();  // implicitLoop() found an older one
  const CPose2D predicted = prev.pose + (kf.odometry - prev.odometry);
  Viewpoints views;
  const auto recent = submapAround(predicted, views, kf.travel_m - params_.chain_recent_m, prev.travel_m);
  if (recent.empty()) return std::nullopt;
  IcpParams p = icp_;
  p.enabled = true;
  IcpResult r = alignPlanar(recent, kf.cloud, predicted, p, &views);
  if (!r.accepted || r.degenerate || r.pairs == 0) return std::nullopt;
  return r;
}

std::optional<std::size_t> LoopCloser::nearestOlderThanChain(const CPose2D& pose, double travel_m) const
{
  const double max_travel = travel_m - params_.chain_recent_m;
  double best = params_.submap_radius_m;
  std::optional<std::size_t> out;
  for (std::size_t i = 0; i < keyframes_.size() && keyframes_[i].travel_m <= max_travel; i++)
    if (const double d = xyDist(keyframes_[i].pose, pose); d <= best)
    {
      best = d;
      out = i;
    }
  return out;
}

std::optional<LoopCloser::ImplicitLoop> LoopCloser::implicitLoop(const Keyframe& kf) const
{
  const auto old = nearestOlderThanChain(kf.pose, kf.travel_m);
  if (!old || *old + 1 >= keyframes_.size()) return std::nullopt;
  // The metaview registration pulled on the old keyframes' points only if
  // it paired them: an old keyframe behind a wall would pin the drifted
  // estimate to it.
  Viewpoints views;
  const auto old_map = submapAround(kf.pose, views, -std::numeric_limits<double>::infinity(),
                                    kf.travel_m - params_.chain_recent_m);
  const double share = old_map.empty() ? 0.0 : goodnessAt(old_map, kf.cloud, kf.pose, icp_, &views);
  if (share < params_.implicit_min_old_share) return std::nullopt;
  auto chain = chainRegistration(kf);
  if (!chain) return std::nullopt;
  return ImplicitLoop{*chain, *old, share};
}

std::optional<IcpResult> LoopCloser::match(LoopEvent& ev, std::size_t& anchor)
{
  const Keyframe& cur = keyframes_.back();
  const double max_travel = cur.travel_m - params_.min_travel_m;
  // The nearest old keyframe: is there anything old close enough to overlap?
  double best = params_.search_radius_m;
  bool any = false;
  for (std::size_t i = 0; i + 1 < keyframes_.size(); i++)
  {
    const auto& kf = keyframes_[i];
    if (kf.travel_m > max_travel) break;  // travel grows with the index
    const double d = xyDist(kf.pose, cur.pose);
    if (d <= best)
    {
      best = d;
      anchor = i;
      any = true;
    }
  }
  if (!any) return std::nullopt;
  if (params_.min_points > 0 && cur.cloud_points < static_cast<std::size_t>(params_.min_points))
  {
    ev.message = "no loop search: a cloud of " + std::to_string(cur.cloud_points) +
                 " points, under min_points";
    return std::nullopt;
  }
  ev.searched = true;
  // One pass: the keyframes within submap_pass_m of travel of the nearest.
  double pass_lo = -std::numeric_limits<double>::infinity(), pass_hi = max_travel;
  if (params_.submap_pass_m > 0)
  {
    pass_lo = keyframes_[anchor].travel_m - params_.submap_pass_m;
    pass_hi = std::min(max_travel, keyframes_[anchor].travel_m + params_.submap_pass_m);
  }
  Viewpoints views;
  const auto submap = submapAround(cur.pose, views, pass_lo, pass_hi);
  const double travelled = cur.travel_m - keyframes_[anchor].travel_m;
  IcpParams p = icp_;
  p.enabled = true;
  p.min_goodness = params_.min_goodness;
  p.low_overlap_min_goodness = 0;  // a loop is taken on its own goodness only
  p.max_correction_xy_m =
      std::clamp(params_.drift_per_m * travelled, params_.min_window_m, params_.max_window_m);
  p.max_correction_yaw = std::clamp(params_.yaw_drift_per_m * travelled, params_.min_window_yaw,
                                    params_.max_window_yaw);
  // 1. From the estimate: the common case (the graph already agrees).
  IcpResult r = alignPlanar(submap, cur.cloud, cur.pose, p, &views);
  if (!(r.accepted && consistent(r.pose, cur.pose) && !r.degenerate))
  {
    // 2. A search over the pose uncertainty, accepted only when good,
    //    unambiguous and not degenerate (relocalizePlanar's rules).
    p.relocalize_radius_m = p.max_correction_xy_m;
    p.relocalize_yaw = p.max_correction_yaw;
    p.relocalize_min_goodness = params_.min_goodness;
    p.relocalize_margin = params_.margin;
    r = relocalizePlanar(submap, cur.cloud, cur.pose, p, &views);
  }
  ev.goodness = r.goodness;
  if (!r.accepted || r.degenerate)
  {
    ev.message = "no loop: " + (r.degenerate ? std::string("degenerate match") : r.reason);
    return std::nullopt;
  }
  // Judged on the match taken, which relocalisation may have replaced.
  const bool correcting = !consistent(r.pose, cur.pose);
  // A correcting match with lopsided information must hold along its weak
  // direction (probe_ratio). Not a consistent one that would confirm a
  // waiting candidate: the candidate was probed, and consistent matches
  // there slid while right (b2 compact nearest, b3 compact nbv seed 3).
  if (correcting)
    if (const auto why = slidesAlongWeak(submap, views, r, p))
    {
      ev.message = "no loop: " + *why;
      return std::nullopt;
    }
  // The old keyframe nearest to the matched pose anchors the edge.
  double dmin = 1e9;
  for (std::size_t i = 0; i + 1 < keyframes_.size() && keyframes_[i].travel_m <= pass_hi; i++)
    if (const double d = xyDist(keyframes_[i].pose, r.pose);
        d < dmin && keyframes_[i].travel_m >= pass_lo)
    {
      dmin = d;
      anchor = i;
    }
  // A correcting match must hold against its anchor's own pass.
  if (params_.anchor_check_m > 0 && correcting)
    if (const auto why = anchorDisagrees(ev, r, anchor, pass_hi, p))
    {
      ev.message = "no loop: " + *why;
      return std::nullopt;
    }
  return r;
}

double slideAlongWeak(const mrpt::maps::CPointsMap& submap, const Viewpoints* views,
                      const mrpt::maps::CPointsMap& cloud_robot, const CPose2D& prediction,
                      const IcpResult& match, const IcpParams& p, double probe_m)
{
  if (!(match.degenerate_dir.norm() > 0.5))
    return std::numeric_limits<double>::infinity();  // no direction
  const Eigen::Vector2d w = match.degenerate_dir.normalized();
  double worst = 0;
  for (const double side : {-1.0, 1.0})
  {
    const CPose2D start(match.pose.x() + side * probe_m * w.x(),
                        match.pose.y() + side * probe_m * w.y(), match.pose.phi());
    // Where ICP converges from there (icp_pose: also when it is refused).
    const IcpResult q = alignPlanar(submap, cloud_robot, prediction, p, views, 0.0, &start);
    worst = std::max(worst, xyDist(q.icp_pose, match.pose));
  }
  return worst;
}

std::optional<std::string> LoopCloser::slidesAlongWeak(const mrpt::maps::CPointsMap& submap,
                                                       const Viewpoints& views, const IcpResult& r,
                                                       const IcpParams& p) const
{
  if (r.info_ratio >= params_.probe_ratio) return std::nullopt;
  const Keyframe& cur = keyframes_.back();
  const double worst = slideAlongWeak(submap, &views, cur.cloud, cur.pose, r, p, params_.probe_m);
  if (worst <= params_.probe_tol_m) return std::nullopt;
  const Eigen::Vector2d& w = r.degenerate_dir;  // a unit eigenvector (zero: no information)
  std::ostringstream why;
  why.precision(3);
  why << "the match slides along (" << w.x() << ", " << w.y() << ") (information ratio "
      << r.info_ratio << "): registered from " << params_.probe_m
      << " m either side there it ends up to " << worst << " m from it";
  return why.str();
}

bool LoopCloser::consistent(const CPose2D& matched, const CPose2D& estimate) const
{
  return xyDist(matched, estimate) <= params_.consistent_m &&
         std::abs(yawDiff(matched, estimate)) <= params_.consistent_yaw;
}

std::optional<std::string> LoopCloser::anchorDisagrees(LoopEvent& ev, const IcpResult& r,
                                                       std::size_t anchor, double max_travel,
                                                       const IcpParams& p) const
{
  const Keyframe& a = keyframes_[anchor];
  Viewpoints views;
  const auto pass = submapAround(r.pose, views, a.travel_m - params_.anchor_pass_m,
                                 std::min(max_travel, a.travel_m + params_.anchor_pass_m));
  IcpParams q = p;
  q.min_goodness = params_.anchor_min_goodness;
  const IcpResult own = alignPlanar(pass, keyframes_.back().cloud, r.pose, q, &views);
  ev.anchor_goodness = own.goodness;
  ev.anchor_shift_m = xyDist(own.pose, r.pose);
  ev.anchor_shift_yaw = yawDiff(own.pose, r.pose);
  // A pass that sees too little of the cloud cannot judge the match: no
  // veto (b3 omniRob nbv: passes pairing 0.12-0.47 refused two right
  // closures). One that sees enough must hold it where it is.
  if (own.goodness < params_.anchor_min_goodness) return std::nullopt;
  std::ostringstream why;
  why.precision(3);
  if (!own.accepted)
    why << "stop " << a.stop << "'s own pass does not hold the match (goodness " << own.goodness
        << ", " << own.reason << ")";
  else if (ev.anchor_shift_m > params_.anchor_check_m ||
           std::abs(ev.anchor_shift_yaw) > params_.anchor_check_yaw)
    why << "stop " << a.stop << "'s own pass moves the match " << ev.anchor_shift_m << " m, "
        << mrpt::RAD2DEG(ev.anchor_shift_yaw) << " deg (goodness " << own.goodness << ")";
  else
    return std::nullopt;
  return why.str();
}

}  // namespace voxplore::mapping
