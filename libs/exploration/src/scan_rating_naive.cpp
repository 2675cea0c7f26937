/* voxplore — the naive scan rating with stock OctoMap calls only: the
 * reference rateScan is tested and benchmarked against. */
#include <octomap/OcTree.h>

#include "scan_rating_beams.h"

namespace voxplore::exploration
{
// Why not OcTree::castRay to find where a beam stops: it cannot give the same
// voxels as the rating's definition (computeRayKeys of the whole beam, cut at
// the first voxel above th_occ).
//  - It stops at isNodeOccupied: the tree's threshold, and >= instead of >.
//  - Its range cut-off compares voxel centres with maxRange, not the beam
//    length, so it can stop one voxel early or late at the end of the beam.
//  - Its DDA adds the half voxel in double where computeRayKeys rounds it to
//    float: at 5 cm the two walks can pick different voxels at grid-edge ties.
//  - computeRayKeys(origin, castRay's end) walks to the hit voxel's centre, a
//    different line than the beam's.
// Hence one computeRayKeys per whole beam, one search() per key in order with
// the stop rule checked on the node itself.
ScanRating rateScanNaive(const octomap::OcTree& V, const mrpt::poses::CPose2D& pose,
                         const ScanRatingParams& p)
{
  detail::checkRatingParams(p);
  const float stop_log_odds = detail::stopLogOdds(p.th_occ);
  std::vector<detail::VirtualBeam> beams;
  detail::virtualBeams(pose, p, beams);

  ScanRating out;
  out.beams = beams.size();
  uint32_t count_kz[2] = {0u, 0xFFFFu};
  if (p.countBand()) detail::countBandKeys(V, p, count_kz);
  octomap::KeySet visited;
  octomap::KeyRay ray;
  for (const auto& beam : beams)
  {
    octomap::OcTreeKey end_key;
    if (!V.computeRayKeys(beam.origin, beam.end, ray) || !V.coordToKeyChecked(beam.end, end_key))
      continue;           // outside the tree's key range: nothing to rate
    ray.addKey(end_key);  // computeRayKeys leaves the end voxel out
    for (const octomap::OcTreeKey& key : ray)
    {
      const octomap::OcTreeNode* node = V.search(key);
      if (key[2] >= count_kz[0] && key[2] <= count_kz[1] && visited.insert(key).second)
      {
        out.voxels++;
        if (node)
          out.gain += detail::entropyOfLogOdds(node->getLogOdds());
        else
        {
          out.unknown_voxels++;
          out.gain += detail::unknownEntropy();
        }
      }
      if (node && node->getLogOdds() > stop_log_odds) break;  // this voxel counted
    }
  }
  return out;
}

}  // namespace voxplore::exploration
