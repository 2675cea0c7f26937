// voxplore-bench: the "integration into V" row of thesis table 5.2 (OctoMap
// insertion per stop over l_res), our insertion beside stock OctoMap.
#include <octomap/OcTree.h>
#include <voxplore/common/Progress.h>
#include <voxplore/mapping/OctoMapLayer.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <ostream>

#include "bench_slam.h"
#include "bench_table.h"

namespace voxplore::bench
{
using mrpt::poses::CPose3D;

namespace
{
/// Thesis table 5.2, "integration into V" [ms] (Xeon W3520 2.66 GHz), keyed by l_res [mm].
const std::map<int, double> kThesisIntegrationMs = {{10, 3308}, {20, 1767}, {30, 1238},
                                                    {40, 892},  {50, 737},  {60, 592},
                                                    {80, 456},  {100, 423}, {120, 319}};

constexpr double kScanTargetMs = 30.0;  ///< issue 3: one 24,576-ray scan at l_res 5 cm
constexpr double kTargetLresM = 0.05;

/// Voxels (in l_res units) by the thesis thresholds.
struct VoxelCounts
{
  std::size_t occupied = 0, free = 0;
  bool operator==(const VoxelCounts& o) const { return occupied == o.occupied && free == o.free; }
};

/// Counts leaves expanded to l_res voxels: occupied above th_occ, free below th_free.
VoxelCounts countVoxels(const mapping::OctoMapLayer& layer)
{
  const auto& tree = layer.tree();
  const double p_occ = mapping::OctoMapParams::probOf(layer.params().th_occ);
  const double p_free = mapping::OctoMapParams::probOf(layer.params().th_free);
  const unsigned max_depth = tree.getTreeDepth();
  VoxelCounts c;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
  {
    const std::size_t n = std::size_t(1) << (3 * (max_depth - it.getDepth()));
    const double p = it->getOccupancy();
    if (p > p_occ)
      c.occupied += n;
    else if (p < p_free)
      c.free += n;
  }
  return c;
}

/// Inserts the depth images of one stop; @return wall time [ms].
double insertStop(mapping::OctoMapLayer& layer, const RecordedStop& stop,
                  const CPose3D& T_world_robot, bool stock, std::size_t& rays)
{
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& scan : stop.scans)
    rays += (stock ? layer.insertScanStock(*scan, T_world_robot)
                   : layer.insertScan(*scan, T_world_robot))
                .rays;
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// One column of the row: our and stock insertion at one l_res.
struct IntegrationColumn
{
  double l_res_m = 0;
  double ours_ms = 0, stock_ms = 0, ours_max_ms = 0, stock_max_ms = 0;
  double rays_per_stop = 0;
  std::size_t leaves_ours = 0, leaves_stock = 0, mem_ours = 0, mem_stock = 0;
  VoxelCounts ours, stock;
};

IntegrationColumn measureLres(const SlamBenchData& data, const SlamBenchOptions& opts,
                              const std::vector<CPose3D>& poses, double l_res_m)
{
  auto params = data.params.octomap;
  params.l_res_m = l_res_m;
  const std::size_t n = data.stops.size();
  common::Progress progress("table 5.2  l_res " + fixed(l_res_m * 1e3, 0) + " mm", n * opts.repeat,
                            !opts.quiet);
  std::vector<double> ours_mean, stock_mean, ours_max, stock_max;
  IntegrationColumn c;
  c.l_res_m = l_res_m;
  for (unsigned rep = 0; rep < opts.repeat; rep++)
  {
    mapping::OctoMapLayer ours(params), stock(params);
    double sum_ours = 0, sum_stock = 0, max_ours = 0, max_stock = 0;
    std::size_t rays_ours = 0, rays_stock = 0;
    for (std::size_t i = 0; i < n; i++)
    {
      // Alternate which tree goes first so neither always finds warm caches.
      double t_ours = 0, t_stock = 0;
      if (i % 2 == 0) t_ours = insertStop(ours, data.stops[i], poses[i], false, rays_ours);
      t_stock = insertStop(stock, data.stops[i], poses[i], true, rays_stock);
      if (i % 2 == 1) t_ours = insertStop(ours, data.stops[i], poses[i], false, rays_ours);
      sum_ours += t_ours;
      sum_stock += t_stock;
      max_ours = std::max(max_ours, t_ours);
      max_stock = std::max(max_stock, t_stock);
      progress.update(rep * n + i + 1);
    }
    ours_mean.push_back(sum_ours / double(n));
    stock_mean.push_back(sum_stock / double(n));
    ours_max.push_back(max_ours);
    stock_max.push_back(max_stock);
    c.rays_per_stop = double(rays_ours) / double(n);
    if (rays_ours != rays_stock)
      throw std::logic_error("insertScan and insertScanStock cast different ray counts (" +
                             std::to_string(rays_ours) + " vs " + std::to_string(rays_stock) + ")");
    if (rep + 1 == opts.repeat)
    {
      c.leaves_ours = ours.numLeafNodes();
      c.leaves_stock = stock.numLeafNodes();
      c.mem_ours = ours.memoryUsage();
      c.mem_stock = stock.memoryUsage();
      c.ours = countVoxels(ours);
      c.stock = countVoxels(stock);
    }
  }
  progress.finish();
  c.ours_ms = median(ours_mean);
  c.stock_ms = median(stock_mean);
  c.ours_max_ms = median(ours_max);
  c.stock_max_ms = median(stock_max);
  return c;
}

TextTable integrationTable(const std::vector<IntegrationColumn>& cols)
{
  TextTable t({{"l_res [mm]", "l_res_mm"},
               {"ours [ms]", "ours_ms"},
               {"stock [ms]", "stock_ms"},
               {"thesis [ms]", "thesis_ms"},
               {"stock/ours", "speedup_vs_stock"},
               {"ours max", "ours_max_ms"},
               {"stock max", "stock_max_ms"},
               {"rays/stop", "rays_per_stop"},
               {"leaves ours", "leaves_ours"},
               {"leaves stock", "leaves_stock"},
               {"MiB ours", "memory_mib_ours"},
               {"MiB stock", "memory_mib_stock"},
               {"occ. ours", "occupied_voxels_ours"},
               {"occ. stock", "occupied_voxels_stock"},
               {"free ours", "free_voxels_ours"},
               {"free stock", "free_voxels_stock"},
               {"same", "same_counts"}});
  for (const auto& c : cols)
  {
    const auto it = kThesisIntegrationMs.find(static_cast<int>(std::lround(c.l_res_m * 1e3)));
    const bool thesis =
        it != kThesisIntegrationMs.end() && std::abs(c.l_res_m * 1e3 - it->first) < 1e-6;
    t.addRow({fixed(c.l_res_m * 1e3, 0), fixed(c.ours_ms, 2), fixed(c.stock_ms, 2),
              thesis ? fixed(it->second, 0) : "-", fixed(c.stock_ms / c.ours_ms, 2),
              fixed(c.ours_max_ms, 2), fixed(c.stock_max_ms, 2), fixed(c.rays_per_stop, 0),
              std::to_string(c.leaves_ours), std::to_string(c.leaves_stock),
              fixed(double(c.mem_ours) / (1 << 20), 2), fixed(double(c.mem_stock) / (1 << 20), 2),
              std::to_string(c.ours.occupied), std::to_string(c.stock.occupied),
              std::to_string(c.ours.free), std::to_string(c.stock.free),
              c.ours == c.stock ? "yes" : "NO"});
  }
  return t;
}
}  // namespace

void runIntegrationTable(const SlamBenchData& data, const SlamBenchOptions& opts,
                         const std::vector<CPose3D>& poses, std::ostream& out)
{
  if (poses.size() != data.stops.size())
    throw std::logic_error("runIntegrationTable: one pose per stop needed");
  std::vector<IntegrationColumn> cols;
  for (const double l_res : opts.l_res_m) cols.push_back(measureLres(data, opts, poses, l_res));
  const auto table = integrationTable(cols);

  std::size_t pixels = 0;
  for (const auto& s : data.stops)
    for (const auto& scan : s.scans) pixels += scan->rangeImage.size();
  out << "\n== Table 5.2, row \"integration into V\": one stop's depth images into V ==\n"
      << "First " << data.stops.size() << " stops, fresh trees, poses from "
      << (opts.poses_from_gt ? "ground truth" : "ICP at d_min 20 mm")
      << "; mean (and max) ms per stop, one stop = " << pixels / data.stops.size()
      << " pixels (rays/stop: the valid ones)"
      << (opts.repeat > 1 ? ", median of " + std::to_string(opts.repeat) + " runs" : "") << ".\n"
      << "ours = OctoMapLayer::insertScan, stock = octomap::OcTree::insertPointCloud, same rays\n"
      << "from each camera's origin, separate trees in the same run. Voxel counts in l_res\n"
      << "voxels after the last stop: occupied > th_occ, free < th_free. thesis: Xeon W3520.\n\n"
      << table.str();
  for (const auto& c : cols)
    if (std::abs(c.l_res_m - kTargetLresM) < 1e-9)
      out << "\nTarget (issue 3): integrating one 24,576-ray scan at l_res 50 mm < "
          << kScanTargetMs << " ms on one core: ours " << fixed(c.ours_ms, 2) << " ms mean, "
          << fixed(c.ours_max_ms, 2) << " ms max -> "
          << (c.ours_max_ms < kScanTargetMs ? "met"
              : c.ours_ms < kScanTargetMs   ? "met on average, MISSED by the slowest stop"
                                            : "MISSED")
          << " (stock " << fixed(c.stock_ms, 2) << " ms)\n";
  if (!opts.csv_dir.empty())
    table.writeCsv((std::filesystem::path(opts.csv_dir) / "table_5_2_integration.csv").string());
}

}  // namespace voxplore::bench
