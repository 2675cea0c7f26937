/* voxplore fuzz target: the `.world` loader (libs/sim parseWorldFile, the same
 * code loadWorldFile runs after reading the file). Relative element files
 * resolve against fuzz/data/ (a small mesh and floor plan the seeds use).
 * Contract under test: any input either loads or throws std::runtime_error;
 * nothing else may escape and no sanitizer may fire. */

#include <voxplore/sim/world_loading.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  try
  {
    const voxplore::sim::World w =
        voxplore::sim::parseWorldFile(text, VOXPLORE_FUZZ_DATA_DIR "/fuzz.world");
    if (w.mesh.empty() || w.mesh.firstNonFiniteVertex() >= 0)
    {
      __builtin_trap();  // loadWorldFile promises finite geometry or an error
    }
  }
  catch (const std::runtime_error&)
  {
    // the documented error for malformed input
  }
  return 0;
}
