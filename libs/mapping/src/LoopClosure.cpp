// Loop closure: keyframes, pose graph, detection against old keyframes only,
// relaxation with MRPT's optimize_graph_spa_levmarq (see LoopClosure.h).
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/mapping/LoopClosure.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "cell_key.h"
#include "pose_diff.h"

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;

using detail::cellKey;
using detail::shiftDist;
using detail::xyDist;
using detail::yawDiff;

namespace
{
/// "; its anchor's pass moves it ..." when the anchor-pass check ran
std::string anchorNote(const LoopEvent& ev)
{
  if (ev.anchor_shift_m < 0) return {};
  std::ostringstream o;
  o.precision(3);
  o << "; its anchor's pass moves it " << ev.anchor_shift_m << " m, "
    << mrpt::RAD2DEG(ev.anchor_shift_yaw) << " deg, goodness " << ev.anchor_goodness;
  return o.str();
}
}  // namespace

mrpt::maps::CSimplePointsMap reduceCloud(const mrpt::maps::CPointsMap& cloud, double cell_m)
{
  mrpt::maps::CSimplePointsMap out;
  const auto& xs = cloud.getPointsBufferRef_x();
  const auto& ys = cloud.getPointsBufferRef_y();
  const auto& zs = cloud.getPointsBufferRef_z();
  if (cell_m <= 0)
  {
    out.reserve(xs.size());
    for (std::size_t i = 0; i < xs.size(); i++) out.insertPointFast(xs[i], ys[i], zs[i]);
    return out;
  }
  std::unordered_set<uint64_t> seen;
  seen.reserve(xs.size());
  const double inv = 1.0 / cell_m;
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    const auto k = cellKey(static_cast<int64_t>(std::floor(xs[i] * inv)),
                           static_cast<int64_t>(std::floor(ys[i] * inv)),
                           static_cast<int64_t>(std::floor(zs[i] * inv)));
    if (seen.insert(k).second) out.insertPointFast(xs[i], ys[i], zs[i]);
  }
  out.mark_as_modified();
  return out;
}

struct LoopCloser::Graph
{
  mrpt::graphs::CNetworkOfPoses2DInf net;

  void addEdge(std::size_t from, std::size_t to, const CPose2D& mean, const Eigen::Matrix3d& info)
  {
    mrpt::graphs::CNetworkOfPoses2DInf::edge_t e;
    e.mean = mean;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) e.cov_inv(i, j) = info(i, j);
    net.insertEdge(from, to, e);
  }

  /// Replaces the consecutive edge from -> to (there is one).
  void replaceEdge(std::size_t from, std::size_t to, const CPose2D& mean, const Eigen::Matrix3d& info)
  {
    auto it = net.edges.find(mrpt::graphs::TPairNodeIDs(from, to));
    if (it == net.edges.end()) return;
    it->second.mean = mean;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) it->second.cov_inv(i, j) = info(i, j);
  }
};

LoopCloser::LoopCloser(const LoopClosureParams& params, const IcpParams& icp)
    : params_(params), icp_(icp), graph_(std::make_unique<Graph>())
{
  graph_->net.root = 0;
}
LoopCloser::~LoopCloser() = default;
LoopCloser::LoopCloser(LoopCloser&&) noexcept = default;
LoopCloser& LoopCloser::operator=(LoopCloser&&) noexcept = default;

std::size_t LoopCloser::numEdges() const { return graph_->net.edges.size(); }

Eigen::Matrix3d LoopCloser::edgeInformation(const IcpResult* reg, const CPose2D& from,
                                            double dist_m) const
{
  const auto& p = params_;
  Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
  if (!reg || reg->pairs == 0 || !reg->information.allFinite())
  {
    // Odometry only: std grows with the distance driven.
    const double d = std::max(dist_m, 0.1);
    const double sxy = std::clamp(p.odometry_std_per_m * d, p.edge_min_std_m, p.edge_max_std_m);
    const double syaw =
        std::clamp(p.odometry_std_yaw_per_m * d, p.edge_min_std_yaw, p.edge_max_std_yaw);
    out(0, 0) = out(1, 1) = 1.0 / (sxy * sxy);
    out(2, 2) = 1.0 / (syaw * syaw);
    return out;
  }
  // The point-to-line information J^T J is for the absolute pose (map-frame
  // x, y and yaw about the robot); the edge is in the frame of `from`:
  // Omega_local = B^T Omega B with B = blkdiag(R_from, 1).
  const double sigma = std::max(reg->rms_m, p.edge_sigma_floor_m);
  const Eigen::Matrix3d info = reg->information * (p.edge_info_scale / (sigma * sigma));
  Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
  const double c = std::cos(from.phi()), s = std::sin(from.phi());
  B(0, 0) = c;
  B(0, 1) = -s;
  B(1, 0) = s;
  B(1, 1) = c;
  const Eigen::Matrix3d local = B.transpose() * info * B;
  // Clamp the translational eigenvalues and the yaw term to the std bounds
  // (cross terms dropped: they mix units and would defeat the clamping).
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(local.topLeftCorner<2, 2>());
  Eigen::Vector2d ev = es.eigenvalues();
  const double lo = 1.0 / (p.edge_max_std_m * p.edge_max_std_m);
  const double hi = 1.0 / (p.edge_min_std_m * p.edge_min_std_m);
  for (int i = 0; i < 2; i++) ev(i) = std::clamp(ev(i), lo, hi);
  out.topLeftCorner<2, 2>() = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
  out(2, 2) = std::clamp(local(2, 2), 1.0 / (p.edge_max_std_yaw * p.edge_max_std_yaw),
                         1.0 / (p.edge_min_std_yaw * p.edge_min_std_yaw));
  return out;
}

void LoopCloser::addLoopEdge(std::size_t anchor, std::size_t kf, const CPose2D& matched,
                             const IcpResult& reg)
{
  const CPose2D& from = keyframes_[anchor].pose;
  graph_->addEdge(anchor, kf, matched - from, edgeInformation(&reg, from, 0));
  loop_edges_++;
}

std::pair<double, double> LoopCloser::optimize()
{
  if (keyframes_.size() < 2) return {0, 0};
  mrpt::graphslam::TResultInfoSpaLevMarq info;
  mrpt::containers::yaml extra;
  extra["max_iterations"] = params_.max_iterations;
  mrpt::graphslam::optimize_graph_spa_levmarq(graph_->net, info, nullptr, extra);
  double max_shift = 0, sum = 0;
  for (std::size_t i = 0; i < keyframes_.size(); i++)
  {
    const CPose2D& n = graph_->net.nodes.at(i);
    const double shift = shiftDist(n, keyframes_[i].pose);
    max_shift = std::max(max_shift, shift);
    sum += shift;
    keyframes_[i].pose = n;
  }
  return {max_shift, sum / double(keyframes_.size())};
}

bool LoopCloser::independentOf(const CPose2D& moved) const
{
  if (params_.confirm_min_move_m <= 0 && params_.confirm_min_turn <= 0) return true;
  const bool far = params_.confirm_min_move_m > 0 &&
                   std::hypot(moved.x(), moved.y()) >= params_.confirm_min_move_m;
  const bool turned = params_.confirm_min_turn > 0 &&
                      std::abs(mrpt::math::wrapToPi(moved.phi())) >= params_.confirm_min_turn;
  return far || turned;
}

LoopCloser::Agreement LoopCloser::agreement(const Pending& pending, const Keyframe& cur,
                                            const CPose2D& matched) const
{
  // Verification: the first match carried forward by the odometry must
  // land where this stop's own match puts it.
  const CPose2D moved = cur.odometry - keyframes_[pending.kf].odometry;
  const CPose2D expect = pending.matched + moved;
  Agreement a;
  a.err_m = xyDist(expect, matched);
  a.err_yaw = std::abs(yawDiff(expect, matched));
  a.agrees = a.err_m <= params_.confirm_xy_m + params_.confirm_per_m * std::hypot(moved.x(), moved.y()) &&
             a.err_yaw <= params_.confirm_yaw;
  return a;
}

void LoopCloser::relax(LoopEvent& ev)
{
  mrpt::system::CTicTac tic;
  const auto [max_shift, mean_shift] = optimize();
  ev.t_optimize_ms = 1e3 * tic.Tac();
  ev.closed = true;
  ev.graph_shift_max_m = max_shift;
  ev.graph_shift_mean_m = mean_shift;
}

void LoopCloser::closePending(LoopEvent& ev, const IcpResult* match, std::size_t anchor)
{
  addLoopEdge(pending_->anchor, pending_->kf, pending_->matched, pending_->reg);
  if (match)
    addLoopEdge(anchor, keyframes_.size() - 1, match->pose, *match);
  else
  {
    // Confirmed by a consistent match: the registrations since the candidate
    // carried the estimate onto the old map, so their edges hold that jump as
    // if the robot had moved it. Both ends are now tied to the old map by
    // loop edges; between them the odometry says how the robot moved.
    for (std::size_t i = pending_->kf + 1; i < keyframes_.size(); i++)
    {
      const Keyframe& a = keyframes_[i - 1];
      const Keyframe& b = keyframes_[i];
      const CPose2D odo = b.odometry - a.odometry;
      graph_->replaceEdge(i - 1, i, odo,
                          edgeInformation(nullptr, a.pose, std::hypot(odo.x(), odo.y())));
    }
  }
  pending_.reset();
  relax(ev);
}

void LoopCloser::relaxImplicitLoop(LoopEvent& ev, const ImplicitLoop& implicit,
                                   const CPose2D& registered)
{
  const Keyframe& a = keyframes_[implicit.anchor];
  ev.with_stop = a.stop;
  ev.matched = registered;
  ev.correction_m = xyDist(registered, implicit.chain.pose);
  ev.correction_yaw = yawDiff(registered, implicit.chain.pose);
  relax(ev);
  std::ostringstream msg;
  msg.precision(3);
  if (!ev.message.empty()) msg << ev.message << "; ";
  msg << "implicit loop with stop " << a.stop << ": the metaview registration (old keyframes pair "
      << implicit.old_share << " of the cloud) is " << ev.correction_m
      << " m, " << mrpt::RAD2DEG(ev.correction_yaw) << " deg from the recent pass's; graph moved "
      << ev.graph_shift_max_m << " m at most";
  ev.message = msg.str();
}

LoopEvent LoopCloser::addKeyframe(std::size_t stop, const CPose2D& pose, const CPose2D& odometry,
                                  double travel_m, const mrpt::maps::CPointsMap& cloud_robot,
                                  double d_min_m, const IcpResult* reg)
{
  LoopEvent ev;
  Keyframe kf;
  kf.stop = stop;
  kf.pose = pose;
  kf.odometry = odometry;
  kf.travel_m = travel_m;
  kf.cloud = reduceCloud(cloud_robot, d_min_m);
  kf.cloud_points = cloud_robot.size();
  const std::size_t k = keyframes_.size();
  graph_->net.nodes[k] = pose;
  // chain_recent_m: where old keyframes are near, the edge from the previous
  // keyframe is the recent pass's registration and the metaview's joins the
  // nearest old keyframe.
  std::optional<ImplicitLoop> implicit;
  if (k > 0 && params_.enabled && params_.chain_recent_m > 0 && reg) implicit = implicitLoop(kf);
  if (k > 0)
  {
    const Keyframe& prev = keyframes_.back();
    if (implicit)
      graph_->addEdge(k - 1, k, implicit->chain.pose - prev.pose,
                      edgeInformation(&implicit->chain, prev.pose, 0));
    else
      graph_->addEdge(k - 1, k, pose - prev.pose,
                      edgeInformation(reg, prev.pose, xyDist(pose, prev.pose)));
  }
  keyframes_.push_back(std::move(kf));
  if (!params_.enabled) return ev;
  bool relax_implicit = false;
  if (implicit)
  {
    // The metaview registration as an edge from the old keyframe, at the
    // poses as registered (before any relaxation below).
    const Keyframe& a = keyframes_[implicit->anchor];
    graph_->addEdge(implicit->anchor, k, pose - a.pose, edgeInformation(reg, a.pose, 0));
    loop_edges_++;
    // Registrations scatter by a few centimetres (loop errors of 1-10 cm at
    // 3-5 cm disagreements, replays): only a larger return relaxes.
    relax_implicit = !consistent(implicit->chain.pose, pose) &&
                     shiftDist(implicit->chain.pose, pose) >= params_.implicit_min_m;
  }
  detectLoop(ev);
  if (relax_implicit && !ev.closed) relaxImplicitLoop(ev, *implicit, pose);
  return ev;
}

void LoopCloser::detectLoop(LoopEvent& ev)
{
  const std::size_t k = keyframes_.size() - 1;
  mrpt::system::CTicTac tic;
  std::size_t anchor = 0;
  const auto m = match(ev, anchor);
  ev.t_detect_ms = 1e3 * tic.Tac();
  if (pending_ && k - pending_->kf > static_cast<std::size_t>(params_.confirm_within))
  {
    ev.message += (ev.message.empty() ? "" : "; ") + std::string("loop candidate at stop ") +
                  std::to_string(keyframes_[pending_->kf].stop) + " not confirmed: dropped";
    pending_.reset();
  }
  if (!m) return;
  const Keyframe& cur = keyframes_.back();
  ev.with_stop = keyframes_[anchor].stop;
  ev.matched = m->pose;
  ev.correction_m = xyDist(m->pose, cur.pose);
  ev.correction_yaw = yawDiff(m->pose, cur.pose);
  std::ostringstream msg;
  msg.precision(3);
  if (!ev.message.empty()) msg << ev.message << "; ";  // a candidate dropped above
  if (consistent(m->pose, cur.pose))
  {
    addLoopEdge(anchor, k, m->pose, *m);
    ev.consistent = true;
    msg << "consistent with stop " << ev.with_stop << " (correction " << ev.correction_m << " m)";
    // The registration against the metaview can carry the estimate onto the
    // old map by itself before a stop confirms the candidate (b5 omniRob
    // nbv seed 2: a 9 cm candidate, then ICP corrections of 5 cm, 2 cm and
    // 5 cm onto the start's map, then "consistent"). The drifted stretch
    // behind it stays in the maps unless the candidate closes, and a
    // consistent match that agrees with the candidate confirms it as any
    // other match does.
    if (pending_ && params_.confirm_when_consistent &&
        independentOf(cur.odometry - keyframes_[pending_->kf].odometry))
    {
      const std::size_t first_stop = keyframes_[pending_->kf].stop;
      const Agreement a = agreement(*pending_, cur, m->pose);
      if (a.agrees)
      {
        // The loop is the candidate's: its old stop and its correction.
        const Keyframe& pk = keyframes_[pending_->kf];
        ev.with_stop = keyframes_[pending_->anchor].stop;
        ev.correction_m = xyDist(pending_->matched, pk.pose);
        ev.correction_yaw = yawDiff(pending_->matched, pk.pose);
        closePending(ev, nullptr, anchor);
        msg << "; loop closed with stop " << ev.with_stop << " (stop " << first_stop
            << "'s candidate, correction " << ev.correction_m << " m, "
            << mrpt::RAD2DEG(ev.correction_yaw) << " deg; this match agrees with it within "
            << a.err_m << " m, " << mrpt::RAD2DEG(a.err_yaw) << " deg); graph moved "
            << ev.graph_shift_max_m << " m at most";
      }
      else
        msg << "; loop candidate at stop " << first_stop << " disagrees with it by " << a.err_m
            << " m, " << mrpt::RAD2DEG(a.err_yaw) << " deg";
    }
    ev.message = msg.str();
    return;
  }
  if (pending_)
  {
    const Keyframe& pk = keyframes_[pending_->kf];
    const CPose2D moved = cur.odometry - pk.odometry;
    if (!independentOf(moved))
    {
      msg << "loop candidate at stop " << pk.stop << " waits: this stop moved "
          << std::hypot(moved.x(), moved.y()) << " m, " << mrpt::RAD2DEG(std::abs(moved.phi()))
          << " deg from it";
      ev.message = msg.str();
      return;
    }
    const Agreement a = agreement(*pending_, cur, m->pose);
    if (a.agrees)
    {
      const std::size_t first_stop = pk.stop;
      closePending(ev, &*m, anchor);
      msg << "loop closed with stop " << ev.with_stop << " (correction " << ev.correction_m
          << " m, " << mrpt::RAD2DEG(ev.correction_yaw) << " deg; confirmed by stop "
          << first_stop << anchorNote(ev) << "); graph moved " << ev.graph_shift_max_m << " m at most";
      ev.message = msg.str();
      return;
    }
    msg << "loop candidate at stop " << pk.stop << " disagrees with this one by " << a.err_m
        << " m, " << mrpt::RAD2DEG(a.err_yaw) << " deg: replaced; ";
  }
  pending_ = Pending{k, anchor, m->pose, *m};
  ev.candidate = true;
  msg << "loop candidate with stop " << ev.with_stop << " (correction " << ev.correction_m
      << " m, goodness " << m->goodness << ", information ratio " << m->info_ratio
      << anchorNote(ev) << "), to be confirmed";
  ev.message = msg.str();
}

}  // namespace voxplore::mapping
