/* voxplore — the projection's reading of V (thesis 4.5.1, algorithm 2,
 * lines 2-17's column states): the grid's key box and the per-column tally
 * of the z band, kept by ProjectionCache from one step to the next so that
 * only the columns the map changed are visited again (issue 12). */
#include <octomap/OcTree.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "projection_columns.h"

namespace voxplore::exploration
{
struct ProjectionCache::State
{
  const octomap::OcTree* tree = nullptr;  ///< the V of the last tally
  mapping::KeyBox box;   ///< its grid's columns, z: the band
  int above_hi = 0;      ///< end key of the band above (box.hi[2]: none)
  float lo_free = 0, lo_occ = 0;  ///< its thresholds (log-odds)
  detail::ColumnTally tally;
  bool all_changed = true;  ///< also while a tally is under way (an exception leaves it set)
  mapping::KeyBox changed;  ///< where V changed since (markChanged)
  std::size_t full = 0, partial = 0;
};

ProjectionCache::ProjectionCache() : s_(std::make_unique<State>()) {}
ProjectionCache::~ProjectionCache() = default;
ProjectionCache::ProjectionCache(ProjectionCache&&) noexcept = default;
ProjectionCache& ProjectionCache::operator=(ProjectionCache&&) noexcept = default;
void ProjectionCache::markChanged(const mapping::KeyBox& keys) { s_->changed.extend(keys); }
void ProjectionCache::markAllChanged() { s_->all_changed = true; }
std::size_t ProjectionCache::fullTallies() const { return s_->full; }
std::size_t ProjectionCache::partialTallies() const { return s_->partial; }

namespace
{
using KeyTriple = std::array<int, 3>;
/// Half-open box of OctoMap keys: [lo, hi) per axis.
using KeyBox = mapping::KeyBox;
using detail::ColumnTally;

/// Visits every leaf of the subtree at `n` (depth `depth`, lowest key `start`)
/// that overlaps `box`, calling f(node, start, edge_in_voxels). Coarse
/// (pruned) leaves come once with their full edge; callers clip.
template <typename Fn>
void visitLeaves(const octomap::OcTree& t, const octomap::OcTreeNode* n, int depth,
                 const KeyTriple& start, const KeyBox& box, Fn&& f)
{
  const int edge = 1 << (static_cast<int>(t.getTreeDepth()) - depth);
  for (int a = 0; a < 3; ++a)
    if (start[a] >= box.hi[a] || start[a] + edge <= box.lo[a]) return;
  if (!t.nodeHasChildren(n))
  {
    f(n, start, edge);
    return;
  }
  const int half = edge >> 1;
  for (unsigned i = 0; i < 8; ++i)
  {
    if (!t.nodeChildExists(n, i)) continue;
    const KeyTriple child{start[0] + ((i & 1) ? half : 0), start[1] + ((i & 2) ? half : 0),
                          start[2] + ((i & 4) ? half : 0)};
    visitLeaves(t, t.getNodeChild(n, i), depth + 1, child, box, f);
  }
}

/// Smallest lower key (want_min) or largest upper key (exclusive) along
/// `axis` over all leaves: OcTree::getMetricMin/Max in keys, found by a
/// branch-and-bound descent instead of the const getters' full leaf scans.
void keyExtent(const octomap::OcTree& t, const octomap::OcTreeNode* n, int depth,
               const KeyTriple& start, int axis, bool want_min, int& best)
{
  const int edge = 1 << (static_cast<int>(t.getTreeDepth()) - depth);
  if (want_min ? start[axis] >= best : start[axis] + edge <= best) return;
  if (!t.nodeHasChildren(n))
  {
    best = want_min ? start[axis] : start[axis] + edge;
    return;
  }
  const int half = edge >> 1;
  const unsigned bit = 1u << axis;
  for (unsigned pass = 0; pass < 2; ++pass)  // the promising half first
  {
    const bool upper = want_min ? pass == 1 : pass == 0;
    for (unsigned i = 0; i < 8; ++i)
    {
      if (((i & bit) != 0) != upper || !t.nodeChildExists(n, i)) continue;
      KeyTriple child = start;
      for (int a = 0; a < 3; ++a)
        if (i & (1u << a)) child[a] += half;
      keyExtent(t, t.getNodeChild(n, i), depth + 1, child, axis, want_min, best);
    }
  }
}

/// Adds the leaves of V inside `region` (clipped to it) to `tally`, whose
/// columns are those of `box`: occupied voxels set the column's flag, free
/// ones add to its count unless `occupied_only`. Unknown ones add nothing.
void tallyInto(const octomap::OcTree& V, const KeyBox& box, const KeyBox& region, float lo_free,
               float lo_occ, bool occupied_only, ColumnTally& tally)
{
  if (!V.getRoot() || region.empty()) return;
  const int nx = box.hi[0] - box.lo[0];
  const auto visit = [&](const octomap::OcTreeNode* n, const KeyTriple& s, int edge)
  {
    const float v = n->getLogOdds();
    const bool occupied = v > lo_occ;
    if (!occupied && (occupied_only || v >= lo_free)) return;  // unknown: adds no free voxel
    KeyTriple lo, hi;
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::max(s[a], region.lo[a]);
      hi[a] = std::min(s[a] + edge, region.hi[a]);
    }
    const auto nz = static_cast<uint16_t>(hi[2] - lo[2]);
    for (int ky = lo[1]; ky < hi[1]; ++ky)
    {
      const std::size_t row = static_cast<std::size_t>(ky - box.lo[1]) * nx;
      for (int kx = lo[0]; kx < hi[0]; ++kx)
      {
        const std::size_t i = row + (kx - box.lo[0]);
        if (occupied)
          tally.occupied[i] = 1;
        else
          tally.free_count[i] = static_cast<uint16_t>(tally.free_count[i] + nz);
      }
    }
  };
  visitLeaves(V, V.getRoot(), 0, {0, 0, 0}, region, visit);
}

/// The columns of `band` (keys; z: the band) tallied over the band, and
/// their occupied flags over the band above it up to key `above_hi`
/// (exclusive; band.hi[2]: none): only its occupied voxels count; only
/// the columns and voxels inside `region`. Thresholds in log-odds.
void tallyBands(const octomap::OcTree& V, const KeyBox& band, int above_hi, float lo_free,
                float lo_occ, ColumnTally& tally, const KeyBox& region)
{
  KeyBox in_band = region, above = region;
  in_band.lo[2] = band.lo[2];
  in_band.hi[2] = band.hi[2];
  above.lo[2] = band.hi[2];
  above.hi[2] = above_hi;
  tallyInto(V, band, in_band, lo_free, lo_occ, false, tally);
  tallyInto(V, band, above, lo_free, lo_occ, true, tally);
}

}  // namespace

namespace detail
{
/// Grid key box: V's bounds plus margin and the robot column, in whole voxels.
KeyBox gridKeyBox(const octomap::OcTree& V, const octomap::OcTreeKey& robot, double margin_m)
{
  KeyBox b;
  b.lo = {robot[0], robot[1], 0};
  b.hi = {robot[0] + 1, robot[1] + 1, 0};
  if (const auto* root = V.getRoot())
  {
    for (int a = 0; a < 2; ++a)
    {
      keyExtent(V, root, 0, {0, 0, 0}, a, true, b.lo[a]);
      keyExtent(V, root, 0, {0, 0, 0}, a, false, b.hi[a]);
    }
  }
  const int margin = static_cast<int>(std::ceil(margin_m / V.getResolution() - 1e-9));
  const int key_end = 1 << V.getTreeDepth();
  for (int a = 0; a < 2; ++a)
  {
    b.lo[a] = std::max(0, b.lo[a] - margin);
    b.hi[a] = std::min(key_end, b.hi[a] + margin);
  }
  return b;
}

/// The tally of every column of `band`, from `cache` where V did not change
/// since its last tally (same tree, band and thresholds); the cache then
/// holds this one. Returns the tally to use (the cache's, or `local`).
const ColumnTally& tallyColumns(const octomap::OcTree& V, const KeyBox& band, int above_hi,
                                double th_free, double th_occ, ProjectionCache::State* c,
                                ColumnTally& local)
{
  const int nx = band.hi[0] - band.lo[0];
  const int ny = band.hi[1] - band.lo[1];
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  // Log-odds thresholds: comparing log-odds is comparing getOccupancy().
  const float lo_free = static_cast<float>(octomap::logodds(th_free));
  const float lo_occ = static_cast<float>(octomap::logodds(th_occ));
  KeyBox columns = band;
  columns.hi[2] = above_hi;
  const bool reuse = c && !c->all_changed && c->tree == &V &&
                     c->box.lo[2] == band.lo[2] && c->box.hi[2] == band.hi[2] &&
                     c->above_hi == above_hi && c->lo_free == lo_free && c->lo_occ == lo_occ;
  if (c) c->all_changed = true;  // until the tally below is complete
  if (!reuse)
  {
    ColumnTally& t = c ? c->tally : local;
    t.occupied.assign(n, 0);
    t.free_count.assign(n, 0);
    tallyBands(V, band, above_hi, lo_free, lo_occ, t, columns);
    if (!c) return local;
    ++c->full;
  }
  else
  {
    if (c->box.lo[0] != band.lo[0] || c->box.lo[1] != band.lo[1] || c->box.hi[0] != band.hi[0] ||
        c->box.hi[1] != band.hi[1])
    {
      // The grid grew (or moved): the old columns where the boxes overlap;
      // a column outside the old box had no leaf then (the box held V's
      // bounds), so whatever it holds now lies in the changed box.
      ColumnTally t;
      t.occupied.assign(n, 0);
      t.free_count.assign(n, 0);
      const int onx = c->box.hi[0] - c->box.lo[0];
      const int x0 = std::max(band.lo[0], c->box.lo[0]), x1 = std::min(band.hi[0], c->box.hi[0]);
      const int y0 = std::max(band.lo[1], c->box.lo[1]), y1 = std::min(band.hi[1], c->box.hi[1]);
      for (int ky = y0; ky < y1 && x0 < x1; ++ky)
      {
        const std::size_t from = static_cast<std::size_t>(ky - c->box.lo[1]) * onx + (x0 - c->box.lo[0]);
        const std::size_t to = static_cast<std::size_t>(ky - band.lo[1]) * nx + (x0 - band.lo[0]);
        std::copy_n(c->tally.occupied.begin() + static_cast<std::ptrdiff_t>(from), x1 - x0,
                    t.occupied.begin() + static_cast<std::ptrdiff_t>(to));
        std::copy_n(c->tally.free_count.begin() + static_cast<std::ptrdiff_t>(from), x1 - x0,
                    t.free_count.begin() + static_cast<std::ptrdiff_t>(to));
      }
      c->tally = std::move(t);
    }
    // The changed columns, counted again from scratch (none when the
    // changes lie outside the band and the band above).
    KeyBox redo = c->changed;
    for (int a = 0; a < 3; ++a)
    {
      redo.lo[a] = std::max(redo.lo[a], columns.lo[a]);
      redo.hi[a] = std::min(redo.hi[a], columns.hi[a]);
    }
    if (!redo.empty())
    {
      for (int ky = redo.lo[1]; ky < redo.hi[1]; ++ky)
      {
        const std::size_t row = static_cast<std::size_t>(ky - band.lo[1]) * nx;
        const auto a = static_cast<std::ptrdiff_t>(row + (redo.lo[0] - band.lo[0]));
        const auto b = static_cast<std::ptrdiff_t>(row + (redo.hi[0] - band.lo[0]));
        std::fill(c->tally.occupied.begin() + a, c->tally.occupied.begin() + b, uint8_t{0});
        std::fill(c->tally.free_count.begin() + a, c->tally.free_count.begin() + b, uint16_t{0});
      }
      redo.lo[2] = columns.lo[2];
      redo.hi[2] = columns.hi[2];
      tallyBands(V, band, above_hi, lo_free, lo_occ, c->tally, redo);
    }
    ++c->partial;
  }
  c->tree = &V;
  c->box = band;
  c->above_hi = above_hi;
  c->lo_free = lo_free;
  c->lo_occ = lo_occ;
  c->changed = KeyBox{};
  c->all_changed = false;
  return c->tally;
}

}  // namespace detail
}  // namespace voxplore::exploration
