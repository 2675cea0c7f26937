/* voxplore — batched ray insertion into an octomap::OcTree (see octomap_insert.h). */
#include "octomap_insert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace voxplore::mapping::detail
{
namespace
{
/// Morton masks of the x, y and z bits of a 16-bit-per-axis key.
constexpr std::uint64_t kMaskX = 0x0000249249249249ULL;
constexpr std::array<std::uint64_t, 3> kAxisMask = {kMaskX, kMaskX << 1, kMaskX << 2};
constexpr unsigned kTreeDepth = 16;
constexpr std::size_t kCacheBits = 12;  // 4096-entry dedup cache (32 KiB, stays in L1/L2)

/// Spreads the 8 bits of a byte to bit positions 0, 3, ..., 21.
constexpr std::array<std::uint32_t, 256> makeSpreadTable()
{
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t v = 0; v < 256; v++)
    for (unsigned b = 0; b < 8; b++) t[v] |= ((v >> b) & 1U) << (3 * b);
  return t;
}
constexpr std::array<std::uint32_t, 256> kSpread = makeSpreadTable();

/// The axis with the smallest t (ties as in OcTreeBaseImpl::computeRayKeys).
inline unsigned argMin(double tx, double ty, double tz)
{
  const bool x_lt_y = tx < ty;
  const double t_xy = x_lt_y ? tx : ty;
  return t_xy < tz ? (x_lt_y ? 0U : 1U) : 2U;
}

/// LSD radix sort of 49-bit values, 11 bits per pass; passes whose digit is
/// the same for every value are skipped.
void radixSort(std::vector<std::uint64_t>& v)
{
  constexpr unsigned kBits = 11, kPasses = 5, kBuckets = 1U << kBits;
  std::vector<std::array<std::uint32_t, kBuckets>> hist(kPasses);
  for (auto& h : hist) h.fill(0);
  for (const std::uint64_t x : v)
    for (unsigned p = 0; p < kPasses; p++) hist[p][(x >> (p * kBits)) & (kBuckets - 1)]++;
  std::vector<std::uint64_t> tmp(v.size());
  for (unsigned p = 0; p < kPasses; p++)
  {
    auto& h = hist[p];
    if (std::any_of(h.begin(), h.end(), [&](std::uint32_t n) { return n == v.size(); })) continue;
    std::uint32_t sum = 0;
    for (auto& n : h) sum += std::exchange(n, sum);  // exclusive prefix sums
    for (const std::uint64_t x : v) tmp[h[(x >> (p * kBits)) & (kBuckets - 1)]++] = x;
    v.swap(tmp);
  }
}

/// OccupancyOcTreeBase::updateNode's early abort: the value is already at
/// the clamping bound the update pushes towards.
inline bool updateIsNoOp(float log_odds, bool hit, float clamp_min, float clamp_max)
{
  return hit ? log_odds >= clamp_max : log_odds <= clamp_min;
}

/// The depth-first batched update of applyBatch().
struct BatchWalker
{
  LayerTree& tree;
  float hit_log, miss_log, clamp_min, clamp_max;

  bool allNoOps(float log_odds, const std::uint64_t* b, const std::uint64_t* e) const
  {
    return std::all_of(b, e,
                       [&](std::uint64_t x)
                       { return updateIsNoOp(log_odds, x & 1U, clamp_min, clamp_max); });
  }

  /// Updates the subtree of `node` (at `depth`) with the entries [b, e),
  /// all of which lie in it. Mirrors OccupancyOcTreeBase::updateNodeRecurs.
  void walk(octomap::OcTreeNode* node, bool just_created, const std::uint64_t* b,
            const std::uint64_t* e, unsigned depth)
  {
    if (depth == kTreeDepth)  // a leaf voxel: exactly one entry
    {
      const bool hit = *b & 1U;
      if (!just_created && updateIsNoOp(node->getLogOdds(), hit, clamp_min, clamp_max)) return;
      tree.updateNodeLogOdds(node, hit ? hit_log : miss_log);
      return;
    }
    if (!just_created && !tree.nodeHasChildren(node))  // a pruned (coarse) leaf
    {
      if (allNoOps(node->getLogOdds(), b, e)) return;
      tree.expandNode(node);
    }
    const unsigned shift = 1 + 3 * (kTreeDepth - 1 - depth);
    for (const std::uint64_t* it = b; it != e;)
    {
      const std::uint64_t prefix = *it >> shift;
      const std::uint64_t* run_end = std::lower_bound(it, e, (prefix + 1) << shift);
      const unsigned pos = static_cast<unsigned>(prefix & 7U);
      bool created = false;
      if (!tree.nodeChildExists(node, pos))
      {
        tree.createNodeChild(node, pos);
        created = true;
      }
      walk(tree.getNodeChild(node, pos), created, it, run_end, depth + 1);
      it = run_end;
    }
    if (!tree.pruneNode(node)) node->updateOccupancyChildren();
  }
};
}  // namespace

octomap::OcTreeNode* LayerTree::rootForUpdate(bool& created)
{
  created = false;
  if (root == nullptr)
  {
    root = new octomap::OcTreeNode();
    tree_size++;
    created = true;
  }
  return root;
}

std::uint64_t mortonOf(const octomap::OcTreeKey& key)
{
  auto spread = [](unsigned v) -> std::uint64_t
  { return kSpread[v & 0xFFU] | (static_cast<std::uint64_t>(kSpread[v >> 8]) << 24); };
  return spread(key[0]) | (spread(key[1]) << 1) | (spread(key[2]) << 2);
}

bool coordToKeySafe(const octomap::OcTree& tree, const octomap::point3d& p, octomap::OcTreeKey& key)
{
  // The tree spans +-2^(depth-1) voxels around the origin.
  const double half_extent = tree.getResolution() * static_cast<double>(1U << (kTreeDepth - 1));
  for (unsigned i = 0; i < 3; i++)
    if (!(std::abs(static_cast<double>(p(i))) < half_extent)) return false;  // NaN fails too
  return tree.coordToKeyChecked(p, key);
}

bool clipRay(const octomap::point3d& origin, const octomap::point3d& p, double max_range_m,
             octomap::point3d& end)
{
  if ((p - origin).norm() <= max_range_m)
  {
    end = p;
    return true;
  }
  const octomap::point3d direction = (p - origin).normalized();
  end = origin + direction * static_cast<float>(max_range_m);
  return false;
}

RayKeyCollector::RayKeyCollector(const octomap::OcTree& tree)
    : tree_(tree),
      entries_(std::size_t{1} << 16),
      cache_(std::size_t{1} << kCacheBits, std::numeric_limits<std::uint64_t>::max())
{
}

inline void RayKeyCollector::push(std::uint64_t entry)
{
  const std::size_t slot = (entry * 0x9E3779B97F4A7C15ULL) >> (64 - kCacheBits);
  if (cache_[slot] == entry) return;
  cache_[slot] = entry;
  entries_[size_++] = entry;  // room reserved by reserveForRay()
}

void RayKeyCollector::reserveForRay(float length)
{
  // A DDA step moves one voxel along one axis: at most 3 * (length / res + 2) steps.
  const auto steps = static_cast<std::size_t>(3.0 * (length / tree_.getResolution() + 2.0)) + 2;
  if (size_ + steps > entries_.size())
    entries_.resize(std::max(2 * entries_.size(), size_ + steps));
}

std::vector<std::uint64_t> RayKeyCollector::release()
{
  entries_.resize(size_);
  size_ = 0;
  return std::move(entries_);
}

bool RayKeyCollector::addRay(const octomap::point3d& origin, const octomap::point3d& end, bool hit)
{
  octomap::OcTreeKey key_origin, key_end;
  if (!coordToKeySafe(tree_, end, key_end)) return false;
  octomap::point3d direction = end - origin;
  const float length = static_cast<float>(direction.norm());
  reserveForRay(length);
  const std::uint64_t code_end = mortonOf(key_end);
  if (hit) push((code_end << 1) | 1U);
  if (!coordToKeySafe(tree_, origin, key_origin)) return false;
  if (key_origin == key_end) return true;

  // Initialisation exactly as OcTreeBaseImpl::computeRayKeys (Amanatides & Woo),
  // so that both insertions visit the same voxels.
  std::uint64_t code = mortonOf(key_origin);
  push(code << 1);
  direction /= length;
  DdaAxes ax;
  const double res = tree_.getResolution();
  for (unsigned i = 0; i < 3; i++)
  {
    const bool up = direction(i) > 0.0f;
    // ((code & and_mask) | or_mask) + inc, masked, steps the axis field by +-1.
    ax.and_mask[i] = up ? ~std::uint64_t{0} : kAxisMask[i];
    ax.or_mask[i] = up ? ~kAxisMask[i] : 0;
    ax.inc[i] = up ? 1 : ~std::uint64_t{0};
    if (direction(i) != 0.0f)
    {
      double border = tree_.keyToCoord(key_origin[i]);
      border += static_cast<float>((up ? 1 : -1) * res * 0.5);
      ax.t_max[i] = (border - origin(i)) / direction(i);
      ax.t_delta[i] = res / std::fabs(direction(i));
    }
    else
    {
      ax.t_max[i] = std::numeric_limits<double>::max();
      ax.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  walkDda(ax, code, code_end, length);
  return true;
}

void RayKeyCollector::walkDda(const DdaAxes& ax, std::uint64_t code, std::uint64_t code_end,
                              double length)
{
  // Incremental phase on the Morton code, t_max kept in registers.
  double tx = ax.t_max[0], ty = ax.t_max[1], tz = ax.t_max[2];
  unsigned dim = argMin(tx, ty, tz);
  while (true)
  {
    const std::uint64_t mask = kAxisMask[dim];
    code = ((((code & ax.and_mask[dim]) | ax.or_mask[dim]) + ax.inc[dim]) & mask) | (code & ~mask);
    tx += dim == 0 ? ax.t_delta[0] : 0.0;
    ty += dim == 1 ? ax.t_delta[1] : 0.0;
    tz += dim == 2 ? ax.t_delta[2] : 0.0;
    if (code == code_end) break;
    dim = argMin(tx, ty, tz);
    // Past the end point without reaching its voxel (discretisation): stop.
    if ((dim == 0 ? tx : dim == 1 ? ty : tz) > length) break;
    push(code << 1);
  }
}

std::pair<std::size_t, std::size_t> sortUnique(std::vector<std::uint64_t>& entries)
{
  radixSort(entries);
  std::size_t out = 0, n_free = 0, n_occ = 0;
  for (std::size_t i = 0; i < entries.size();)
  {
    std::size_t j = i + 1;
    while (j < entries.size() && (entries[j] >> 1) == (entries[i] >> 1)) j++;
    const std::uint64_t kept = entries[j - 1];  // the hit (odd) sorts last
    (kept & 1U) ? n_occ++ : n_free++;
    entries[out++] = kept;
    i = j;
  }
  entries.resize(out);
  return {n_free, n_occ};
}

void applyBatch(LayerTree& tree, const std::vector<std::uint64_t>& entries)
{
  if (entries.empty()) return;
  BatchWalker walker{tree, tree.getProbHitLog(), tree.getProbMissLog(),
                     tree.getClampingThresMinLog(), tree.getClampingThresMaxLog()};
  bool created = false;
  octomap::OcTreeNode* root = tree.rootForUpdate(created);
  walker.walk(root, created, entries.data(), entries.data() + entries.size(), 0);
}

}  // namespace voxplore::mapping::detail
