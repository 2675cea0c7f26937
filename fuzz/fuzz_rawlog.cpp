/* voxplore fuzz target: our rawlog reader (libs/common forEachRawlogEntry),
 * which hands the stream to MRPT's CArchive::ReadObject (plain or gzip).
 * The input is written to a per-process file under /dev/shm (or $TMPDIR) so
 * the real entry point runs, gzip detection included. Inputs are made by the
 * structure-aware mutator in rawlog_mutator.cpp (MRPT's deserialisation is not
 * safe on arbitrary bytes: see there and fuzz/README.md). Contract under test:
 * every input either yields entries, each with a sensory frame, or throws
 * std::runtime_error. */

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
                                         });
  }
  catch (const std::runtime_error&)
  {
  }
  return 0;
}
