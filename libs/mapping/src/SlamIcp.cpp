#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/system/CTicTac.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/SlamIcp.h>

#include <stdexcept>

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;

void SlamIcpParams::load(const mrpt::config::CConfigFileBase& cfg)
{
  common::loadChecked(cloud, cfg, "cloud");
  common::loadChecked(metaview, cfg, "metaview");
  common::loadChecked(icp, cfg, "icp");
  common::loadChecked(octomap, cfg, "octomap");
}

void SlamIcpParams::save(mrpt::config::CConfigFileBase& cfg) const
{
  cloud.saveToConfigFile(cfg, "cloud");
  metaview.saveToConfigFile(cfg, "metaview");
  icp.saveToConfigFile(cfg, "icp");
  octomap.saveToConfigFile(cfg, "octomap");
}

SlamIcp::SlamIcp(const SlamIcpParams& params)
    : params_(params), metaview_(params.metaview), octomap_(params.octomap)
{
}

std::optional<CPose2D> SlamIcp::odometryOf(
    const mrpt::obs::CActionCollection* actions, const mrpt::obs::CSensoryFrame& sf)
{
  if (const auto odo = sf.getObservationByClass<mrpt::obs::CObservationOdometry>())
    return odo->odometry;
  if (actions)
  {
    if (const auto mv = actions->getBestMovementEstimation())
    {
      // Accumulate increments into a reading of our own (starts at 0, 0, 0).
      const CPose2D prev = action_odometry_ ? *action_odometry_ : CPose2D();
      action_odometry_ = prev + mv->rawOdometryIncrementReading;
      return action_odometry_;
    }
  }
  return std::nullopt;
}

StopReport SlamIcp::processStop(
    const mrpt::obs::CSensoryFrame& sf, const CPose2D& odometry, mrpt::Clock::time_point timestamp)
{
  mrpt::system::CTicTac total, tic;
  StopReport rep;
  rep.index = reports_.size();
  rep.timestamp = timestamp;
  rep.odometry = odometry;
  const auto scans = depthScansOf(sf);
  if (scans.empty())
    throw std::runtime_error("stop " + std::to_string(rep.index) +
                             ": the sensory frame holds no CObservation3DRangeScan with a range image");

  // 1. Prediction, thesis 4.4.1: the first pose is the origin (eq. 4.1, 4.2 after).
  rep.predicted = last_odometry_ ? predictPose(pose_, *last_odometry_, odometry) : CPose2D();
  last_odometry_ = odometry;

  // 2. Cloud Q in the robot frame, floor removed.
  tic.Tic();
  const RobotCloud cloud = buildRobotCloud(scans, params_.cloud);
  rep.t_cloud_ms = 1e3 * tic.Tac();
  rep.cloud_points = cloud.points.size();
  rep.invalid_pixels = cloud.invalid_pixels;

  // 3. Planar ICP against the metaview M (none for the first stop).
  rep.pose = rep.predicted;
  if (!metaview_.empty())
  {
    tic.Tic();
    rep.icp = alignPlanar(metaview_.footprint(), cloud.points, rep.predicted, params_.icp);
    rep.t_icp_ms = 1e3 * tic.Tac();
    rep.pose = rep.icp.pose;
    // Flagged: ICP ran and was rejected (or could not run). With ICP
    // disabled on purpose, odometry is the method and nothing is flagged.
    rep.flagged = params_.icp.enabled && !rep.icp.accepted;
  }
  else
  {
    rep.icp.reason = "first stop";
    rep.icp.pose = rep.pose;
  }
  pose_ = rep.pose;

  // 4. Metaview with point reduction. A rejected stop does not enter M: its
  //    pose is only as good as odometry.
  tic.Tic();
  if (!rep.flagged) rep.metaview_added = metaview_.insert(cloud.points, rep.pose);
  rep.metaview_size = metaview_.size();
  rep.t_metaview_ms = 1e3 * tic.Tac();

  // 5. OctoMap V, per camera, from each camera's origin.
  tic.Tic();
  const CPose3D T_map_robot(rep.pose);
  if (reports_.empty()) octomap_.setStartBoxFree(T_map_robot);
  if (!rep.flagged)
    for (const auto& s : scans)
    {
      const auto st = octomap_.insertScan(*s, T_map_robot);
      rep.octomap.rays += st.rays;
      rep.octomap.hits += st.hits;
      rep.octomap.invalid += st.invalid;
      rep.octomap.free_updates += st.free_updates;
      rep.octomap.occ_updates += st.occ_updates;
    }
  rep.t_octomap_ms = 1e3 * tic.Tac();

  // Keyframe for the .simplemap: every stop, with its sensory frame.
  simplemap_.insert(mrpt::poses::CPose3DPDFGaussian(T_map_robot), sf);
  rep.t_total_ms = 1e3 * total.Tac();
  reports_.push_back(rep);
  return rep;
}

}  // namespace voxplore::mapping
