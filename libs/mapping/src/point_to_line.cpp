// Point-to-line planar ICP refinement. Our own code because MRPT's CICP is
// point-to-point only and converges slowly on sampled surfaces (measured:
// see PlanarIcp.h); the normals also give the information matrix used to
// detect degenerate (corridor) directions.
#include "point_to_line.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

namespace voxplore::mapping::detail
{
namespace
{
// A neighbourhood is a line when the variance across is below this share of
// the variance along. A wall seen with 1.5-2.5 cm range noise over a 0.25 m
// radius gives about 0.03; a table leg (a few cm of arc) is above 1.
constexpr double kLineRatio = 0.05;
// Over the small radius the same noise is a larger share of the spread along
// (about 0.1 over 0.1 m); a corner's two arms still give about 1.
constexpr double kSmallLineRatio = 0.2;
}  // namespace

LocalLine LineNormals::fit(std::size_t idx, double radius_m, double max_ratio) const
{
  const auto& xs = ref_.getPointsBufferRef_x();
  const auto& ys = ref_.getPointsBufferRef_y();
  std::vector<nanoflann::ResultItem<size_t, float>> nn;
  ref_.kdTreeRadiusSearch2D(xs[idx], ys[idx], static_cast<float>(radius_m * radius_m), nn);
  LocalLine line;
  if (nn.size() < 5) return line;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& n : nn) mean += Eigen::Vector2d(xs[n.first], ys[n.first]);
  mean /= double(nn.size());
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (const auto& n : nn)
  {
    const Eigen::Vector2d d = Eigen::Vector2d(xs[n.first], ys[n.first]) - mean;
    C += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
  // Line-like: the spread across is well below the spread along.
  line.valid = es.eigenvalues()(0) < max_ratio * es.eigenvalues()(1);
  line.normal = es.eigenvectors().col(0);
  line.centroid = mean;
  return line;
}

const LocalLine& LineNormals::lineAt(std::size_t idx)
{
  auto it = cache_.find(idx);
  if (it != cache_.end()) return it->second;
  LocalLine line = fit(idx, radius_m_, kLineRatio);
  // Not a line at radius_m_: a corner, or both faces of a wall (0.15 m
  // apart in the generated buildings). Fitted again over a radius below the
  // wall thickness, so that a face keeps its own line (and the same-side
  // test can tell the faces apart) instead of becoming point-to-point pairs
  // that slide onto the other face.
  if (!line.valid && small_radius_m_ > 0) line = fit(idx, small_radius_m_, kSmallLineRatio);
  return cache_.emplace(idx, line).first->second;
}

namespace
{
struct Accum
{
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // weighted
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();  // unweighted J^T J
  std::size_t pairs = 0;  // points with a reference point within the radius, in H
  std::size_t near = 0;   // ... and those refused for being seen from the other side
  double sum_r2 = 0;
};

Accum linearise(
    const mrpt::maps::CPointsMap& ref, const mrpt::maps::CPointsMap& cloud, const mrpt::poses::CPose2D& T,
    double radius, std::size_t stride, double huber, double point_weight, LineNormals& normals,
    const Viewpoints* views)
{
  Accum a;
  const auto& xs = cloud.getPointsBufferRef_x();
  const auto& ys = cloud.getPointsBufferRef_y();
  const auto& rx = ref.getPointsBufferRef_x();
  const auto& ry = ref.getPointsBufferRef_y();
  const double c = std::cos(T.phi()), s = std::sin(T.phi());
  const float r2max = static_cast<float>(radius * radius);
  for (std::size_t i = 0; i < xs.size(); i += stride)
  {
    const double px = T.x() + c * xs[i] - s * ys[i], py = T.y() + s * xs[i] + c * ys[i];
    float d2;
    const std::size_t m = ref.kdTreeClosestPoint2D(static_cast<float>(px), static_cast<float>(py), d2);
    if (d2 > r2max) continue;
    a.near++;
    const LocalLine& line = normals.lineAt(m);
    // d p / d yaw = R' q
    const double dpx = -s * xs[i] - c * ys[i], dpy = c * xs[i] - s * ys[i];
    if (line.valid)
    {
      // Point-to-line residual against the local wall/surface line fit.
      const Eigen::Vector2d& n = line.normal;
      if (views)
      {
        // Seen from opposite sides of the line (the two faces of a wall,
        // a wall thickness apart): not the same surface.
        const Eigen::Vector2f& v = (*views)[m];
        const double side_ref = n.x() * (v.x() - line.centroid.x()) + n.y() * (v.y() - line.centroid.y());
        const double side_cur = n.x() * (T.x() - px) + n.y() * (T.y() - py);
        if (side_ref * side_cur < 0) continue;
      }
      const double r = n.x() * (px - line.centroid.x()) + n.y() * (py - line.centroid.y());
      const Eigen::Vector3d J(n.x(), n.y(), n.x() * dpx + n.y() * dpy);
      const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
      a.H += w * J * J.transpose();
      a.b += w * J * r;
      a.info += J * J.transpose();
      a.sum_r2 += r * r;
    }
    else
    {
      // Not line-like (a table leg, a corner): point-to-point, two residuals.
      // Seen from opposite directions it is not the same surface either: a
      // wall's end seen from its far side pulled a cloud onto the other face
      // (willowgarage, compact robot: a 0.68 m step with odometry 6 mm off
      // registered 11 cm off against the true map).
      if (views)
      {
        const Eigen::Vector2f& v = (*views)[m];
        if ((v.x() - rx[m]) * (T.x() - px) + (v.y() - ry[m]) * (T.y() - py) < 0) continue;
      }
      const Eigen::Vector2d r(px - rx[m], py - ry[m]);
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, dpx, 0, 1, dpy;
      const double rn = r.norm();
      const double w = point_weight * (rn <= huber ? 1.0 : huber / rn);
      a.H += w * J.transpose() * J;
      a.b += w * J.transpose() * r;
      a.info += J.transpose() * J;
      a.sum_r2 += r.squaredNorm();
    }
    a.pairs++;
  }
  return a;
}
}  // namespace

RefineResult refinePointToLine(
    const mrpt::maps::CPointsMap& ref, const mrpt::maps::CPointsMap& cloud,
    const mrpt::poses::CPose2D& start, double radius_start_m, const IcpParams& p,
    const mrpt::poses::CPose2D& prior, const Viewpoints* viewpoints, double prior_std_m)
{
  if (viewpoints && viewpoints->size() != ref.size())
    throw std::invalid_argument("refinePointToLine: " + std::to_string(viewpoints->size()) +
                                " viewpoints for " + std::to_string(ref.size()) + " reference points");
  RefineResult res;
  res.pose = start;
  LineNormals normals(ref, p.normal_radius_m, p.normal_radius_small_m);
  const std::size_t stride =
      std::max<std::size_t>(1, cloud.size() / static_cast<std::size_t>(std::max(1, p.max_points)));
  res.used = (cloud.size() + stride - 1) / stride;
  double radius = std::max(radius_start_m, p.d_max_final_m);
  Accum a;
  // A weak direction fused with a loose odometry prior converges slowly:
  // the pairs re-associate a few mm per iteration along it. Such a
  // registration gets 3 x max_iterations (a compact-robot stop whose
  // odometry was 0.25 m off along a corridor crept 16 cm in 30 iterations,
  // was refused as not converged and kept its odometry; with 58 it landed
  // 1.4 cm from the truth).
  int max_iterations = p.max_iterations;
  for (int it = 0; it < max_iterations; it++)
  {
    a = linearise(ref, cloud, res.pose, radius, stride, p.huber_m, p.point_weight, normals, viewpoints);
    res.iterations++;
    if (a.pairs < 3) break;
    // Degenerate translation directions get no update (solution remapping).
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(a.info.topLeftCorner<2, 2>());
    const double lmax = es.eigenvalues()(1);
    res.info_ratio = lmax > 0 ? es.eigenvalues()(0) / lmax : 0.0;
    res.degenerate = p.degeneracy_check && res.info_ratio < p.degeneracy_ratio;
    res.degenerate_dir = es.eigenvectors().col(0);
    Eigen::Matrix3d H = a.H;
    if (p.odometry_prior_pairs > 0)
    {
      // The prediction's translation as a prior: residual t - t_prior, J = I.
      H(0, 0) += p.odometry_prior_pairs;
      H(1, 1) += p.odometry_prior_pairs;
      a.b.x() += p.odometry_prior_pairs * (res.pose.x() - prior.x());
      a.b.y() += p.odometry_prior_pairs * (res.pose.y() - prior.y());
    }
    const bool fuse = res.degenerate && prior_std_m > 0;
    if (fuse)
    {
      max_iterations = p.max_iterations * 3;
      // The odometry prediction along the weak direction v as a prior of
      // std prior_std_m, in pair units: residual v.(t - t_prior), weight
      // (pair_std_m / prior_std_m)^2.
      const Eigen::Vector2d v = res.degenerate_dir;
      const double k = std::pow(p.pair_std_m / prior_std_m, 2);
      const double r = v.x() * (res.pose.x() - prior.x()) + v.y() * (res.pose.y() - prior.y());
      H.topLeftCorner<2, 2>() += k * v * v.transpose();
      a.b.head<2>() += k * r * v;
    }
    H.diagonal().array() += 1e-9 * (H.trace() + 1.0);
    Eigen::Vector3d delta = -H.ldlt().solve(a.b);
    if (res.degenerate && !fuse)
    {
      const Eigen::Vector2d v = res.degenerate_dir;
      delta.head<2>() -= v * v.dot(delta.head<2>());
    }
    res.pose = mrpt::poses::CPose2D(res.pose.x() + delta.x(), res.pose.y() + delta.y(),
                                    res.pose.phi() + delta.z());
    res.last_step_m = delta.head<2>().norm();
    res.last_step_rad = std::abs(delta.z());
    const bool converged = delta.head<2>().norm() < 2e-4 && std::abs(delta.z()) < 5e-5;
    if (converged)
    {
      if (radius <= p.d_max_final_m)
      {
        res.converged = true;
        break;
      }
      radius = std::max(p.d_max_final_m, radius * p.alfa);
    }
  }
  a = linearise(ref, cloud, res.pose, p.d_max_final_m, stride, p.huber_m, p.point_weight, normals, viewpoints);
  res.information = a.info;
  res.pairs = a.pairs;
  res.near = a.near;
  res.rms_m = a.pairs ? std::sqrt(a.sum_r2 / double(a.pairs)) : 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(a.info.topLeftCorner<2, 2>());
  const double lmax = es.eigenvalues()(1);
  res.info_ratio = lmax > 0 ? es.eigenvalues()(0) / lmax : 0.0;
  res.degenerate = p.degeneracy_check && res.info_ratio < p.degeneracy_ratio;
  res.degenerate_dir = es.eigenvectors().col(0);
  return res;
}

}  // namespace voxplore::mapping::detail
