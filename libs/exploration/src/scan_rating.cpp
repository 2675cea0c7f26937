/* voxplore — entropy scan rating of a candidate pose (thesis 3.7, 4.5.4).
 *
 * A rating at 5 cm and beam_reduction 1 takes ~1.5 M voxel steps (24,576
 * beams; a voxel is crossed ~6 times on average, far more near the cameras)
 * over ~250 k distinct voxels in ~2,000 of the octree's 8x8x8-voxel nodes. So:
 *  - voxels are looked up in a dense window of 16-bit cells over the rating's
 *    key box (scan_rating_window.h), filled lazily a depth-13 node at a time:
 *    one tree search per block instead of one per step, and the cell's
 *    "counted" bit is the distinct-voxel set (no hashing, nothing to clear);
 *  - each beam's DDA repeats OcTree::computeRayKeys' arithmetic exactly, so
 *    ours and rateScanNaive count the same voxels; the DDA set-ups (nine
 *    divisions each) are done in batches of 64 beams;
 *  - where the CPU has AVX2 four beams step together in vector registers and
 *    their cells are handled without branches (scan_rating_avx2.cpp); else
 *    one beam at a time (walkBeamsScalar).
 * Measured at 5 cm, beam_reduction 1, one core (bench_scan_rating): a hash
 * set of keys plus a hash-map cache of voxel values, one beam at a time,
 * ~18 ms per rating; the window, one beam at a time, ~12-16 ms; four AVX2
 * lanes, ~6.2 ms; the naive stock-OctoMap rating ~110 ms.
 */
#include <octomap/OcTree.h>

#include <algorithm>
#include <cstdlib>
#include <limits>

#include "scan_rating_walk.h"

namespace voxplore::exploration
{
namespace detail
{
namespace
{
/// Sets up a beam's DDA as computeRayKeys does.
void setUpDda(const octomap::OcTree& V, const VirtualBeam& beam, const octomap::OcTreeKey& ko,
              const VoxelWindow& w, BeamDda& s)
{
  octomap::point3d direction = beam.end - beam.origin;
  const float length = static_cast<float>(direction.norm());
  direction /= length;
  s.length = length;
  const double res = V.getResolution();
  for (int i = 0; i < 3; i++)
  {
    const int step = direction(i) > 0.0f ? 1 : (direction(i) < 0.0f ? -1 : 0);
    s.advance[i] = step * w.stride(i);
    if (step != 0)
    {
      double border = V.keyToCoord(ko[i]);
      border += static_cast<float>(step * res * 0.5);
      s.t_max[i] = (border - beam.origin(i)) / direction(i);
      s.t_delta[i] = res / std::fabs(direction(i));
    }
    else
    {
      s.t_max[i] = std::numeric_limits<double>::max();
      s.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
}

/// Larger windows (max_range_m beyond ~12 m at 5 cm) are rated by rateScanNaive.
constexpr std::size_t kMaxWindowCells = std::size_t(1) << 25;

/// Per-thread scratch reused across ratings.
struct Scratch
{
  WindowStorage window;
  RatedBeams beams;
  std::vector<RatedBeams> batch;  ///< rateScans: one per pose
  std::vector<uint32_t> counted;  ///< rateScans: the window's log of counted voxels
};
thread_local Scratch t_scratch;

/// rateScans shares a window while it is at most this many times the
/// largest single rating's (memory: 2 bytes a cell).
constexpr std::size_t kBatchWindowGrowth = 4;

/// The window box of beams keyed into [kmin, kmax]: 2 voxels of slack,
/// aligned to the 8-voxel blocks of depth 13. False when no beam is in the
/// tree.
bool windowBox(const RatedBeams& b, octomap::OcTreeKey& kmin, const octomap::OcTreeKey& kmax,
               std::size_t n[3])
{
  if (b.in_tree.empty()) return false;
  for (int d = 0; d < 3; d++)
  {
    kmin[d] = static_cast<octomap::key_type>(std::max(int(kmin[d]) - 2, 0) & ~7);
    const unsigned hi = std::min(unsigned(kmax[d]) + 2u, 0xFFFFu);
    n[d] = ((hi - kmin[d]) | 7u) + 1;
  }
  return true;
}

/// Voxels the beams of `b` can count at most: each beam's DDA steps once
/// per key it crosses, plus its first and last voxel and rounding slack.
std::size_t countBound(const RatedBeams& b)
{
  std::size_t n = 0;
  for (const uint32_t i : b.in_tree)
  {
    const octomap::OcTreeKey &ko = b.origin_keys[i], &ke = b.end_keys[i];
    for (int d = 0; d < 3; d++) n += static_cast<std::size_t>(std::abs(int(ke[d]) - int(ko[d])));
    n += 4;
  }
  return n;
}

/// Keys of the beams' ends into `b`; their bounding box in kmin / kmax.
void computeKeys(const octomap::OcTree& V, RatedBeams& b, octomap::OcTreeKey& kmin,
                 octomap::OcTreeKey& kmax)
{
  const std::size_t n = b.beams.size();
  b.origin_keys.resize(n);
  b.end_keys.resize(n);
  b.in_tree.clear();
  kmin = octomap::OcTreeKey(0xFFFF, 0xFFFF, 0xFFFF);
  kmax = octomap::OcTreeKey(0, 0, 0);
  octomap::OcTreeKey ko;
  bool origin_ok = false;
  for (std::size_t i = 0; i < n; i++)
  {
    const VirtualBeam& beam = b.beams[i];
    if (i == 0 || !(beam.origin == b.beams[i - 1].origin))  // once per camera
      origin_ok = V.coordToKeyChecked(beam.origin, ko);
    octomap::OcTreeKey& ke = b.end_keys[i];
    if (!origin_ok || !V.coordToKeyChecked(beam.end, ke))
      continue;  // outside the tree's key range: nothing to rate (as rateScanNaive)
    b.origin_keys[i] = ko;
    b.in_tree.push_back(static_cast<uint32_t>(i));
    for (int d = 0; d < 3; d++)
    {
      kmin[d] = std::min({kmin[d], ko[d], ke[d]});
      kmax[d] = std::max({kmax[d], ko[d], ke[d]});
    }
  }
}
}  // namespace

void BeamFeed::setUpBatch()
{
  size_ = 0;
  taken_ = 0;
  for (; size_ < kBatch && next_ < beams_.in_tree.size(); size_++, next_++)
  {
    const uint32_t i = beams_.in_tree[next_];
    const octomap::OcTreeKey& ko = beams_.origin_keys[i];
    const octomap::OcTreeKey& ke = beams_.end_keys[i];
    BeamDda& s = batch_[size_];
    s.addr = w_.addrOf(ko);
    s.end = w_.addrOf(ke);
    one_voxel_[size_] = ko == ke;
    if (!one_voxel_[size_]) setUpDda(V_, beams_.beams[i], ko, w_, s);
  }
}

bool BeamFeed::pop(VoxelWindow& w, Tally& tally, BeamDda& s)
{
  for (;;)
  {
    if (taken_ == size_)
    {
      setUpBatch();
      if (size_ == 0) return false;
    }
    const std::size_t k = taken_++;
    // computeRayKeys gives no key when origin and end share a voxel; the end
    // voxel is added. Otherwise the origin voxel comes first.
    if (one_voxel_[k])
      w.visit(batch_[k].end, tally);
    else if (!w.visit(batch_[k].addr, tally))
    {
      s = batch_[k];
      return true;
    }
  }
}

void finishBeam(BeamDda& s, VoxelWindow& w, Tally& tally)
{
  double* t = s.t_max;
  for (;;)
  {
    // computeRayKeys: x if tx < ty and tx < tz; else y if ty < tz; else z.
    const int a = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
    t[a] += s.t_delta[a];
    s.addr += s.advance[a];
    if (s.addr == s.end) break;
    // Rounding may step past the end voxel: stop where computeRayKeys stops.
    if (std::min(std::min(t[0], t[1]), t[2]) > s.length) break;
    if (w.visit(s.addr, tally)) return;
  }
  w.visit(s.end, tally);
}

void walkBeamsScalar(BeamFeed& feed, VoxelWindow& w, Tally& tally)
{
  BeamDda s;
  while (feed.pop(w, tally, s)) finishBeam(s, w, tally);
}

namespace
{
/// Walks the beams of `b` through `w` into a rating.
ScanRating walkAll(const octomap::OcTree& V, const RatedBeams& b, VoxelWindow& w)
{
  Tally tally;
  BeamFeed feed(V, b, w);
  // VOXPLORE_SCAN_RATING_PORTABLE (any value) forces the portable walker:
  // for tests and benchmarks on AVX2 machines.
  const bool portable = std::getenv("VOXPLORE_SCAN_RATING_PORTABLE") != nullptr;
  if (portable || !walkBeamsAvx2(feed, w, tally)) walkBeamsScalar(feed, w, tally);
  ScanRating out;
  out.beams = b.beams.size();
  out.voxels = tally.voxels;
  out.unknown_voxels = tally.unknown;
  out.gain = tally.gain;
  return out;
}
}  // namespace
}  // namespace detail

ScanRating rateScan(const octomap::OcTree& V, const mrpt::poses::CPose2D& pose,
                    const ScanRatingParams& p)
{
  detail::checkRatingParams(p);
  detail::Scratch& sc = detail::t_scratch;
  detail::virtualBeams(pose, p, sc.beams.beams);
  ScanRating out;
  out.beams = sc.beams.beams.size();

  // The keys' bounding box (plus DDA rounding slack) holds every voxel a
  // beam can visit.
  octomap::OcTreeKey kmin, kmax;
  detail::computeKeys(V, sc.beams, kmin, kmax);
  std::size_t n[3];
  if (!detail::windowBox(sc.beams, kmin, kmax, n)) return out;
  if (n[0] * n[1] * n[2] > detail::kMaxWindowCells) return rateScanNaive(V, pose, p);

  uint32_t count_kz[2] = {detail::VoxelWindow::kCountAll[0], detail::VoxelWindow::kCountAll[1]};
  if (p.countBand()) detail::countBandKeys(V, p, count_kz);
  detail::VoxelWindow window(V, detail::stopLogOdds(p.th_occ), kmin, n, sc.window, count_kz);
  return detail::walkAll(V, sc.beams, window);
}

std::vector<ScanRating> rateScans(const octomap::OcTree& V,
                                  const std::vector<mrpt::poses::CPose2D>& poses,
                                  const ScanRatingParams& p)
{
  std::vector<ScanRating> out;
  out.reserve(poses.size());
  const auto oneByOne = [&]
  {
    for (std::size_t i = out.size(); i < poses.size(); i++) out.push_back(rateScan(V, poses[i], p));
    return out;
  };
  if (poses.size() < 2) return oneByOne();
  detail::checkRatingParams(p);
  detail::Scratch& sc = detail::t_scratch;
  if (sc.batch.size() < poses.size()) sc.batch.resize(poses.size());
  // Each pose's beams and box; the union box.
  octomap::OcTreeKey umin(0xFFFF, 0xFFFF, 0xFFFF);
  unsigned umax[3] = {0, 0, 0};  // last key of the union (may pass 0xFFFF by the alignment)
  std::size_t largest = 0, bound = 0;
  bool any = false;
  for (std::size_t i = 0; i < poses.size(); i++)
  {
    detail::RatedBeams& b = sc.batch[i];
    detail::virtualBeams(poses[i], p, b.beams);
    octomap::OcTreeKey kmin, kmax;
    detail::computeKeys(V, b, kmin, kmax);
    std::size_t n[3];
    if (!detail::windowBox(b, kmin, kmax, n)) continue;
    any = true;
    largest = std::max(largest, n[0] * n[1] * n[2]);
    bound = std::max(bound, detail::countBound(b));
    for (int d = 0; d < 3; d++)
    {
      umin[d] = std::min(umin[d], kmin[d]);
      umax[d] = std::max(umax[d], static_cast<unsigned>(kmin[d] + n[d] - 1));
    }
  }
  if (!any) return oneByOne();  // nothing in the tree: rateScan's empty ratings
  std::size_t n[3];
  for (int d = 0; d < 3; d++) n[d] = umax[d] - umin[d] + 1;  // 8-aligned already
  const std::size_t cells = n[0] * n[1] * n[2];
  if (largest > detail::kMaxWindowCells || cells > detail::kMaxWindowCells ||
      cells > detail::kBatchWindowGrowth * largest)
    return oneByOne();

  uint32_t count_kz[2] = {detail::VoxelWindow::kCountAll[0], detail::VoxelWindow::kCountAll[1]};
  if (p.countBand()) detail::countBandKeys(V, p, count_kz);
  detail::VoxelWindow window(V, detail::stopLogOdds(p.th_occ), umin, n, sc.window, count_kz);
  sc.counted.resize(bound + 1);  // the four-lane walker writes one past the last kept
  window.logCounted(sc.counted.data());
  for (std::size_t i = 0; i < poses.size(); i++)
  {
    out.push_back(detail::walkAll(V, sc.batch[i], window));
    window.forgetCounted();
  }
  return out;
}

}  // namespace voxplore::exploration
