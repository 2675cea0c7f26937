/* voxplore — room segmentation of G (issue 12). Our own code: a
 * distance-transform segmentation (Bormann et al., ICRA 2016) at a fixed
 * door-width threshold, on the collision space's exact EDT; see rooms.h for
 * why this method. */
#include <mrpt/config/CConfigFileBase.h>
#include <voxplore/common/config.h>
#include <voxplore/exploration/rooms.h>

#include <deque>

namespace voxplore::exploration
{
void RoomParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(finish_room, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(door_width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_room_area_m2, double, c, s);
  common::requireValid(door_width_m > 0, c, s, "door_width_m", "must be > 0");
  common::requireValid(min_room_area_m2 >= 0, c, s, "min_room_area_m2", "must be >= 0");
}

void RoomParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(finish_room, c, s);
  MRPT_SAVE_CONFIG_VAR(door_width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_room_area_m2, c, s);
}

RoomMap segmentRooms(const GroundGrid& g, const CollisionSpace& cs, const RoomParams& p)
{
  const auto& st = g.state;
  const double res = st.getResolution();
  const int nx = static_cast<int>(st.getSizeX()), ny = static_cast<int>(st.getSizeY());
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  ASSERTMSG_(cs.clearance_occ_m.getSizeX() == st.getSizeX() &&
                 cs.clearance_occ_m.getSizeY() == st.getSizeY(),
             "segmentRooms: the collision space is not over G's grid");
  RoomMap rm;
  const int32_t none = -1;
  rm.label.setSize(st.getXMin(), st.getXMax(), st.getYMin(), st.getYMax(), res, &none);
  if (n == 0) return rm;
  const GroundState* s = st.data().data();
  const float* clear = cs.clearance_occ_m.data().data();
  int32_t* label = rm.label.cellByIndex(0, 0);  // row-major, nx * ny
  const float core_m = static_cast<float>(p.door_width_m / 2);
  auto isFree = [&](std::size_t i) { return s[i] == GroundState::Free; };
  auto isCore = [&](std::size_t i) { return isFree(i) && clear[i] > core_m; };
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};

  // Cores: 4-connected components; the big enough ones are rooms.
  const double cell_m2 = res * res;
  std::vector<uint8_t> walked(n, 0);
  std::vector<std::size_t> comp;
  std::deque<std::size_t> wave;  // the wavefront, seeded with every room's core
  for (std::size_t i0 = 0; i0 < n; ++i0)
  {
    if (walked[i0] || !isCore(i0)) continue;
    comp.clear();
    comp.push_back(i0);
    walked[i0] = 1;
    for (std::size_t k = 0; k < comp.size(); ++k)
    {
      const int cx = static_cast<int>(comp[k] % nx), cy = static_cast<int>(comp[k] / nx);
      for (int d = 0; d < 4; ++d)
      {
        const int x = cx + dx[d], y = cy + dy[d];
        if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
        const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
        if (walked[j] || !isCore(j)) continue;
        walked[j] = 1;
        comp.push_back(j);
      }
    }
    const bool room = static_cast<double>(comp.size()) * cell_m2 >= p.min_room_area_m2;
    const int32_t id = room ? static_cast<int32_t>(rm.area_m2.size()) : none;
    if (room) rm.area_m2.push_back(0.0);
    for (const std::size_t j : comp)
    {
      label[j] = id;
      if (room) wave.push_back(j);
    }
  }
  // Wavefront over Free cells from every room's core at once (breadth-first:
  // a cell joins the room whose core is fewest 4-steps away; ties go to the
  // room queued first, so the labels are deterministic).
  while (!wave.empty())
  {
    const std::size_t i = wave.front();
    wave.pop_front();
    const int cx = static_cast<int>(i % nx), cy = static_cast<int>(i / nx);
    for (int d = 0; d < 4; ++d)
    {
      const int x = cx + dx[d], y = cy + dy[d];
      if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
      const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
      if (label[j] != none || !isFree(j)) continue;
      label[j] = label[i];
      wave.push_back(j);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (label[i] >= 0) rm.area_m2[static_cast<std::size_t>(label[i])] += cell_m2;
  return rm;
}

}  // namespace voxplore::exploration
