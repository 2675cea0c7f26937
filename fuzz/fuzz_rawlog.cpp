/* voxplore fuzz target: our rawlog reader (libs/common forEachRawlogEntry),
 * which hands the stream to MRPT's CArchive::ReadObject (plain or gzip), with
 * its protection on: every object is parsed first in a forked child process
 * (rawlog_objects.cpp), so bytes that crash MRPT or make it allocate GBs
 * (fuzz/mrpt_crashes/) are errors, not crashes. The input is written to a
 * per-process file under /dev/shm (or $TMPDIR) so the real entry point runs,
 * gzip detection included. Inputs come from plain byte mutation and from the
 * structure-aware mutator in rawlog_mutator.cpp, half each. Contract under
 * test: any bytes either yield entries, each with a sensory frame, or throw
 * std::runtime_error (RawlogError for corrupt ones), never crash, leak or hang. */

#include <mrpt/obs/CObservation.h>
#include <unistd.h>
#include <voxplore/common/rawlog_io.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace
{
std::string scratchPath()
{
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
  return (dir / ("voxplore_fuzz_rawlog_" + std::to_string(::getpid()) + ".rawlog")).string();
}

const std::string& path()
{
  static const std::string p = scratchPath();
  return p;
}

void removeScratch()
{
  std::remove(path().c_str());
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const bool registered = (std::atexit(removeScratch), true);
  (void)registered;
  {
    std::ofstream out(path(), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  // The child's limits: far below libFuzzer's -rss_limit_mb / -malloc_limit_mb
  // and -timeout, so MRPT's faults end in the child, never in this process.
  voxplore::common::RawlogReadOptions opts;
  opts.object_memory_mb = 32;
  opts.object_timeout_ms = 1000;
  opts.fresh_child_when_threaded = false;  // libFuzzer's watchdog thread holds no lock the child needs
  try
  {
    std::size_t observations = 0;
    voxplore::common::forEachRawlogEntry(path(),
                                         [&](const voxplore::common::RawlogEntry& e)
                                         {
                                           if (!e.observations)
                                           {
                                             __builtin_trap();  // every entry has a sensory frame
                                           }
                                           for (const auto& obs : *e.observations)
                                           {
                                             observations += obs ? 1 : 0;
                                           }
                                           return true;
                                         },
                                         opts);
  }
  catch (const std::runtime_error& e)
  {
    // The guard itself must work on every call: a pipe or fork that fails
    // (descriptors or processes leaking across calls) would otherwise hide
    // as an ordinary error and silently stop the fuzzing.
    // Match the reader's own message from its start: the input's bytes can
    // appear inside other messages (libFuzzer once wrote ": pipe: " into a
    // corrupt string that MRPT's error quoted).
    const std::string msg = e.what();
    const std::string own = "cannot read '" + path() + "': ";
    if (msg.rfind(own + "pipe: ", 0) == 0 || msg.rfind(own + "fork: ", 0) == 0)
    {
      __builtin_trap();
    }
  }
  return 0;
}
