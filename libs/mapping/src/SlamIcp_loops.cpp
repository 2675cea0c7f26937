// SlamIcp and loop closure: keyframes into the pose graph, corrected poses
// after a relaxation, and the metaview and OctoMap rebuilt from the keyframes.
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/mapping/SlamIcp.h>

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
    rep.loop.t_rebuild_ms = rebuildMaps();
    rep.loop.rebuilt = true;
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

double SlamIcp::rebuildMaps()
{
  mrpt::system::CTicTac tic;
  const auto& kfs = loop_.keyframes();
  Metaview metaview(params_.metaview);
  for (const auto& kf : kfs) metaview.insert(kf.cloud, kf.pose);
  OctoMapLayer octomap(params_.octomap);
  if (!reports_.empty()) octomap.setStartBoxFree(mrpt::poses::CPose3D(reports_.front().pose));
  for (std::size_t i = 0; i < kfs.size() && i < simplemap_.size(); i++)
  {
    mrpt::poses::CPose3DPDF::Ptr pdf;
    mrpt::obs::CSensoryFrame::Ptr sf;
    simplemap_.get(i, pdf, sf);
    const mrpt::poses::CPose3D T(kfs[i].pose);
    for (const auto& s : depthScansOf(*sf))  // the depth images, not the tools cloud
      octomap.insertScan(*s, T);
  }
  metaview_ = std::move(metaview);
  octomap_ = std::move(octomap);
  return 1e3 * tic.Tac();
}

}  // namespace voxplore::mapping
