/* voxplore — the pockets of open unknown in G (frontiers' unknown_m2,
 * FrontierLooks' small closed pockets). */
#include <voxplore/exploration/stages.h>

#include <cstdint>
#include <vector>

namespace voxplore::exploration
{
namespace
{
constexpr int kDx4[4] = {1, -1, 0, 0};
constexpr int kDy4[4] = {0, 0, 1, -1};
}  // namespace

UnknownPockets openUnknownPockets(const uint8_t* open_unknown, int nx, int ny)
{
  const std::size_t n = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  UnknownPockets out;
  out.label.assign(n, -1);
  std::vector<int> stack;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (!open_unknown[seed] || out.label[seed] >= 0) continue;
    const auto id = static_cast<int32_t>(out.cells.size());
    int64_t cells = 0;
    bool border = false;
    out.label[seed] = id;
    stack.assign(1, static_cast<int>(seed));
    while (!stack.empty())
    {
      const int i = stack.back();
      stack.pop_back();
      ++cells;
      const int cx = i % nx, cy = i / nx;
      for (int k = 0; k < 4; ++k)
      {
        const int x = cx + kDx4[k], y = cy + kDy4[k];
        if (x < 0 || y < 0 || x >= nx || y >= ny)
        {
          border = true;
          continue;
        }
        const int j = x + y * nx;
        if (!open_unknown[j] || out.label[j] >= 0) continue;
        out.label[j] = id;
        stack.push_back(j);
      }
    }
    out.cells.push_back(border ? -1 : cells);
  }
  return out;
}

}  // namespace voxplore::exploration
