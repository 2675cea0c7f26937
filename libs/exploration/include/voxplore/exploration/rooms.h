/* voxplore — rooms and corridors of the exploration grid G (issue 12). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <voxplore/exploration/grid.h>
#include <voxplore/exploration/stages.h>

#include <cstdint>
#include <vector>

namespace voxplore::exploration
{
/// @brief ini section [rooms].
struct RoomParams : public mrpt::config::CLoadableOptions
{
  /// next-best-view: the frontiers of the room the robot is in (above th_f2)
  /// are taken before any other, whatever their length (the thesis' th_f1
  /// tier sent the robot off to a long frontier elsewhere and it came back
  /// for the room's short ones later); a frontier of the room that gives no
  /// target (no sample space, no gain, no path) falls back to the usual
  /// order. false = the thesis' order over the whole map.
  bool finish_room = false;
  /// Passages narrower than this split rooms: a room's core is the Free
  /// cells farther than door_width_m / 2 from every Occupied cell centre
  /// (office doors are 0.8-1.0 m; the generated buildings' corridors 1.8-2.4
  /// m keep a core) [m].
  double door_width_m = 1.1;
  /// A core smaller than this is no room (an alcove, the gap between two
  /// tables); its cells join the room that grows over them [m^2].
  double min_room_area_m2 = 2.0;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Rooms of G: every Free cell of G labelled with its room.
struct RoomMap
{
  Grid<int32_t> label;        ///< room index, or -1 (not Free, or no room grows there)
  std::vector<double> area_m2;  ///< per room: its cells (core and grown) x l_res^2
  /// @brief The room of cell c (-1: none, or c outside the grid).
  int32_t roomAt(const Cell& c) const
  {
    return inGrid(label, c.cx, c.cy) ? *label.cellByIndex(c.cx, c.cy) : -1;
  }
};

/// @brief Distance-transform room segmentation (Bormann et al., "Room
///        segmentation: survey, implementation, and analysis", ICRA 2016,
///        the ipa_room_segmentation comparison): cores are the Free cells
///        farther than door_width_m / 2 from every Occupied cell
///        (CollisionSpace::clearance_occ_m, the exact EDT already computed),
///        grouped 4-connected; cores of at least min_room_area_m2 are rooms,
///        numbered in row-major order of their first cell; every other Free
///        cell joins the room whose core a 4-connected wavefront over Free
///        cells reaches it from first.
///        Why this method: ipa's distance segmentation sweeps the threshold
///        for the most rooms, and its Voronoi segmentation (best scored
///        there) reshapes as the skeleton grows; a fixed threshold at the
///        door width depends only on the geometry within door_width_m / 2
///        of a cell, so a room seen once keeps its shape while the rest of
///        the map grows, and it costs one pass over G (the EDT is the
///        collision space's). Unknown is no wall: a room half seen is one
///        room up to its frontier, not cut at it.
RoomMap segmentRooms(const GroundGrid& g, const CollisionSpace& cs, const RoomParams& p);

}  // namespace voxplore::exploration
