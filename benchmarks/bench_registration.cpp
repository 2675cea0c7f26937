// voxplore-bench 'registration': the error of each stop's planar ICP alone,
// with the drift of the run taken out. Stop k is registered against a
// metaview of stops 0..k-1 placed at their ground-truth poses, from the
// prediction ground truth(k-1) + odometry increment, exactly as SlamIcp
// registers it (alignPlanar, relocalizePlanar after a rejection). The error
// against ground truth(k) is then the registration's own: a step that a
// replay shows as drift, a wall-thickness jump or a shortened corridor step
// shows here without the feedback of an already drifted map.
#include "bench_registration.h"

#include <mrpt/math/wrap2pi.h>
#include <voxplore/common/Progress.h>
#include <voxplore/mapping/Metaview.h>
#include <voxplore/mapping/PlanarIcp.h>
#include <voxplore/mapping/robot_cloud.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "bench_table.h"

namespace voxplore::bench
{
namespace fs = std::filesystem;
using mrpt::poses::CPose2D;

namespace
{
double percentile(std::vector<double> v, double q)
{
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * double(v.size())))];
}
}  // namespace

RegistrationErrors measureRegistration(const SlamBenchData& data, const std::function<void(std::size_t)>& on_stop)
{
  if (data.ground_truth.empty())
    throw std::runtime_error("registration: needs a ground truth (--gt or trajectory_gt.tum beside the rawlog)");
  RegistrationErrors out;
  mapping::Metaview metaview(data.params.metaview);
  mapping::SlamIcp odometry_reader(data.params);  // only its odometryOf()
  std::optional<CPose2D> odo_prev;
  CPose2D gt_prev;
  for (std::size_t k = 0; k < data.stops.size(); k++)
  {
    const auto& s = data.stops[k];
    auto odo = odometry_reader.odometryOf(s.actions.get(), *s.observations);
    if (!odo) odo = odo_prev ? *odo_prev : CPose2D();
    const CPose2D gt = CPose2D(groundTruthOf(data, s, "registration"));
    const auto usable = mapping::usableDepthScans(*s.observations, data.params.cloud);
    const auto cloud = mapping::buildRobotCloud(usable.scans, data.params.cloud);
    if (k > 0 && !metaview.empty())
    {
      RegistrationError e;
      e.stop = k;
      const CPose2D predicted = mapping::predictPose(gt_prev, *odo_prev, *odo);
      e.step_m = std::hypot(gt.x() - gt_prev.x(), gt.y() - gt_prev.y());
      e.odometry_error_m = std::hypot(predicted.x() - gt.x(), predicted.y() - gt.y());
      const auto& icp = data.params.icp;
      // As SlamIcp::registerStop (without its odometry prior, off by default).
      auto r = mapping::alignPlanarMultiStart(metaview.footprint(), cloud.points, predicted, icp,
                                              &metaview.footprintViewpoints(),
                                              mapping::odometryStdXy(predicted - gt_prev, icp));
      if (!r.accepted && icp.enabled && icp.relocalize && r.iterations > 0)
      {
        r = mapping::relocalizePlanar(metaview.footprint(), cloud.points, predicted, icp,
                                      &metaview.footprintViewpoints());
        e.relocalized = r.accepted;
      }
      e.accepted = r.accepted;
      e.goodness = r.goodness;
      e.info_ratio = r.info_ratio;
      const CPose2D err = gt - r.pose;  // the truth in the estimated robot frame: x > 0 = step too short
      e.along_m = err.x();
      e.across_m = err.y();
      e.error_m = std::hypot(err.x(), err.y());
      e.yaw_error_deg = mrpt::RAD2DEG(mrpt::math::wrapToPi(err.phi()));
      out.stops.push_back(e);
    }
    metaview.insert(cloud.points, gt);
    gt_prev = gt;
    odo_prev = *odo;
    if (on_stop) on_stop(k + 1);
  }
  return out;
}

void runRegistrationTable(const SlamBenchData& data, const SlamBenchOptions& opts, std::ostream& out)
{
  common::Progress progress("registration", data.stops.size(), !opts.quiet);
  const auto res = measureRegistration(data, [&](std::size_t n) { progress.update(n); });
  progress.finish();
  std::vector<double> err, odo, yaw;
  std::size_t over2 = 0, over5 = 0, rejected = 0, reloc = 0;
  for (const auto& e : res.stops)
  {
    err.push_back(e.error_m);
    odo.push_back(e.odometry_error_m);
    yaw.push_back(std::abs(e.yaw_error_deg));
    over2 += e.error_m > 0.02;
    over5 += e.error_m > 0.05;
    rejected += !e.accepted;
    reloc += e.relocalized;
  }
  auto mean = [](const std::vector<double>& v)
  {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / double(v.size());
  };
  TextTable t({{"", "what"},
               {"mean [mm]", "mean_mm"},
               {"p50 [mm]", "p50_mm"},
               {"p90 [mm]", "p90_mm"},
               {"max [mm]", "max_mm"}});
  auto row = [&](const std::string& name, const std::vector<double>& v, double scale)
  {
    t.addRow({name, fixed(scale * mean(v), 1), fixed(scale * percentile(v, 0.5), 1),
              fixed(scale * percentile(v, 0.9), 1),
              fixed(scale * (v.empty() ? 0.0 : *std::max_element(v.begin(), v.end())), 1)});
  };
  row("prediction (odometry) xy", odo, 1e3);
  row("registration xy", err, 1e3);
  row("registration |yaw| [mdeg]", yaw, 1e3);
  out << "\n== Registration alone: each stop against the ground-truth map of the stops before ==\n"
      << res.stops.size() << " registrations of " << opts.rawlog << " (ground truth "
      << data.ground_truth_path << ").\n\n"
      << t.str() << "\nOver 2 cm: " << over2 << ", over 5 cm: " << over5 << ", rejected (prediction kept): "
      << rejected << ", relocalised: " << reloc << "\n";
  std::vector<RegistrationError> worst = res.stops;
  std::sort(worst.begin(), worst.end(), [](const auto& a, const auto& b) { return a.error_m > b.error_m; });
  out << "\nWorst stops (the truth in the estimated robot frame: along > 0 = the step came out short):\n";
  for (std::size_t i = 0; i < std::min<std::size_t>(10, worst.size()); i++)
  {
    const auto& e = worst[i];
    out << "  stop " << e.stop << ": " << fixed(1e3 * e.error_m, 1) << " mm (along "
        << fixed(1e3 * e.along_m, 1) << ", across " << fixed(1e3 * e.across_m, 1) << ", yaw "
        << fixed(e.yaw_error_deg, 2) << " deg), step " << fixed(e.step_m, 2) << " m, odometry "
        << fixed(1e3 * e.odometry_error_m, 1) << " mm, goodness " << fixed(e.goodness, 3)
        << ", info ratio " << fixed(e.info_ratio, 3) << (e.accepted ? "" : ", rejected")
        << (e.relocalized ? ", relocalised" : "") << "\n";
  }
  if (!opts.csv_dir.empty())
  {
    const auto path = fs::path(opts.csv_dir) / "registration.csv";
    std::ofstream f(path);
    if (!f) throw std::runtime_error("cannot write '" + path.string() + "'");
    f << "stop,step_m,odometry_error_m,error_m,along_m,across_m,yaw_error_deg,goodness,info_ratio,"
         "accepted,relocalized\n";
    for (const auto& e : res.stops)
      f << e.stop << "," << e.step_m << "," << e.odometry_error_m << "," << e.error_m << ","
        << e.along_m << "," << e.across_m << "," << e.yaw_error_deg << "," << e.goodness << ","
        << e.info_ratio << "," << e.accepted << "," << e.relocalized << "\n";
  }
}

}  // namespace voxplore::bench
