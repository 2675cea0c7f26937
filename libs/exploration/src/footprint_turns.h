/* voxplore — turns on the way (issue 15): the footprint path's turns in
 * place moved onto its translations where the planner's turn layer holds
 * them. Internal to libs/exploration (footprint_path.cpp). */
#pragma once

#include <voxplore/exploration/footprint.h>

#include "footprint_search.h"

namespace voxplore::exploration::detail
{
/// Turns in place of at most max_rad followed by a translation in a narrow
/// passage (a footprint drive) are made on that translation instead, where
/// turnClearAlong() holds for a turn in proportion to the way (the driver's),
/// or else on the footprint translation before them, or else on a part of
/// either: the drive turns while it translates and does not stop
/// (PathParams::turn_on_the_way_deg). Our own: the SE(2) search plans turns
/// in place only.
void turnOnTheWay(Path& path, const SE2Search& s, const FootprintSpace& fs, double max_rad);

/// Lead-ins: a translation along which the turn layer holds every yaw,
/// before a narrow translation or at the goal, turns from any yaw to the one
/// needed there (Path::kTurnFromAnyYaw); the turns in place round it are
/// dropped. Our own, as turnOnTheWay().
void leadInTurns(Path& path, const SE2Search& s, const FootprintSpace& fs);
}  // namespace voxplore::exploration::detail
