// SlamIcp exports: map.bt, map.simplemap, metaview.ply, trajectory_est.tum, stops.csv.
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <voxplore/common/trajectory_io.h>
#include <voxplore/mapping/SlamIcp.h>

#include <filesystem>
#include <fstream>
#include <iomanip>

namespace voxplore::mapping
{
void writeStopsCsv(const std::vector<StopReport>& reports, const std::string& path)
{
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write '" + path + "'");
  f << "stop,timestamp,odo_x,odo_y,odo_yaw_deg,pred_x,pred_y,pred_yaw_deg,x,y,yaw_deg,"
       "icp_accepted,flagged,integrated,relocalized,icp_goodness,icp_iterations,icp_converged,icp_last_step_m,"
       "icp_degenerate,icp_info_ratio,icp_reason,cameras_used,cameras_skipped,camera_issues,cloud_points,invalid_pixels,metaview_added,metaview_size,octomap_rays,"
       "loop_searched,loop_consistent,loop_candidate,loop_closed,loop_with_stop,loop_correction_m,"
       "loop_correction_yaw_deg,loop_goodness,graph_shift_max_m,graph_shift_mean_m,maps_rebuilt,"
       "t_cloud_ms,t_icp_ms,t_metaview_ms,t_octomap_ms,t_loop_detect_ms,t_loop_optimize_ms,"
       "t_loop_rebuild_ms,t_total_ms,octomap_rebuilt_keyframes,octomap_rebuild_left,"
       "t_octomap_rebuild_ms,icp_start,icp_starts_tried,icp_held,odometry_kept,loop_message\n";
  f << std::fixed;
  for (const auto& r : reports)
  {
    const auto clean = [](std::string t)
    {
      for (auto& ch : t)
        if (ch == ',' || ch == '"' || ch == '\n') ch = ';';
      return t;
    };
    const std::string reason = clean(r.icp.reason);
    std::string issues;
    std::size_t skipped = 0;
    for (const auto& i : r.camera_issues)
    {
      skipped += i.skipped;
      issues += (issues.empty() ? "" : " | ") + i.label + ": " + i.reason;
    }
    issues = clean(issues);
    f << r.index << "," << std::setprecision(6) << mrpt::Clock::toDouble(r.timestamp) << ","
      << std::setprecision(5) << r.odometry.x() << "," << r.odometry.y() << ","
      << mrpt::RAD2DEG(r.odometry.phi()) << "," << r.predicted.x() << "," << r.predicted.y()
      << "," << mrpt::RAD2DEG(r.predicted.phi()) << "," << r.pose.x() << "," << r.pose.y() << ","
      << mrpt::RAD2DEG(r.pose.phi()) << "," << r.icp.accepted << "," << r.flagged << ","
      << r.integrated << "," << r.relocalized << "," << std::setprecision(4) << r.icp.goodness << "," << r.icp.iterations
      << "," << r.icp.converged << "," << std::setprecision(6) << r.icp.last_step_m << ","
      << r.icp.degenerate << "," << std::setprecision(4) << r.icp.info_ratio << "," << reason
      << "," << r.cameras_used << "," << skipped << "," << issues << "," << r.cloud_points
      << "," << r.invalid_pixels << "," << r.metaview_added << "," << r.metaview_size << ","
      << r.octomap.rays << "," << r.loop.searched << "," << r.loop.consistent << ","
      << r.loop.candidate << "," << r.loop.closed << ","
      << ((r.loop.searched && (r.loop.consistent || r.loop.candidate)) || r.loop.closed
              ? std::to_string(r.loop.with_stop)
              : std::string())
      << "," << std::setprecision(4) << r.loop.correction_m << ","
      << mrpt::RAD2DEG(r.loop.correction_yaw) << "," << r.loop.goodness << ","
      << r.loop.graph_shift_max_m << "," << r.loop.graph_shift_mean_m << "," << r.loop.rebuilt
      << "," << std::setprecision(3) << r.t_cloud_ms << "," << r.t_icp_ms << ","
      << r.t_metaview_ms << "," << r.t_octomap_ms << "," << r.loop.t_detect_ms << ","
      << r.loop.t_optimize_ms << "," << r.loop.t_rebuild_ms << "," << r.t_total_ms << ","
      << r.octomap_rebuilt_keyframes << "," << r.octomap_rebuild_left << ","
      << r.t_octomap_rebuild_ms << "," << r.icp.start << "," << r.icp.starts_tried << ","
      << r.held << "," << r.odometry_kept << "," << clean(r.loop.message) << "\n";
  }
  if (!f) throw std::runtime_error("write failed: '" + path + "'");
}

void SlamIcp::saveOutputs(const std::string& dir)
{
  finishMapRebuild();  // the corrected OctoMap, not the one planning went on with
  namespace fs = std::filesystem;
  const auto p = [&](const char* name) { return (fs::path(dir) / name).string(); };

  octomap_.writeBinary(p("map.bt"));

  {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(p("map.simplemap"))) throw std::runtime_error("cannot write '" + p("map.simplemap") + "'");
    auto arch = mrpt::serialization::archiveFrom(out);
    arch << simplemap_;
  }

  if (!metaview_.points().saveToPlyFile(p("metaview.ply"), true))
    throw std::runtime_error("cannot write '" + p("metaview.ply") + "'");

  const auto writeTrajectory = [&](const char* name, mrpt::poses::CPose2D StopReport::*pose) {
    common::TumWriter tum(p(name));
    for (const auto& r : reports_)
      tum.write(mrpt::Clock::toDouble(r.timestamp), mrpt::poses::CPose3D(r.*pose));
  };
  writeTrajectory("trajectory_est.tum", &StopReport::pose);
  writeTrajectory("trajectory_online.tum", &StopReport::online_pose);
  writeStopsCsv(reports_, p("stops.csv"));
}

}  // namespace voxplore::mapping
