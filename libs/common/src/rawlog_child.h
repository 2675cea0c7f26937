/* voxplore — the process that deserialises a rawlog ahead of its reader
 * (internal to libs/common: rawlog_objects.cpp reads, rawlog_child.cpp starts
 * and limits the process). */
#pragma once

#include <sys/types.h>
#include <voxplore/common/rawlog_io.h>

#include <string>

namespace voxplore::common::detail
{
/// @brief Starts the child that parses `path` ahead of the reader and writes
///        a record per object to `write_fd`: a fork() of a single-threaded
///        caller; with other threads (and opts.fresh_child_when_threaded)
///        this program started afresh (posix_spawn of /proc/self/exe with
///        VOXPLORE_RAWLOG_CHILD set, taken over by a library constructor
///        before main()), because a forked child can deadlock on a lock
///        another thread held (seen under ASan).
/// @param read_fd the reader's end, closed in a forked child
/// @return the child's pid, or -1 with errno set (the caller closes both ends)
pid_t startChild(const std::string& path, int write_fd, int read_fd, const RawlogReadOptions& opts);

/// @brief The child's side (rawlog_objects.cpp): parses `path` object by
///        object, each under opts.object_timeout_ms, and writes a record per
///        object to `fd` until the end, an error or the reader is gone.
[[noreturn]] void childMain(const std::string& path, int fd, pid_t parent,
                            const RawlogReadOptions& opts) noexcept;

/// @brief The child's process settings, first thing in childMain(): dies
///        with the reader (and exits if it is gone already), ignores SIGINT,
///        dies by any fault signal (the reader names it), clears the
///        sanitizers' death callback, silences its output unless
///        opts.child_output, and may grow by opts.object_memory_mb at most.
void prepareChild(pid_t parent, const RawlogReadOptions& opts);

/// @brief SIGALRM (default action: the child dies, the reader names it)
///        after `ms`; 0 cancels.
void setAlarm(unsigned ms);

/// @brief Why the child ended without a verdict on the object it was reading.
std::string describeChildEnd(int status, const RawlogReadOptions& opts);

}  // namespace voxplore::common::detail
