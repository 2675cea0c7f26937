/* voxplore — the voxel window of one scan rating (private to
 * libs/exploration): a dense 16-bit cell per voxel of the rating's key
 * bounding box, filled lazily from the octree one 8x8x8 block at a time.
 *
 * Cell bits: 15..10 epoch of the rating that filled it (an older epoch means
 * "not filled yet"), 9 counted in this rating (set when filled outside the
 * counting band: never counted), 8 stops a beam (above
 * th_occ), 7..0 occupancy class (0 = unknown, 1..254 = a log-odds value
 * interned in this rating, 255 = more distinct values than that: entropy
 * from the tree). */
#pragma once

#include <octomap/OcTree.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <unordered_map>

namespace voxplore::exploration::detail
{
constexpr uint32_t kClassMask = 0xFF;
constexpr uint32_t kOverflow = 0xFF;
constexpr uint32_t kStop = 0x100;
constexpr uint32_t kVisited = 0x200;
constexpr int kEpochShift = 10;

/// @brief Running totals of one rating.
struct Tally
{
  std::size_t voxels = 0, unknown = 0;
  double gain = 0;
};

/// @brief Per-thread window storage, reused across ratings; the epochs make
///        what an earlier rating left invisible to the next.
struct WindowStorage
{
  std::unique_ptr<uint16_t[]> cells;
  std::size_t capacity = 0;
  uint32_t epoch = 0;
};

/// @brief The cells of one rating over the key box starting at `kmin`
///        (8-aligned) with n[0] x n[1] x n[2] cells (multiples of 8).
class VoxelWindow
{
 public:
  /// `count_kz` [lo, hi]: the absolute z keys whose voxels are counted.
  VoxelWindow(const octomap::OcTree& V, float stop_log_odds, const octomap::OcTreeKey& kmin,
              const std::size_t n[3], WindowStorage& storage,
              const uint32_t count_kz[2] = kCountAll);
  static constexpr uint32_t kCountAll[2] = {0u, 0xFFFFu};

  std::size_t addrOf(const octomap::OcTreeKey& k) const
  {
    return (k[0] - origin_[0]) + nx_ * (k[1] - origin_[1]) + nxy_ * (k[2] - origin_[2]);
  }
  /// Address step of one voxel along axis 0, 1, 2.
  std::ptrdiff_t stride(int axis) const
  {
    return static_cast<std::ptrdiff_t>(axis == 0 ? 1 : (axis == 1 ? nx_ : nxy_));
  }
  uint16_t* cells() const { return cells_; }
  /// Cells filled in this rating lie in [epochBase(), epochBase() + 1024).
  uint32_t epochBase() const { return epoch_ << kEpochShift; }
  /// Classes interned so far (1..classCount() are valid).
  uint32_t classCount() const { return classes_; }
  /// Entropy [nats] per class; [0] = unknown (ln 2).
  const double* entropy() const { return entropy_; }

  /// @brief Several ratings in one window (rateScans): the voxels each
  ///        counts are logged into `log` (room for every voxel its beams can
  ///        step on), so that forgetCounted() clears their counted bits and
  ///        the next rating finds the filled blocks still there.
  void logCounted(uint32_t* log)
  {
    log_ = log;
    log_n_ = 0;
  }
  uint32_t* countedLog() const { return log_; }
  std::size_t countedCount() const { return log_n_; }
  void setCountedCount(std::size_t n) { log_n_ = n; }
  /// Uncounts what the logged voxels counted; the log starts again.
  void forgetCounted()
  {
    for (std::size_t i = 0; i < log_n_; i++)
      cells_[log_[i]] = static_cast<uint16_t>(cells_[log_[i]] & ~kVisited);
    log_n_ = 0;
  }

  /// @brief Counts the voxel at `addr` if not yet counted (filling its block
  ///        first if needed).
  /// @return true when the voxel stops a beam
  bool visit(std::size_t addr, Tally& t)
  {
    uint32_t c = cells_[addr];
    if (c - epochBase() >= (1u << kEpochShift)) c = fill(addr);
    if (!(c & kVisited))
    {
      cells_[addr] = static_cast<uint16_t>(c | kVisited);
      if (log_) log_[log_n_++] = static_cast<uint32_t>(addr);
      const uint32_t cls = c & kClassMask;
      t.voxels++;
      t.unknown += cls == 0;
      t.gain += cls != kOverflow ? entropy_[cls] : entropyFromTree(addr);
    }
    return c & kStop;
  }

 private:
  octomap::OcTreeKey keyOf(std::size_t addr) const;
  uint32_t fill(std::size_t addr);
  void fillNode(const octomap::OcTreeNode* node, std::size_t corner, std::size_t size);
  void fillBox(std::size_t corner, std::size_t size, uint16_t code);
  /// Cell code of a known voxel (its log-odds interned on first sight).
  uint16_t codeOf(const octomap::OcTreeNode* node)
  {
    const float l = node->getLogOdds();
    uint32_t bits;
    std::memcpy(&bits, &l, sizeof bits);
    return bits == last_bits_ ? last_code_ : internCode(l, bits);
  }
  uint16_t internCode(float l, uint32_t bits);
  double entropyFromTree(std::size_t addr) const;

  const octomap::OcTree& V_;
  const float stop_log_odds_;
  const std::size_t nx_, nxy_;
  uint32_t origin_[3];  ///< absolute key of cell 0
  uint32_t count_kz_[2];  ///< z keys counted: [lo, hi]
  uint16_t* cells_;
  uint32_t epoch_;
  double entropy_[256];
  uint32_t classes_ = 0;
  std::unordered_map<uint32_t, uint32_t> code_of_;  ///< float bits -> class | stop
  uint32_t last_bits_ = 0xFFFFFFFFu;                ///< a NaN pattern OctoMap never stores
  uint16_t last_code_ = 0;
  uint32_t* log_ = nullptr;  ///< counted voxels' addresses (logCounted), or none
  std::size_t log_n_ = 0;
};

}  // namespace voxplore::exploration::detail
