/* voxplore fuzz target: the HouseExpo floor-plan reader (libs/sim
 * parseFloorPlan, the same code loadFloorPlan runs after reading the file).
 * Contract under test: any input either gives walls around a polygon of at
 * least 3 finite vertices or throws std::runtime_error. */

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
    const voxplore::sim::World w = voxplore::sim::parseFloorPlan(text, "fuzz.json");
    if (w.free_space_outlines.size() != 1 || w.free_space_outlines[0].size() < 3 ||
        w.mesh.firstNonFiniteVertex() >= 0)
    {
      __builtin_trap();
    }
  }
  catch (const std::runtime_error&)
  {
  }
  return 0;
}
