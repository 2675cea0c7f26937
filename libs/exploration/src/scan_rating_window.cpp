/* voxplore — lazy filling of the scan rating's voxel window from the octree. */
#include "scan_rating_window.h"

#include <algorithm>

#include "scan_rating_beams.h"

namespace voxplore::exploration::detail
{
namespace
{
constexpr uint32_t kMaxEpoch = (1u << (16 - kEpochShift)) - 1;
}  // namespace

VoxelWindow::VoxelWindow(const octomap::OcTree& V, float stop_log_odds,
                         const octomap::OcTreeKey& kmin, const std::size_t n[3],
                         WindowStorage& storage, const uint32_t count_kz[2])
    : V_(V), stop_log_odds_(stop_log_odds), nx_(n[0]), nxy_(n[0] * n[1])
{
  count_kz_[0] = count_kz[0];
  count_kz_[1] = count_kz[1];
  for (int i = 0; i < 3; i++) origin_[i] = kmin[i];
  const std::size_t cells = n[0] * n[1] * n[2];
  if (cells > storage.capacity)
  {
    storage.cells = std::make_unique<uint16_t[]>(cells);  // zero: epoch 0, never filled
    storage.capacity = cells;
    storage.epoch = 0;
  }
  if (++storage.epoch > kMaxEpoch)
  {
    std::fill_n(storage.cells.get(), storage.capacity, uint16_t(0));
    storage.epoch = 1;
  }
  cells_ = storage.cells.get();
  epoch_ = storage.epoch;
  std::fill(std::begin(entropy_), std::end(entropy_), 0.0);
  entropy_[0] = unknownEntropy();
}

octomap::OcTreeKey VoxelWindow::keyOf(std::size_t addr) const
{
  return octomap::OcTreeKey(static_cast<octomap::key_type>(origin_[0] + addr % nx_),
                            static_cast<octomap::key_type>(origin_[1] + addr % nxy_ / nx_),
                            static_cast<octomap::key_type>(origin_[2] + addr / nxy_));
}

uint32_t VoxelWindow::fill(std::size_t addr)
{
  const std::size_t x = addr % nx_, y = addr % nxy_ / nx_, z = addr / nxy_;
  const std::size_t corner =
      (x & ~std::size_t(7)) + nx_ * (y & ~std::size_t(7)) + nxy_ * (z & ~std::size_t(7));
  // The depth-13 node, a pruned ancestor leaf, or null (unknown): what
  // OcTree::search(key) finds for each voxel of the block.
  fillNode(V_.search(keyOf(corner), V_.getTreeDepth() - 3), corner, 8);
  // Layers outside the counting band are marked counted: never counted.
  const uint32_t kz0 = origin_[2] + static_cast<uint32_t>(z & ~std::size_t(7));
  for (std::size_t dz = 0; dz < 8; dz++)
  {
    const uint32_t kz = kz0 + static_cast<uint32_t>(dz);
    if (kz >= count_kz_[0] && kz <= count_kz_[1]) continue;
    for (std::size_t dy = 0; dy < 8; dy++)
    {
      uint16_t* row = cells_ + corner + nx_ * dy + nxy_ * dz;
      for (std::size_t dx = 0; dx < 8; dx++) row[dx] = static_cast<uint16_t>(row[dx] | kVisited);
    }
  }
  return cells_[addr];
}

void VoxelWindow::fillBox(std::size_t corner, std::size_t size, uint16_t code)
{
  for (std::size_t z = 0; z < size; z++)
    for (std::size_t y = 0; y < size; y++)
    {
      uint16_t* row = cells_ + corner + nx_ * y + nxy_ * z;
      for (std::size_t x = 0; x < size; x++) row[x] = code;
    }
}

void VoxelWindow::fillNode(const octomap::OcTreeNode* node, std::size_t corner, std::size_t size)
{
  const auto unknown = static_cast<uint16_t>(epoch_ << kEpochShift);
  if (!node || !V_.nodeHasChildren(node))
  {
    fillBox(corner, size, node ? codeOf(node) : unknown);
    return;
  }
  // A missing child of an inner node is unknown (search() returns null).
  // The children are fetched first: leaf nodes lie scattered on the heap,
  // and their loads then overlap instead of queueing behind each branch.
  const octomap::OcTreeNode* child[8];
  for (unsigned i = 0; i < 8; i++)
  {
    child[i] = V_.nodeChildExists(node, i) ? V_.getNodeChild(node, i) : nullptr;
    if (child[i]) __builtin_prefetch(child[i]);
  }
  const std::size_t h = size / 2;
  for (unsigned i = 0; i < 8; i++)
  {
    const std::size_t c = corner + (i & 1 ? h : 0) + (i & 2 ? h * nx_ : 0) + (i & 4 ? h * nxy_ : 0);
    if (h == 1)  // children are voxels: the common case near surfaces
      cells_[c] = child[i] ? codeOf(child[i]) : unknown;
    else
      fillNode(child[i], c, h);
  }
}

uint16_t VoxelWindow::internCode(float l, uint32_t bits)
{
  auto [it, inserted] = code_of_.try_emplace(bits, 0u);
  if (inserted)
  {
    uint32_t cls = kOverflow;
    if (classes_ + 1 < kOverflow)
    {
      cls = ++classes_;
      entropy_[cls] = entropyOfLogOdds(l);
    }
    it->second = cls | (l > stop_log_odds_ ? kStop : 0u);
  }
  last_bits_ = bits;
  return last_code_ = static_cast<uint16_t>((epoch_ << kEpochShift) | it->second);
}

double VoxelWindow::entropyFromTree(std::size_t addr) const
{
  return entropyOfLogOdds(V_.search(keyOf(addr))->getLogOdds());
}

}  // namespace voxplore::exploration::detail
