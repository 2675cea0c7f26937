#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/slam/CICP.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/PlanarIcp.h>

#include "point_to_line.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <optional>
#include <vector>
#include <cmath>
#include <sstream>

namespace voxplore::mapping
{
using mrpt::poses::CPose2D;

void IcpParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(d_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(d_max_final_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(alfa, double, c, s);
  MRPT_LOAD_CONFIG_VAR(coarse_iterations, int, c, s);
  MRPT_LOAD_CONFIG_VAR(decimation, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_iterations, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_points, int, c, s);
  MRPT_LOAD_CONFIG_VAR(huber_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(point_weight, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_overlap_min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_correction_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_correction_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(correction_gate_sigmas, double, c, s);
  MRPT_LOAD_CONFIG_VAR(hold_sigmas, double, c, s);
  MRPT_LOAD_CONFIG_VAR(hold_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(hold_sure_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(keep_fitting_prediction, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(keep_low_overlap_max_std_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_large_corrections, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(confirm_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(large_correction_min_points, int, c, s);
  MRPT_LOAD_CONFIG_VAR(degeneracy_check, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(degeneracy_ratio, double, c, s);
  MRPT_LOAD_CONFIG_VAR(degenerate_fusion, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_std_xy_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_std_xy_per_rad, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_std_xy_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pair_std_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(multi_start_min_std_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(multi_start_scale, double, c, s);
  MRPT_LOAD_CONFIG_VAR(multi_start_margin, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_prior_pairs, double, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_prior_step_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(same_side_only, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_radius_small_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_points, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_unconverged_step_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(relocalize, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(relocalize_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(relocalize_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(relocalize_min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(relocalize_margin, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_length_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_z_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_z_max_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(body_max_voxels, int, c, s);
  MRPT_LOAD_CONFIG_VAR(body_relocalize_min_goodness, double, c, s);
  using common::requireValid;
  requireValid(d_max_m > 0, c, s, "d_max_m", "must be positive");
  requireValid(d_max_final_m > 0 && d_max_final_m <= d_max_m, c, s, "d_max_final_m",
               "need 0 < d_max_final_m <= d_max_m");
  requireValid(alfa > 0 && alfa < 1, c, s, "alfa", "must be in (0, 1)");
  requireValid(coarse_iterations >= 0, c, s, "coarse_iterations", "must be >= 0");
  requireValid(max_iterations > 0, c, s, "max_iterations", "must be positive");
  requireValid(max_points >= 10, c, s, "max_points", "must be >= 10");
  requireValid(huber_m > 0, c, s, "huber_m", "must be positive");
  requireValid(point_weight >= 0 && point_weight <= 1, c, s, "point_weight", "must be in [0, 1]");
  requireValid(decimation >= 1, c, s, "decimation", "must be >= 1");
  requireValid(min_goodness >= 0 && min_goodness <= 1, c, s, "min_goodness", "must be in [0, 1]");
  requireValid(low_overlap_min_goodness >= 0 && low_overlap_min_goodness <= 1, c, s,
               "low_overlap_min_goodness", "must be in [0, 1]");
  requireValid(max_correction_xy_m > 0, c, s, "max_correction_xy_m", "must be positive");
  requireValid(correction_gate_sigmas >= 0, c, s, "correction_gate_sigmas", "must be >= 0");
  requireValid(hold_sigmas >= 0, c, s, "hold_sigmas", "must be >= 0 (0 = off)");
  requireValid(hold_min_m >= 0, c, s, "hold_min_m", "must be >= 0");
  requireValid(keep_low_overlap_max_std_m >= 0, c, s, "keep_low_overlap_max_std_m", "must be >= 0");
  requireValid(hold_sure_goodness >= 0 && hold_sure_goodness <= 1, c, s, "hold_sure_goodness",
               "must be in [0, 1]");
  requireValid(max_correction_yaw > 0, c, s, "max_correction_yaw", "must be positive");
  requireValid(confirm_xy_m > 0, c, s, "confirm_xy_m", "must be positive");
  requireValid(confirm_yaw > 0, c, s, "confirm_yaw", "must be positive");
  requireValid(confirm_min_goodness >= 0 && confirm_min_goodness <= 1, c, s, "confirm_min_goodness",
               "must be in [0, 1]");
  requireValid(large_correction_min_points >= 0, c, s, "large_correction_min_points", "must be >= 0");
  requireValid(odometry_prior_pairs >= 0, c, s, "odometry_prior_pairs", "must be >= 0");
  requireValid(odometry_prior_step_m > 0, c, s, "odometry_prior_step_m", "must be > 0");
  requireValid(degeneracy_ratio >= 0 && degeneracy_ratio < 1, c, s, "degeneracy_ratio",
               "must be in [0, 1)");
  requireValid(odometry_std_xy_per_m >= 0, c, s, "odometry_std_xy_per_m", "must be >= 0");
  requireValid(odometry_std_xy_per_rad >= 0, c, s, "odometry_std_xy_per_rad", "must be >= 0");
  requireValid(odometry_std_xy_min_m > 0, c, s, "odometry_std_xy_min_m", "must be positive");
  requireValid(pair_std_m > 0, c, s, "pair_std_m", "must be positive");
  requireValid(multi_start_min_std_m >= 0, c, s, "multi_start_min_std_m", "must be >= 0 m (0 = off)");
  requireValid(multi_start_scale > 0 && multi_start_scale <= 10, c, s, "multi_start_scale",
               "must be in (0, 10] stds");
  requireValid(multi_start_margin >= 0 && multi_start_margin < 1, c, s, "multi_start_margin",
               "must be in [0, 1)");
  requireValid(normal_radius_m > 0, c, s, "normal_radius_m", "must be positive");
  requireValid(normal_radius_small_m >= 0 && normal_radius_small_m < normal_radius_m, c, s,
               "normal_radius_small_m", "must be in [0, normal_radius_m)");
  requireValid(min_points >= 3, c, s, "min_points", "must be >= 3");
  requireValid(max_unconverged_step_m >= 0, c, s, "max_unconverged_step_m", "must be >= 0");
  requireValid(relocalize_radius_m >= 0 && relocalize_radius_m <= 10, c, s, "relocalize_radius_m",
               "must be in [0, 10] m");
  requireValid(relocalize_yaw >= 0 && relocalize_yaw <= M_PI, c, s, "relocalize_yaw",
               "must be in [0, 180] deg");
  requireValid(relocalize_min_goodness > 0 && relocalize_min_goodness <= 1, c, s,
               "relocalize_min_goodness", "must be in (0, 1]");
  requireValid(relocalize_margin >= 0 && relocalize_margin < 1, c, s, "relocalize_margin",
               "must be in [0, 1)");
  requireValid(body_length_m >= 0 && body_width_m >= 0, c, s, "body_length_m",
               "body_length_m and body_width_m must be >= 0 (0 = no body check)");
  requireValid(body_margin_m >= 0, c, s, "body_margin_m", "must be >= 0");
  requireValid(body_z_max_m > body_z_min_m, c, s, "body_z_max_m", "must be above body_z_min_m");
  requireValid(body_max_voxels >= 0, c, s, "body_max_voxels", "must be >= 0");
  requireValid(body_relocalize_min_goodness > 0 && body_relocalize_min_goodness <= 1, c, s,
               "body_relocalize_min_goodness", "must be in (0, 1]");
}

void IcpParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(d_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(d_max_final_m, c, s);
  MRPT_SAVE_CONFIG_VAR(alfa, c, s);
  MRPT_SAVE_CONFIG_VAR(coarse_iterations, c, s);
  MRPT_SAVE_CONFIG_VAR(decimation, c, s);
  MRPT_SAVE_CONFIG_VAR(max_iterations, c, s);
  MRPT_SAVE_CONFIG_VAR(max_points, c, s);
  MRPT_SAVE_CONFIG_VAR(huber_m, c, s);
  MRPT_SAVE_CONFIG_VAR(point_weight, c, s);
  MRPT_SAVE_CONFIG_VAR(min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(low_overlap_min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(max_correction_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_correction_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(correction_gate_sigmas, c, s);
  MRPT_SAVE_CONFIG_VAR(hold_sigmas, c, s);
  MRPT_SAVE_CONFIG_VAR(hold_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(hold_sure_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(keep_fitting_prediction, c, s);
  MRPT_SAVE_CONFIG_VAR(keep_low_overlap_max_std_m, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_large_corrections, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(confirm_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(large_correction_min_points, c, s);
  MRPT_SAVE_CONFIG_VAR(degeneracy_check, c, s);
  MRPT_SAVE_CONFIG_VAR(degeneracy_ratio, c, s);
  MRPT_SAVE_CONFIG_VAR(degenerate_fusion, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_std_xy_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_std_xy_per_rad, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_std_xy_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(pair_std_m, c, s);
  MRPT_SAVE_CONFIG_VAR(multi_start_min_std_m, c, s);
  MRPT_SAVE_CONFIG_VAR(multi_start_scale, c, s);
  MRPT_SAVE_CONFIG_VAR(multi_start_margin, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_prior_pairs, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_prior_step_m, c, s);
  MRPT_SAVE_CONFIG_VAR(same_side_only, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_radius_small_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_points, c, s);
  MRPT_SAVE_CONFIG_VAR(max_unconverged_step_m, c, s);
  MRPT_SAVE_CONFIG_VAR(relocalize, c, s);
  MRPT_SAVE_CONFIG_VAR(relocalize_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(relocalize_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(relocalize_min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(relocalize_margin, c, s);
  MRPT_SAVE_CONFIG_VAR(body_length_m, c, s);
  MRPT_SAVE_CONFIG_VAR(body_width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(body_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(body_z_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(body_z_max_m, c, s);
  MRPT_SAVE_CONFIG_VAR(body_max_voxels, c, s);
  MRPT_SAVE_CONFIG_VAR(body_relocalize_min_goodness, c, s);
}


namespace
{
/// IcpParams::low_overlap_min_goodness: a registration that paired little
/// of its cloud but agrees with the odometry of its step.
bool lowOverlapAgrees(const IcpResult& r, double dxy, double dyaw, const IcpParams& p, double odometry_std_m)
{
  return p.low_overlap_min_goodness > 0 && r.goodness >= p.low_overlap_min_goodness && r.converged &&
         !r.degenerate && dxy <= std::max(0.02, 2.0 * odometry_std_m) && dyaw <= mrpt::DEG2RAD(2.0);
}
}  // namespace

IcpResult alignPlanar(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const CPose2D& predicted, const IcpParams& p, const Viewpoints* reference_viewpoints,
    double odometry_std_m, const CPose2D* start, double gate_xy_m)
{
  IcpResult r;
  r.pose = predicted;
  r.icp_pose = predicted;
  if (!p.enabled)
  {
    r.reason = "icp disabled";
    return r;
  }
  if (cloud_robot.size() < static_cast<std::size_t>(p.min_points) ||
      reference_map.size() < static_cast<std::size_t>(p.min_points))
  {
    r.reason = "too few points (cloud " + std::to_string(cloud_robot.size()) + ", metaview " +
               std::to_string(reference_map.size()) + ")";
    return r;
  }
  // Stage 1: MRPT's point-to-point ICP, a few iterations, wide radius.
  CPose2D coarse = start ? *start : predicted;
  double radius = p.d_max_m;
  if (p.coarse_iterations > 0)
  {
    mrpt::slam::CICP icp;
    icp.options.ICP_algorithm = mrpt::slam::icpClassic;
    icp.options.maxIterations = static_cast<unsigned>(p.coarse_iterations);
    icp.options.thresholdDist = p.d_max_m;
    icp.options.thresholdAng = 0;
    icp.options.ALFA = p.alfa;
    icp.options.smallestThresholdDist = std::max(p.d_max_final_m, 0.25 * p.d_max_m);
    icp.options.onlyUniqueRobust = false;
    icp.options.doRANSAC = false;
    icp.options.corresponding_points_decimation = static_cast<uint32_t>(p.decimation);
    icp.options.skip_cov_calculation = true;
    icp.options.skip_quality_calculation = true;
    mrpt::slam::CICP::TReturnInfo info;
    coarse = icp.Align(&reference_map, &cloud_robot, coarse, info)->getMeanVal();
    r.iterations = info.nIterations;
    radius = icp.options.smallestThresholdDist;
  }
  // Stage 2: point-to-line refinement (ours), radius annealed to d_max_final_m.
  const double prior_std_m = p.degenerate_fusion ? odometry_std_m : 0.0;
  const auto fine = detail::refinePointToLine(reference_map, cloud_robot, coarse, radius, p, predicted,
                                              p.same_side_only ? reference_viewpoints : nullptr,
                                              prior_std_m);
  r.icp_pose = fine.pose;
  r.iterations += fine.iterations;
  r.converged = fine.converged;
  r.last_step_m = std::max(fine.last_step_m, fine.last_step_rad * 1.0 /* m */);
  // A point refused only for the side of its line still lies on the map
  // (the thesis' goodness): a door jamb's normal beside a wall's end took
  // 9 % of a stop's points and rejected the omniRob's first turn.
  r.goodness = fine.used ? double(fine.near) / double(fine.used) : 0.0;
  r.paired_share = fine.used ? double(fine.pairs) / double(fine.used) : 0.0;
  r.rms_m = fine.rms_m;
  r.pairs = fine.pairs;
  r.info_ratio = fine.info_ratio;
  r.information = fine.information;
  r.degenerate = fine.degenerate;
  r.degenerate_dir = fine.degenerate_dir;

  CPose2D sol = fine.pose;
  const bool fused = r.degenerate && prior_std_m > 0;
  if (r.degenerate && !fused)
  {
    // Keep the odometry prediction along the unconstrained direction v:
    // t = t_pred + (I - v v^T) (t_icp - t_pred).
    const Eigen::Vector2d dt(sol.x() - predicted.x(), sol.y() - predicted.y());
    const Eigen::Vector2d keep = dt - r.degenerate_dir * r.degenerate_dir.dot(dt);
    sol = CPose2D(predicted.x() + keep.x(), predicted.y() + keep.y(), sol.phi());
  }
  const double dxy = std::hypot(sol.x() - predicted.x(), sol.y() - predicted.y());
  const double dyaw = std::abs(mrpt::math::wrapToPi(sol.phi() - predicted.phi()));
  // Beyond max_correction_xy_m only a good, fully constrained registration passes the gate.
  const bool big_cloud = p.largeCorrectionAllowed(cloud_robot.size());
  const bool gateable = r.goodness >= p.confirm_min_goodness && !r.degenerate && big_cloud;
  std::ostringstream why;
  if (!std::isfinite(sol.x()) || !std::isfinite(sol.y()) || !std::isfinite(sol.phi()))
    why << "non-finite solution";
  else if (!r.converged && r.last_step_m > p.max_unconverged_step_m)
    why << "did not converge in " << r.iterations << " iterations (last step " << r.last_step_m
        << " m > max_unconverged_step_m = " << p.max_unconverged_step_m << " m)";
  else if (r.goodness < p.min_goodness && !lowOverlapAgrees(r, dxy, dyaw, p, odometry_std_m))
    why << "goodness " << r.goodness << " < " << p.min_goodness;
  else if (dxy > p.max_correction_xy_m && !(dxy <= gate_xy_m && gateable))
  {
    why << "correction " << dxy << " m > " << p.max_correction_xy_m << " m";
    if (dxy <= gate_xy_m)
      why << " (within the gate of " << gate_xy_m << " m, but "
          << (r.degenerate ? std::string("degenerate")
              : !big_cloud ? "a cloud of " + std::to_string(cloud_robot.size()) + " points < " +
                                 std::to_string(p.large_correction_min_points)
                           : "goodness " + std::to_string(r.goodness))
          << ")";
    r.over_correction_limit = true;
  }
  else if (dyaw > p.max_correction_yaw)
  {
    why << "correction " << mrpt::RAD2DEG(dyaw) << " deg > " << mrpt::RAD2DEG(p.max_correction_yaw)
        << " deg";
    r.over_correction_limit = true;
  }
  r.reason = why.str();
  r.accepted = r.reason.empty();
  if (r.accepted)
  {
    r.pose = sol;
    if (r.goodness < p.min_goodness)
    {
      std::ostringstream low;
      low << "low overlap: goodness " << r.goodness << " < " << p.min_goodness << ", taken as it agrees with odometry ("
          << dxy << " m, " << mrpt::RAD2DEG(dyaw) << " deg)";
      r.reason = low.str();
    }
    if (fused)
      r.reason = "degenerate: odometry fused along one direction";
    else if (r.degenerate)
      r.reason = "degenerate: odometry kept along one direction";
    if (dxy > p.max_correction_xy_m)
    {
      std::ostringstream gate;
      gate << "correction " << dxy << " m beyond " << p.max_correction_xy_m << " m, within the gate of "
           << gate_xy_m << " m (correction_gate_sigmas odometry stds since the last registered stop)";
      r.reason = r.reason.empty() ? gate.str() : r.reason + "; " + gate.str();
    }
  }
  return r;
}

IcpResult alignPlanarMultiStart(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const CPose2D& predicted, const IcpParams& p, const Viewpoints* reference_viewpoints,
    double odometry_std_m, double gate_xy_m)
{
  IcpResult best =
      alignPlanar(reference_map, cloud_robot, predicted, p, reference_viewpoints, odometry_std_m, nullptr, gate_xy_m);
  if (p.multi_start_min_std_m <= 0 || odometry_std_m < p.multi_start_min_std_m || !best.accepted ||
      best.degenerate)
    return best;
  const double d = p.multi_start_scale * odometry_std_m;
  const double bar = best.paired_share + p.multi_start_margin;
  const std::array<std::array<double, 2>, 4> offsets{{{d, 0}, {-d, 0}, {0, d}, {0, -d}}};
  std::optional<IcpResult> winner;
  for (unsigned k = 0; k < offsets.size(); k++)
  {
    const CPose2D s(predicted.x() + offsets[k][0], predicted.y() + offsets[k][1], predicted.phi());
    IcpResult r = alignPlanar(reference_map, cloud_robot, predicted, p, reference_viewpoints,
                              odometry_std_m, &s, gate_xy_m);
    if (!r.accepted || r.degenerate || r.paired_share <= bar) continue;
    if (!winner || r.paired_share > winner->paired_share)
    {
      r.start = k + 1;
      winner = std::move(r);
    }
  }
  IcpResult out = winner ? std::move(*winner) : std::move(best);
  out.starts_tried = 1 + static_cast<unsigned>(offsets.size());
  if (out.start > 0)
  {
    std::ostringstream why;
    why << "start " << out.start << " of " << out.starts_tried << " (" << d << " m off the prediction)";
    out.reason = out.reason.empty() ? why.str() : out.reason + "; " + why.str();
  }
  return out;
}

double goodnessAt(const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
                  const CPose2D& pose, const IcpParams& p, const Viewpoints* reference_viewpoints)
{
  // No iteration: the refinement's final pairing at d_max_final_m only.
  IcpParams q = p;
  q.max_iterations = 0;
  const auto at = detail::refinePointToLine(reference_map, cloud_robot, pose, p.d_max_final_m, q, pose,
                                            p.same_side_only ? reference_viewpoints : nullptr);
  return at.used ? double(at.near) / double(at.used) : 0.0;
}

double odometryStdXy(const CPose2D& step, const IcpParams& p)
{
  return std::max(p.odometry_std_xy_min_m, p.odometry_std_xy_per_m * std::hypot(step.x(), step.y()) +
                                               p.odometry_std_xy_per_rad * std::abs(step.phi()));
}

}  // namespace voxplore::mapping
