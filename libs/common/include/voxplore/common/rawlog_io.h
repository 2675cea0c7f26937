/* voxplore — writing and reading MRPT rawlog files. */
#pragma once

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <fstream>
#include <functional>
#include <memory>
#include <string>

namespace voxplore::common
{
/// @brief Appends (CActionCollection, CSensoryFrame) pairs to a rawlog
///        (readable by rawlog-edit, RawLogViewer and CRawlog). Written
///        uncompressed and flushed after each pair, so a crash leaves every
///        stop written so far readable (MRPT's file streams cannot flush,
///        so each pair is serialised to memory and written through std::ofstream).
///        Readers accept plain and gzip-compressed rawlogs alike.
class RawlogWriter
{
 public:
  /// @throws std::runtime_error naming the path when it cannot be created.
  explicit RawlogWriter(const std::string& path);
  ~RawlogWriter();
  void write(const mrpt::obs::CActionCollection& actions, const mrpt::obs::CSensoryFrame& sf);
  std::size_t entries() const { return entries_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ofstream out_;
  std::size_t entries_ = 0;
};

/// @brief One entry of a rawlog in (action, sensory frame) form. A rawlog in
///        observation-only format yields one entry per observation with
///        `actions` empty.
struct RawlogEntry
{
  std::size_t index = 0;
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr observations;
};

/// @brief Reads a rawlog entry by entry (streaming, constant memory).
/// @param visit return false to stop early
/// @return the number of entries read
/// @throws std::runtime_error naming the path and entry index when the file is
///         missing, empty or corrupt; entries before the fault were visited.
std::size_t forEachRawlogEntry(
    const std::string& path, const std::function<bool(const RawlogEntry&)>& visit);

}  // namespace voxplore::common
