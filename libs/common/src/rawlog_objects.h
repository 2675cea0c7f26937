/* voxplore — reading a rawlog's top-level objects, guarded by a child process
 * (internal to libs/common; forEachRawlogEntry pairs the objects into entries). */
#pragma once

#include <mrpt/serialization/CSerializable.h>
#include <voxplore/common/rawlog_io.h>

#include <cstdint>
#include <memory>
#include <string>

namespace voxplore::common::detail
{
/// One top-level object of a rawlog, the clean end of the file, or why neither.
struct ObjectRead
{
  enum class Kind : std::uint32_t
  {
    Object = 1,
    End = 2,
    Failed = 3
  };
  Kind kind = Kind::End;
  mrpt::serialization::CSerializable::Ptr object;  ///< null unless Kind::Object
  std::uint64_t begin = 0;  ///< byte offset where the object starts (decompressed stream)
  std::uint64_t end = 0;    ///< byte offset after it (Kind::Object)
  std::string reason;       ///< one line (Kind::Failed)
  std::string details;      ///< the whole text behind `reason`, e.g. MRPT's backtrace
};

/// @brief Reads a rawlog's top-level objects one by one, plain or gzip.
///        With RawlogReadOptions::isolate, a child process forked by the
///        constructor reads the same file ahead of this one (memory limit,
///        per-object timeout, silenced output) and reports each object over a
///        pipe; next() deserialises an object only after the child read it
///        whole. A child killed by a signal (MRPT's null dereferences) or
///        stopped by a limit becomes a Failed result here, never a crash.
class ObjectReader
{
 public:
  /// @throws std::runtime_error when the file cannot be opened or the child not started.
  ObjectReader(const std::string& path, const RawlogReadOptions& opts);
  /// Kills and reaps the child if it still runs; closes the pipe.
  ~ObjectReader();
  ObjectReader(const ObjectReader&) = delete;
  ObjectReader& operator=(const ObjectReader&) = delete;

  /// @brief The next object; after End or Failed, call it no more.
  ObjectRead next();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace voxplore::common::detail
