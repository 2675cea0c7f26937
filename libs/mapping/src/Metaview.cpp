#include <voxplore/common/config.h>
#include <voxplore/mapping/Metaview.h>

#include "cell_key.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

namespace voxplore::mapping
{
void MetaviewParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(d_min_m, double, c, s);
  common::requireValid(d_min_m >= 0 && d_min_m < 10, c, s, "d_min_m", "must be in [0, 10) m");
  MRPT_LOAD_CONFIG_VAR(d_dup_2d_m, double, c, s);
  common::requireValid(d_dup_2d_m >= 0 && d_dup_2d_m < 1, c, s, "d_dup_2d_m", "must be in [0, 1) m");
  common::requireValid(d_dup_2d_m == 0 || d_min_m > 0, c, s, "d_dup_2d_m",
                       "needs d_min_m > 0 (its cells index the footprint)");
  MRPT_LOAD_CONFIG_VAR(d_dup_after_m, double, c, s);
  common::requireValid(d_dup_after_m >= 0, c, s, "d_dup_after_m", "must be >= 0 m");
}

void MetaviewParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(d_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(d_dup_2d_m, c, s);
  MRPT_SAVE_CONFIG_VAR(d_dup_after_m, c, s);
}

Metaview::Metaview(const MetaviewParams& params) : params_(params) {}

uint64_t Metaview::cellKey(int64_t ix, int64_t iy, int64_t iz) const
{
  return detail::cellKey(ix, iy, iz);
}

uint64_t Metaview::cellOf(float x, float y, float z, bool planar) const
{
  const double d = params_.d_min_m;
  return cellKey(static_cast<int64_t>(std::floor(x / d)), static_cast<int64_t>(std::floor(y / d)),
                 planar ? 0 : static_cast<int64_t>(std::floor(z / d)));
}

namespace
{
// Non-finite (or astronomically far) coordinates would overflow the cell
// index casts (undefined behaviour): such a pose or point is never inserted.
constexpr double kFar = 1e6;  // [m]
bool usable(double v) { return std::abs(v) < kFar; }  // false for NaN too
bool usable(const mrpt::poses::CPose2D& p)
{
  return usable(p.x()) && usable(p.y()) && std::isfinite(p.phi());
}
}  // namespace

namespace detail
{
std::size_t CellIndex::slot(uint64_t key) const
{
  // splitmix64's finaliser: neighbouring cells spread over the table.
  uint64_t h = key + 0x9e3779b97f4a7c15ULL;
  h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
  h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
  h ^= h >> 31;
  const std::size_t mask = keys_.size() - 1;
  std::size_t s = static_cast<std::size_t>(h) & mask;
  while (keys_[s] != key && keys_[s] != kFree) s = (s + 1) & mask;
  return s;
}

void CellIndex::rehash(std::size_t capacity)
{
  std::vector<uint64_t> keys(capacity, kFree);
  std::vector<uint32_t> heads(capacity, kNone);
  keys.swap(keys_);
  heads.swap(heads_);
  for (std::size_t i = 0; i < keys.size(); i++)
    if (keys[i] != kFree)
    {
      const std::size_t s = slot(keys[i]);
      keys_[s] = keys[i];
      heads_[s] = heads[i];
    }
}

void CellIndex::clear(std::size_t cells)
{
  std::size_t capacity = 1024;
  while (capacity < 2 * cells) capacity *= 2;  // load factor <= 0.5
  keys_.assign(capacity, kFree);
  heads_.assign(capacity, kNone);
  next_.clear();
  cells_ = 0;
}

uint32_t CellIndex::head(uint64_t key) const
{
  if (keys_.empty()) return kNone;
  return heads_[slot(key)];
}

void CellIndex::add(uint64_t key, uint32_t i)
{
  if (keys_.empty()) clear();
  if (2 * (cells_ + 1) > keys_.size()) rehash(2 * keys_.size());
  if (next_.size() <= i) next_.resize(static_cast<std::size_t>(i) + 1, kNone);
  const std::size_t s = slot(key);
  if (keys_[s] == kFree)
  {
    keys_[s] = key;
    cells_++;
  }
  next_[i] = heads_[s];
  heads_[s] = i;
}
}  // namespace detail

bool Metaview::hasNeighbourWithin(const mrpt::maps::CSimplePointsMap& pts, const detail::CellIndex& grid,
                                  bool planar, float x, float y, float z, double radius,
                                  uint32_t below) const
{
  // thesis 4.4.2: a point is integrated only if ||m_k - p_i|| > d_min for all m_k in M.
  const double d = params_.d_min_m;
  const double r2 = radius * radius;
  const int64_t reach = static_cast<int64_t>(std::ceil(radius / d));  // cells of d_min
  const int64_t cx = static_cast<int64_t>(std::floor(x / d));
  const int64_t cy = static_cast<int64_t>(std::floor(y / d));
  const int64_t cz = planar ? 0 : static_cast<int64_t>(std::floor(z / d));
  const int64_t dz = planar ? 0 : reach;
  const auto& xs = pts.getPointsBufferRef_x();
  const auto& ys = pts.getPointsBufferRef_y();
  const auto& zs = pts.getPointsBufferRef_z();
  for (int64_t ix = cx - reach; ix <= cx + reach; ix++)
    for (int64_t iy = cy - reach; iy <= cy + reach; iy++)
      for (int64_t iz = cz - dz; iz <= cz + dz; iz++)
      {
        for (uint32_t idx = grid.head(cellKey(ix, iy, iz)); idx != detail::CellIndex::kNone;
             idx = grid.next(idx))
        {
          if (idx >= below) continue;
          const double ex = xs[idx] - x, ey = ys[idx] - y, ez = zs[idx] - z;
          if (ex * ex + ey * ey + ez * ez <= r2) return true;
        }
      }
  return false;
}

bool Metaview::addPoint(mrpt::maps::CSimplePointsMap& pts, detail::CellIndex& grid, bool planar,
                        float x, float y, float z, uint32_t older_end)
{
  const double d = params_.d_min_m;
  if (d > 0)
  {
    // d_min first: it refuses most points (the stops overlap) and looks at 9
    // (27) cells, d_dup_2d_m at (2 ceil(d_dup / d_min) + 1)^2.
    if (hasNeighbourWithin(pts, grid, planar, x, y, z, d)) return false;
    if (older_end > 0 &&
        hasNeighbourWithin(pts, grid, planar, x, y, z, params_.d_dup_2d_m, older_end))
      return false;
    grid.add(cellOf(x, y, z, planar), static_cast<uint32_t>(pts.size()));
  }
  pts.insertPointFast(x, y, z);
  return true;
}

std::size_t Metaview::insert(const mrpt::maps::CPointsMap& cloud_robot, const mrpt::poses::CPose2D& T_map_robot)
{
  // Every call is a block (empty when nothing is added), so that blocks
  // stay one per keyframe for reposition().
  double travel = 0;
  if (!blocks_.empty())
    travel = blocks_.back().travel_m + std::hypot(T_map_robot.x() - blocks_.back().pose.x(),
                                                  T_map_robot.y() - blocks_.back().pose.y());
  if (!std::isfinite(travel)) travel = blocks_.empty() ? 0 : blocks_.back().travel_m;
  // With d_dup_2d_m, the footprint points of the stops d_dup_after_m or more
  // of travel back (the blocks before the first one nearer than that; the
  // travel only grows along blocks_); 0 = no such stop, the rule is off.
  uint32_t older_end = 0;
  if (params_.d_dup_2d_m > 0 && params_.d_min_m > 0)
  {
    const auto nearer = std::partition_point(
        blocks_.begin(), blocks_.end(),
        [&](const Block& b) { return b.travel_m <= travel - params_.d_dup_after_m; });
    older_end = nearer == blocks_.begin() ? 0 : std::prev(nearer)->end2d;
  }
  blocks_.push_back({T_map_robot, static_cast<uint32_t>(points_.size()),
                     static_cast<uint32_t>(points2d_.size()), travel});
  if (!usable(T_map_robot)) return 0;
  const double c = std::cos(T_map_robot.phi()), s = std::sin(T_map_robot.phi());
  const auto& xs = cloud_robot.getPointsBufferRef_x();
  const auto& ys = cloud_robot.getPointsBufferRef_y();
  const auto& zs = cloud_robot.getPointsBufferRef_z();
  const std::size_t before = points_.size();
  const Eigen::Vector2f viewpoint(static_cast<float>(T_map_robot.x()), static_cast<float>(T_map_robot.y()));
  for (std::size_t i = 0; i < xs.size(); i++)
  {
    const float x = static_cast<float>(T_map_robot.x() + c * xs[i] - s * ys[i]);
    const float y = static_cast<float>(T_map_robot.y() + s * xs[i] + c * ys[i]);
    if (!usable(x) || !usable(y) || !usable(zs[i])) continue;
    addPoint(points_, grid_, false, x, y, zs[i]);
    if (addPoint(points2d_, grid2d_, true, x, y, 0.0f, older_end))
      viewpoints2d_.push_back(viewpoint);
  }
  points_.mark_as_modified();  // KD-trees rebuilt on next query
  points2d_.mark_as_modified();
  blocks_.back().end3d = static_cast<uint32_t>(points_.size());
  blocks_.back().end2d = static_cast<uint32_t>(points2d_.size());
  return points_.size() - before;
}

void Metaview::rebuildGrid(const mrpt::maps::CSimplePointsMap& pts, detail::CellIndex& grid,
                           bool planar) const
{
  const auto& xs = pts.getPointsBufferRef_x();
  const auto& ys = pts.getPointsBufferRef_y();
  const auto& zs = pts.getPointsBufferRef_z();
  grid.clear(xs.size());  // about one point per cell after the reduction
  if (params_.d_min_m <= 0) return;
  for (std::size_t i = 0; i < xs.size(); i++) grid.add(cellOf(xs[i], ys[i], zs[i], planar), static_cast<uint32_t>(i));
}

void Metaview::reposition(const std::vector<mrpt::poses::CPose2D>& poses)
{
  if (poses.size() != blocks_.size())
    throw std::invalid_argument("Metaview::reposition: " + std::to_string(poses.size()) +
                                " poses for " + std::to_string(blocks_.size()) + " blocks");
  uint32_t begin3d = 0, begin2d = 0;
  for (std::size_t b = 0; b < blocks_.size(); b++)
  {
    Block& blk = blocks_[b];
    const uint32_t b3 = std::exchange(begin3d, blk.end3d), b2 = std::exchange(begin2d, blk.end2d);
    if (!usable(poses[b]) || !usable(blk.pose)) continue;  // such a block holds no points
    // p_new = T_new (+) T_old^-1 (+) p_old: turn by the yaw change about the
    // old position, then put that position on the new one.
    const mrpt::poses::CPose2D old = std::exchange(blk.pose, poses[b]);
    const double dphi = poses[b].phi() - old.phi();
    if (poses[b].x() == old.x() && poses[b].y() == old.y() && dphi == 0) continue;
    const double c = std::cos(dphi), s = std::sin(dphi);
    const auto move = [&](float& x, float& y)
    {
      const double lx = x - old.x(), ly = y - old.y();
      x = static_cast<float>(poses[b].x() + c * lx - s * ly);
      y = static_cast<float>(poses[b].y() + s * lx + c * ly);
    };
    for (uint32_t i = b3; i < blk.end3d; i++)
    {
      float x = 0, y = 0, z = 0;
      points_.getPointFast(i, x, y, z);
      move(x, y);
      points_.setPointFast(i, x, y, z);
    }
    for (uint32_t i = b2; i < blk.end2d; i++)
    {
      float x = 0, y = 0, z = 0;
      points2d_.getPointFast(i, x, y, z);
      move(x, y);
      points2d_.setPointFast(i, x, y, z);
      viewpoints2d_[i] = Eigen::Vector2f(static_cast<float>(poses[b].x()), static_cast<float>(poses[b].y()));
    }
  }
  points_.mark_as_modified();
  points2d_.mark_as_modified();
  rebuildGrid(points_, grid_, false);
  rebuildGrid(points2d_, grid2d_, true);
}

}  // namespace voxplore::mapping
