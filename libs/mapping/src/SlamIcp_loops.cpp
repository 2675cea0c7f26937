// SlamIcp and loop closure: keyframes into the pose graph, corrected poses
// after a relaxation, and the metaview and OctoMap rebuilt from the keyframes.
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/mapping/SlamIcp.h>

#include <algorithm>
#include <stdexcept>

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;

void SlamIcp::closeLoops(StopReport& rep, const RobotCloud& cloud)
{
  if (!params_.loop_closure.enabled || !rep.integrated) return;
  // The edge from the previous keyframe carries this stop's registration
  // information when ICP registered it (else odometry's).
  const IcpResult* reg = rep.icp.accepted && rep.icp.pairs > 0 ? &rep.icp : nullptr;
  rep.loop = loop_.addKeyframe(rep.index, rep.pose, rep.odometry, travel_m_, cloud.points,
                               params_.metaview.d_min_m, reg);
  if (!rep.loop.closed) return;
  loop_closures_++;
  max_graph_shift_m_ = std::max(max_graph_shift_m_, rep.loop.graph_shift_max_m);
  applyCorrection();
  if (rep.loop.graph_shift_max_m > params_.loop_closure.rebuild_min_shift_m)
  {
    const auto per_stop = static_cast<std::size_t>(params_.loop_closure.octomap_rebuild_per_stop);
    rep.loop.t_rebuild_ms = rebuildMaps(per_stop);
    rep.loop.rebuilt = true;
    rep.octomap_rebuild_left = octomapRebuildPending();
    rep.octomap_rebuilt_keyframes = loop_.keyframes().size() - rep.octomap_rebuild_left;
  }
  pose_ = reports_.back().pose;
  rep.metaview_size = metaview_.size();
}

void SlamIcp::applyCorrection()
{
  const auto& kfs = loop_.keyframes();
  if (kfs.empty()) return;
  std::vector<CPose2D> before;  // the poses before the correction, by stop index
  before.reserve(reports_.size());
  for (const auto& r : reports_) before.push_back(r.pose);
  std::size_t ki = 0;
  for (auto& r : reports_)
  {
    while (ki + 1 < kfs.size() && kfs[ki + 1].stop <= r.index) ki++;
    const auto& kf = kfs[ki];
    if (kf.stop > r.index) continue;  // before the first keyframe: nothing to anchor to
    if (kf.stop == r.index)
      r.pose = kf.pose;
    else  // not integrated: keep its offset to the keyframe before it
      r.pose = kf.pose + (before[r.index] - before[kf.stop]);
  }
  // The simplemap's keyframes are the integrated stops, in order.
  if (simplemap_.size() != kfs.size())
    throw std::logic_error("SlamIcp: " + std::to_string(simplemap_.size()) +
                           " simplemap keyframes but " + std::to_string(kfs.size()) +
                           " pose-graph keyframes");
  for (std::size_t i = 0; i < kfs.size(); i++)
  {
    mrpt::poses::CPose3DPDF::Ptr pdf;
    mrpt::obs::CSensoryFrame::Ptr sf;
    simplemap_.get(i, pdf, sf);
    simplemap_.set(i, mrpt::poses::CPose3DPDFGaussian::Create(mrpt::poses::CPose3D(kfs[i].pose)), sf);
  }
}

double SlamIcp::rebuildMaps(std::size_t octomap_keyframes)
{
  mrpt::system::CTicTac tic;
  const auto& kfs = loop_.keyframes();
  // The metaview: each keyframe's points moved rigidly with it (the next
  // registration needs it now; re-inserting every keyframe cost 5.9 s at
  // 1,000 keyframes, moving them 0.25 s; loops benchmark, one core).
  std::vector<CPose2D> poses;
  poses.reserve(kfs.size());
  for (const auto& kf : kfs) poses.push_back(kf.pose);
  metaview_.reposition(poses);  // one block per keyframe: both are the integrated stops
  // The OctoMap cannot be moved (no voxel-exact rigid motion of an octree,
  // and clamped log-odds cannot be taken out again): a new one from the depth
  // images at the corrected poses, a restart if a rebuild was under way.
  octomap_rebuild_.emplace(params_.octomap);
  octomap_rebuild_next_ = 0;
  if (!reports_.empty())
    octomap_rebuild_->setStartBoxFree(mrpt::poses::CPose3D(reports_.front().pose));
  advanceOctomapRebuild(octomap_keyframes == 0 ? kfs.size() : octomap_keyframes);
  return 1e3 * tic.Tac();
}

std::size_t SlamIcp::advanceOctomapRebuild(std::size_t n)
{
  if (!octomap_rebuild_) return 0;
  const auto& kfs = loop_.keyframes();
  const std::size_t end = std::min({kfs.size(), simplemap_.size(), octomap_rebuild_next_ + n});
  const std::size_t begin = octomap_rebuild_next_;
  for (; octomap_rebuild_next_ < end; octomap_rebuild_next_++)
  {
    mrpt::poses::CPose3DPDF::Ptr pdf;
    mrpt::obs::CSensoryFrame::Ptr sf;
    simplemap_.get(octomap_rebuild_next_, pdf, sf);
    const mrpt::poses::CPose3D T(kfs[octomap_rebuild_next_].pose);
    for (const auto& s : depthScansOf(*sf))  // the depth images, not the tools cloud
      octomap_rebuild_->insertScan(*s, T);
  }
  if (octomap_rebuild_next_ >= std::min(kfs.size(), simplemap_.size()))
  {
    octomap_ = std::move(*octomap_rebuild_);
    octomap_rebuild_.reset();
    octomap_rebuild_next_ = 0;
  }
  return end - begin;
}

std::size_t SlamIcp::octomapRebuildPending() const
{
  if (!octomap_rebuild_) return 0;
  return std::min(loop_.keyframes().size(), simplemap_.size()) - octomap_rebuild_next_;
}

double SlamIcp::finishMapRebuild()
{
  mrpt::system::CTicTac tic;
  advanceOctomapRebuild(octomapRebuildPending());
  return 1e3 * tic.Tac();
}

}  // namespace voxplore::mapping
