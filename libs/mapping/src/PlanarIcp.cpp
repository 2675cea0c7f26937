#include <mrpt/math/wrap2pi.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/slam/CICP.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/PlanarIcp.h>

#include "point_to_line.h"

#include <Eigen/Eigenvalues>
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
  MRPT_LOAD_CONFIG_VAR(max_correction_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_correction_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(degeneracy_check, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(degeneracy_ratio, double, c, s);
  MRPT_LOAD_CONFIG_VAR(normal_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_points, int, c, s);
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
  requireValid(max_correction_xy_m > 0, c, s, "max_correction_xy_m", "must be positive");
  requireValid(max_correction_yaw > 0, c, s, "max_correction_yaw", "must be positive");
  requireValid(degeneracy_ratio >= 0 && degeneracy_ratio < 1, c, s, "degeneracy_ratio",
               "must be in [0, 1)");
  requireValid(normal_radius_m > 0, c, s, "normal_radius_m", "must be positive");
  requireValid(min_points >= 3, c, s, "min_points", "must be >= 3");
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
  MRPT_SAVE_CONFIG_VAR(max_correction_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_correction_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(degeneracy_check, c, s);
  MRPT_SAVE_CONFIG_VAR(degeneracy_ratio, c, s);
  MRPT_SAVE_CONFIG_VAR(normal_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_points, c, s);
}


IcpResult alignPlanar(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const CPose2D& predicted, const IcpParams& p)
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
  CPose2D coarse = predicted;
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
    coarse = icp.Align(&reference_map, &cloud_robot, predicted, info)->getMeanVal();
    r.iterations = info.nIterations;
    radius = icp.options.smallestThresholdDist;
  }
  // Stage 2: point-to-line refinement (ours), radius annealed to d_max_final_m.
  const auto fine = detail::refinePointToLine(reference_map, cloud_robot, coarse, radius, p);
  r.icp_pose = fine.pose;
  r.iterations += fine.iterations;
  r.goodness = fine.used ? double(fine.pairs) / double(fine.used) : 0.0;
  r.rms_m = fine.rms_m;
  r.pairs = fine.pairs;
  r.info_ratio = fine.info_ratio;
  r.degenerate = fine.degenerate;
  r.degenerate_dir = fine.degenerate_dir;

  CPose2D sol = fine.pose;
  if (r.degenerate)
  {
    // Keep the odometry prediction along the unconstrained direction v:
    // t = t_pred + (I - v v^T) (t_icp - t_pred).
    const Eigen::Vector2d dt(sol.x() - predicted.x(), sol.y() - predicted.y());
    const Eigen::Vector2d keep = dt - r.degenerate_dir * r.degenerate_dir.dot(dt);
    sol = CPose2D(predicted.x() + keep.x(), predicted.y() + keep.y(), sol.phi());
  }
  const double dxy = std::hypot(sol.x() - predicted.x(), sol.y() - predicted.y());
  const double dyaw = std::abs(mrpt::math::wrapToPi(sol.phi() - predicted.phi()));
  std::ostringstream why;
  if (r.goodness < p.min_goodness)
    why << "goodness " << r.goodness << " < " << p.min_goodness;
  else if (dxy > p.max_correction_xy_m)
    why << "correction " << dxy << " m > " << p.max_correction_xy_m << " m";
  else if (dyaw > p.max_correction_yaw)
    why << "correction " << mrpt::RAD2DEG(dyaw) << " deg > " << mrpt::RAD2DEG(p.max_correction_yaw)
        << " deg";
  r.reason = why.str();
  r.accepted = r.reason.empty();
  if (r.accepted)
  {
    r.pose = sol;
    if (r.degenerate) r.reason = "degenerate: odometry kept along one direction";
  }
  return r;
}

}  // namespace voxplore::mapping
