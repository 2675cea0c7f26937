/* voxplore — writing and reading MRPT rawlog files. */
#pragma once

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <fstream>
#include <functional>
#include <memory>
#include <cstdint>
#include <stdexcept>
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

/// @brief A rawlog that cannot be read to its end. what() is one line,
///        "FILE: entry K (byte offset X): REASON"; details() keeps the whole
///        text (MRPT's exception with its backtrace, or how the parse process
///        died) for a --verbose report.
class RawlogError : public std::runtime_error
{
 public:
  RawlogError(const std::string& one_line, std::string details, std::size_t entry,
              std::uint64_t byte_offset)
      : std::runtime_error(one_line),
        details_(std::move(details)),
        entry_(entry),
        byte_offset_(byte_offset)
  {
  }
  /// @brief MRPT's full message (backtrace included); empty when there is none.
  const std::string& details() const { return details_; }
  /// @brief Index of the entry that could not be read (= entries read before it).
  std::size_t entry() const { return entry_; }
  /// @brief Where the faulty object starts, in the decompressed stream for gzip.
  std::uint64_t byteOffset() const { return byte_offset_; }

 private:
  std::string details_;
  std::size_t entry_;
  std::uint64_t byte_offset_;
};

/// @brief How forEachRawlogEntry protects itself from MRPT's deserialisation,
///        which is not safe on corrupt bytes (fuzz/README.md): with `isolate`,
///        a forked child process parses every object first, under the limits
///        below, and this process parses only objects the child read whole.
///        The child is a fork() of a single-threaded caller; a caller with
///        more threads gets this program started afresh (/proc/self/exe with
///        VOXPLORE_RAWLOG_CHILD set, taken over by a library constructor
///        before main()), because a forked child can deadlock on a lock
///        another thread held (seen under ASan). The caller must not reap
///        the child (waitpid(-1), SIGCHLD ignored).
struct RawlogReadOptions
{
  bool isolate = true;  ///< parse in a forked child first (off: MRPT may crash us)
  /// Address space [MB] the child may add while it parses (a corrupt length
  /// field makes MRPT allocate GBs before it reads anything).
  std::size_t object_memory_mb = 1024;
  unsigned object_timeout_ms = 60000;  ///< wall time [ms] the child may spend on one object
  bool child_output = false;       ///< keep the child's stdout/stderr (debugging)
  /// With other threads in this process, start the child as a fresh process
  /// (see above); false: fork() anyway, for a caller that knows its other
  /// threads hold no lock the child needs (the fuzzer: libFuzzer's watchdog
  /// thread; a fresh process per input cut it from 20-37 to 5 exec/s).
  bool fresh_child_when_threaded = true;
};

/// @brief Reads a rawlog entry by entry (streaming, constant memory). Any
///        bytes end in entries or in an exception, never in a crash (with
///        opts.isolate, the default).
/// @param visit return false to stop early
/// @return the number of entries read
/// @throws std::runtime_error naming the path when the file is missing, empty
///         or unreadable; RawlogError naming the path, entry and byte offset
///         when it is corrupt or truncated. Entries before the fault were visited.
std::size_t forEachRawlogEntry(const std::string& path,
                               const std::function<bool(const RawlogEntry&)>& visit,
                               const RawlogReadOptions& opts = {});

/// @brief Reads a rawlog's top-level objects in file order (what
///        forEachRawlogEntry pairs into entries), with the same protection.
/// @param visit gets each object (null for MRPT's null object) and the byte
///        offset where it starts; return false to stop early
/// @return the number of objects read
/// @throws like forEachRawlogEntry; RawlogError::entry() is then the index of
///         the object that could not be read.
std::size_t forEachRawlogObject(
    const std::string& path,
    const std::function<bool(const mrpt::serialization::CSerializable::Ptr&, std::uint64_t)>& visit,
    const RawlogReadOptions& opts = {});

/// @brief One line for an exception text: the "Message:" lines of MRPT's
///        nested exceptions joined by ": " (its what() holds whole backtraces),
///        else the first non-empty line; trimmed, at most about 300 characters.
std::string summaryLineOf(const std::string& text);

}  // namespace voxplore::common
