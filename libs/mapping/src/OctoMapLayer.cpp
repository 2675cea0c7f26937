/* voxplore — the 3D occupancy map V (thesis 4.4.3). */
#include <mrpt/core/exceptions.h>
#include <octomap/OcTree.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/OctoMapLayer.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "octomap_insert.h"

namespace voxplore::mapping
{
namespace
{
octomap::point3d toPoint3d(const Eigen::Vector3d& p)
{
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}

/// Range up to which invalid pixels clear free space (0: they do not).
double clearingRange(const OctoMapParams& p)
{
  return std::min(p.invalid_free_range_m, p.max_range_m);
}

/// Far points along the invalid pixels' directions: twice the clearing range,
/// so that clipRay / computeUpdate truncate them at exactly that range.
octomap::Pointcloud clearingTargets(const PixelRays& rays, double range_m)
{
  octomap::Pointcloud out;
  out.reserve(rays.invalid_dirs_world.size());
  const octomap::point3d origin = toPoint3d(rays.origin_world);
  for (const auto& d : rays.invalid_dirs_world)
    out.push_back(origin + toPoint3d(d) * static_cast<float>(2.0 * range_m));
  return out;
}

/// A new map id for OctoMapLayer's journal, never 0 and never given twice.
uint64_t newMapId()
{
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

/// Coordinate bounds of the points a scan's rays run between. The voxels a
/// ray passes lie, on every axis, between its two ends' keys (a key is a
/// monotone function of the coordinate), so these bounds' keys, one voxel
/// wider for the float rounding, hold every voxel the scan may change.
struct PointBounds
{
  octomap::point3d lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                      std::numeric_limits<float>::max()};
  octomap::point3d hi{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                      -std::numeric_limits<float>::max()};

  void add(const octomap::point3d& p)
  {
    for (unsigned a = 0; a < 3; ++a)
    {
      lo(a) = std::min(lo(a), p(a));
      hi(a) = std::max(hi(a), p(a));
    }
  }
  /// Empty when no point was added; nullopt when a bound is outside the tree.
  std::optional<KeyBox> keys(const octomap::OcTree& t) const
  {
    if (lo.x() > hi.x()) return KeyBox{};
    octomap::OcTreeKey a, b;
    if (!detail::coordToKeySafe(t, lo, a) || !detail::coordToKeySafe(t, hi, b))
      return std::nullopt;
    KeyBox k;
    for (int i = 0; i < 3; ++i)
    {
      k.lo[i] = std::max(0, static_cast<int>(a[i]) - 1);
      k.hi[i] = static_cast<int>(b[i]) + 2;
    }
    return k;
  }
};

octomap::Pointcloud toPointcloud(const std::vector<Eigen::Vector3d>& pts)
{
  octomap::Pointcloud out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(toPoint3d(p));
  return out;
}

/// Counts of a scan known before the tree is touched.
InsertStats rayCounts(const octomap::OcTree& tree, const PixelRays& rays,
                      const octomap::Pointcloud& hits, double max_range_m, bool clearing)
{
  InsertStats st;
  st.invalid = rays.invalid_dirs_world.size() + rays.unusable;
  st.rays = rays.endpoints_world.size() + (clearing ? rays.invalid_dirs_world.size() : 0);
  const octomap::point3d origin = toPoint3d(rays.origin_world);
  octomap::OcTreeKey key;
  for (const auto& p : hits)
  {
    octomap::point3d end;
    st.hits += detail::clipRay(origin, p, max_range_m, end) && detail::coordToKeySafe(tree, p, key);
  }
  return st;
}
}  // namespace

// ------------------------------------------------------------------- the map

OctoMapLayer::OctoMapLayer(const OctoMapParams& params) : params_(params), low_(params.l_res_m)
{
  ASSERTMSG_(params_.l_res_m > 0, "OctoMapParams::l_res_m must be > 0");
  ASSERTMSG_(params_.th_free < params_.th_occ, "OctoMapParams: need th_free < th_occ");
  auto tree = std::make_unique<detail::LayerTree>(params_.l_res_m);
  // Thesis 0..255 scale: isNodeOccupied() means "value > th_occ" (thesis 4.4.3).
  tree->setOccupancyThres(OctoMapParams::probOf(params_.th_occ));
  tree->setProbHit(params_.prob_hit);
  tree->setProbMiss(params_.prob_miss);
  tree->setClampingThresMin(params_.clamp_min);
  tree->setClampingThresMax(params_.clamp_max);
  tree_ = std::move(tree);
  id_ = newMapId();
  if (params_.low_obstacle_min_z_m > 0)
    low_.setBands(params_.low_obstacle_floor_z_m, params_.low_obstacle_min_z_m,
                  params_.low_obstacle_max_z_m);
}

void OctoMapLayer::countLow(const PixelRays& rays)
{
  if (params_.low_obstacle_min_z_m <= 0) return;
  const double r2 = params_.max_range_m * params_.max_range_m;
  for (const auto& p : rays.endpoints_world)
    if ((p - rays.origin_world).squaredNorm() <= r2) low_.add(p.x(), p.y(), p.z());
}

std::vector<Eigen::Vector2d> OctoMapLayer::lowObstacles() const
{
  if (params_.low_obstacle_min_z_m <= 0) return {};
  return low_.obstacles(params_.low_obstacle_min_hits, params_.low_obstacle_min_share);
}

OctoMapLayer::~OctoMapLayer() = default;
OctoMapLayer::OctoMapLayer(OctoMapLayer&&) noexcept = default;
OctoMapLayer& OctoMapLayer::operator=(OctoMapLayer&&) noexcept = default;

const octomap::OcTree& OctoMapLayer::tree() const
{
  return *tree_;
}
octomap::OcTree& OctoMapLayer::mutableTree()
{
  journal(std::nullopt);
  return *tree_;
}

void OctoMapLayer::journal(const std::optional<KeyBox>& b)
{
  if (!b)
  {
    id_ = newMapId();
    rev_ = journal_first_ = 0;
    journal_.clear();
    return;
  }
  if (journal_.size() == kJournalSize)
  {
    const std::size_t drop = kJournalSize / 2;
    journal_.erase(journal_.begin(), journal_.begin() + static_cast<std::ptrdiff_t>(drop));
    journal_first_ += drop;
  }
  journal_.push_back(*b);
  ++rev_;
}

std::optional<KeyBox> OctoMapLayer::changedSince(const MapRevision& since) const
{
  if (since.map != id_ || since.rev > rev_ || since.rev < journal_first_) return std::nullopt;
  KeyBox out;
  for (std::size_t i = since.rev - journal_first_; i < journal_.size(); ++i) out.extend(journal_[i]);
  return out;
}

std::size_t OctoMapLayer::numLeafNodes() const
{
  return tree_->getNumLeafNodes();
}
std::size_t OctoMapLayer::memoryUsage() const
{
  return tree_->memoryUsage();
}

InsertStats OctoMapLayer::insertScan(const mrpt::obs::CObservation3DRangeScan& obs,
                                     const mrpt::poses::CPose3D& T_world_robot)
{
  const PixelRays rays = unprojectRays(obs, T_world_robot);
  countLow(rays);
  const octomap::point3d origin = toPoint3d(rays.origin_world);
  const double clear_range = clearingRange(params_);
  detail::RayKeyCollector collector(*tree_);
  InsertStats st;
  st.invalid = rays.invalid_dirs_world.size() + rays.unusable;
  st.rays = rays.endpoints_world.size();
  PointBounds bounds;
  bounds.add(origin);
  for (const auto& p_world : rays.endpoints_world)
  {
    octomap::point3d end;
    const bool hit = detail::clipRay(origin, toPoint3d(p_world), params_.max_range_m, end);
    octomap::OcTreeKey key;
    st.hits += hit && detail::coordToKeySafe(*tree_, end, key);
    collector.addRay(origin, end, hit);
    bounds.add(end);
  }
  if (clear_range > 0)
  {
    st.rays += rays.invalid_dirs_world.size();
    for (const auto& far : clearingTargets(rays, clear_range))
    {
      octomap::point3d end;
      detail::clipRay(origin, far, clear_range, end);
      collector.addRay(origin, end, false);
      bounds.add(end);
    }
  }
  std::vector<std::uint64_t> entries = collector.release();
  std::tie(st.free_updates, st.occ_updates) = detail::sortUnique(entries);
  if (!entries.empty()) journal(bounds.keys(*tree_));
  detail::applyBatch(static_cast<detail::LayerTree&>(*tree_), entries);
  return st;
}

InsertStats OctoMapLayer::insertScanStock(const mrpt::obs::CObservation3DRangeScan& obs,
                                          const mrpt::poses::CPose3D& T_world_robot)
{
  const PixelRays rays = unprojectRays(obs, T_world_robot);
  countLow(rays);
  const octomap::point3d origin = toPoint3d(rays.origin_world);
  const double clear_range = clearingRange(params_);
  const octomap::Pointcloud cloud = toPointcloud(rays.endpoints_world);
  InsertStats st = rayCounts(*tree_, rays, cloud, params_.max_range_m, clear_range > 0);
  octomap::OcTreeKey origin_key;  // OctoMap's own key computation is undefined outside the tree
  if (!detail::coordToKeySafe(*tree_, origin, origin_key)) return st;

  // The body of OcTree::insertPointCloud(cloud, origin, max_range_m,
  // lazy_eval = false, discretize = false), inlined so that the rays of
  // invalid pixels (truncated at clear_range, no endpoint) join the same key
  // sets and the counts are known.
  octomap::KeySet free_cells, occupied_cells;
  tree_->computeUpdate(cloud, origin, free_cells, occupied_cells, params_.max_range_m);
  // computeUpdate clips the rays on their way to these points.
  PointBounds bounds;
  bounds.add(origin);
  for (const auto& q : cloud) bounds.add(q);
  const octomap::Pointcloud clearing =
      clear_range > 0 ? clearingTargets(rays, clear_range) : octomap::Pointcloud();
  for (const auto& q : clearing) bounds.add(q);
  if (clear_range > 0)
  {
    octomap::KeySet clear_free, clear_occ;  // clear_occ stays empty: all rays truncated
    tree_->computeUpdate(clearing, origin, clear_free, clear_occ, clear_range);
    for (const auto& k : clear_free)
      if (occupied_cells.count(k) == 0) free_cells.insert(k);
  }
  if (!free_cells.empty() || !occupied_cells.empty()) journal(bounds.keys(*tree_));
  for (const auto& k : free_cells) tree_->updateNode(k, false, false);
  for (const auto& k : occupied_cells) tree_->updateNode(k, true, false);
  st.free_updates = free_cells.size();
  st.occ_updates = occupied_cells.size();
  return st;
}

void OctoMapLayer::setStartBoxFree(const mrpt::poses::CPose3D& T_world_robot)
{
  const double hx = params_.start_box_x_m / 2, hy = params_.start_box_y_m / 2;
  const double hz = params_.start_box_z_m;
  if (hx <= 0 || hy <= 0 || hz <= 0) return;
  // World-frame bounding box of the (rotated) box, then every voxel centre in it.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (int i = 0; i < 8; i++)
  {
    mrpt::math::TPoint3D w;
    T_world_robot.composePoint({i & 1 ? hx : -hx, i & 2 ? hy : -hy, i & 4 ? hz : 0.0}, w);
    lo = lo.cwiseMin(Eigen::Vector3d(w.x, w.y, w.z));
    hi = hi.cwiseMax(Eigen::Vector3d(w.x, w.y, w.z));
  }
  octomap::OcTreeKey kmin, kmax;
  if (!detail::coordToKeySafe(*tree_, toPoint3d(lo), kmin) ||
      !detail::coordToKeySafe(*tree_, toPoint3d(hi), kmax))
    THROW_EXCEPTION("OctoMapLayer::setStartBoxFree: start box outside the octree's range");
  const float free_log_odds = tree_->getClampingThresMinLog();
  KeyBox changed;
  for (int a = 0; a < 3; ++a)
  {
    changed.lo[a] = kmin[a];
    changed.hi[a] = kmax[a] + 1;
  }
  journal(changed);
  constexpr double kEps = 1e-9;
  for (unsigned kx = kmin[0]; kx <= kmax[0]; kx++)
    for (unsigned ky = kmin[1]; ky <= kmax[1]; ky++)
      for (unsigned kz = kmin[2]; kz <= kmax[2]; kz++)
      {
        const octomap::OcTreeKey key(kx, ky, kz);
        const mrpt::math::TPoint3D c(tree_->keyToCoord(key[0]), tree_->keyToCoord(key[1]),
                                     tree_->keyToCoord(key[2]));
        mrpt::math::TPoint3D l;
        T_world_robot.inverseComposePoint(c, l);
        if (std::abs(l.x) <= hx + kEps && std::abs(l.y) <= hy + kEps && l.z >= -kEps &&
            l.z <= hz + kEps)
          tree_->setNodeValue(key, free_log_odds, false);  // non-lazy: inner nodes kept current
      }
}

VoxelState OctoMapLayer::stateAt(const Eigen::Vector3d& p) const
{
  octomap::OcTreeKey key;
  if (!detail::coordToKeySafe(*tree_, toPoint3d(p), key)) return VoxelState::Unknown;
  const octomap::OcTreeNode* node = tree_->search(key);
  if (node == nullptr) return VoxelState::Unknown;
  const double prob = node->getOccupancy();
  if (prob < OctoMapParams::probOf(params_.th_free)) return VoxelState::Free;
  if (prob > OctoMapParams::probOf(params_.th_occ)) return VoxelState::Occupied;
  return VoxelState::Unknown;
}

std::vector<Eigen::Vector3d> OctoMapLayer::occupiedVoxelCenters() const
{
  std::vector<Eigen::Vector3d> out;
  const double p_occ = OctoMapParams::probOf(params_.th_occ);
  const unsigned max_depth = tree_->getTreeDepth();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it)
  {
    if (it->getOccupancy() <= p_occ) continue;
    const unsigned side = 1U << (max_depth - it.getDepth());  // l_res voxels per edge
    const octomap::OcTreeKey k0 = it.getIndexKey();           // lowest corner voxel
    for (unsigned i = 0; i < side; i++)
      for (unsigned j = 0; j < side; j++)
        for (unsigned k = 0; k < side; k++)
          out.emplace_back(tree_->keyToCoord(k0[0] + i), tree_->keyToCoord(k0[1] + j),
                           tree_->keyToCoord(k0[2] + k));
  }
  return out;
}

void OctoMapLayer::writeBinary(const std::string& path) const
{
  // What OcTree::writeBinaryConst writes (the live tree keeps its log-odds;
  // writeBinary() would convert it to maximum likelihood first): leaves above
  // th_occ are written occupied, every other known leaf free. The header and
  // writeBinaryNode are written here because octomap 1.9.7's
  // writeBinaryConst / writeBinaryData print "Writing N nodes to output
  // stream... done." to stderr after every map (OCTOMAP_DEBUG in a library
  // built without NDEBUG).
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (out)
  {
    out << "# Octomap OcTree binary file\n"
           "# (feel free to add / change comments, but leave the first line as it is!)\n#\n"
        << "id " << tree_->getTreeType() << "\n"
        << "size " << tree_->size() << "\n"
        << "res " << tree_->getResolution() << "\n"
        << "data\n";
    if (tree_->getRoot()) tree_->writeBinaryNode(out, tree_->getRoot());
    out.close();
  }
  if (!out) throw std::runtime_error("OctoMapLayer::writeBinary: cannot write '" + path + "'");
}

// ------------------------------------------------------------ unprojection

PixelRays unprojectRays(const mrpt::obs::CObservation3DRangeScan& obs,
                        const mrpt::poses::CPose3D& T_world_robot)
{
  ASSERTMSG_(obs.hasRangeImage,
             "unprojectRays: observation '" + obs.sensorLabel + "' has no range image");
  const int W = static_cast<int>(obs.rangeImage.cols()),
            H = static_cast<int>(obs.rangeImage.rows());
  const auto& lut = obs.get_unproj_lut();  // per pixel, unit range (or depth), sensor frame
  ASSERTMSG_(lut.Kxs.size() == static_cast<std::size_t>(W) * H,
             "unprojectRays: camera intrinsics of '" + obs.sensorLabel +
                 "' do not match its range image size");
  const mrpt::poses::CPose3D T_world_camera = T_world_robot + obs.sensorPose;
  const Eigen::Matrix3d R = T_world_camera.getRotationMatrix().asEigen();
  const Eigen::Vector3d t(T_world_camera.x(), T_world_camera.y(), T_world_camera.z());

  PixelRays rays;
  rays.origin_world = t;
  // Garbage (NaN / inf pose or intrinsics, rangeUnits <= 0) yields unusable
  // pixels, never a ray: non-finite coordinates must not reach OctoMap.
  if (!t.allFinite() || !R.allFinite())
  {
    rays.unusable = static_cast<std::size_t>(W) * H;
    return rays;
  }
  rays.endpoints_world.reserve(static_cast<std::size_t>(W) * H);
  for (int r = 0, idx = 0; r < H; r++)
    for (int c = 0; c < W; c++, idx++)
    {
      const float D = obs.rangeImage(r, c) * obs.rangeUnits;  // as range2XYZ_LUT
      const Eigen::Vector3d k(lut.Kxs[idx], lut.Kys[idx], lut.Kzs[idx]);
      if (!k.allFinite() || k.squaredNorm() == 0.0 || !std::isfinite(D) || D < 0.0f)
      {
        rays.unusable++;
        continue;
      }
      if (D == 0.0f)
      {
        rays.invalid_dirs_world.push_back(R * k.normalized());
        continue;
      }
      const Eigen::Vector3d local(lut.Kxs[idx] * D, lut.Kys[idx] * D, lut.Kzs[idx] * D);
      const Eigen::Vector3d p = R * local + t;
      if (!p.allFinite())
      {
        rays.unusable++;
        continue;
      }
      rays.endpoints_world.push_back(p);
    }
  return rays;
}

}  // namespace voxplore::mapping
