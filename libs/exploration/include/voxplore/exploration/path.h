/* voxplore — clearance-keeping paths on the collision space (thesis 4.5.5). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/stages.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace voxplore::exploration
{
/// @brief ini section [path].
struct PathParams : public mrpt::config::CLoadableOptions
{
  double clearance_weight = 2.0;   ///< A* cost per metre: 1 + weight * max(0, clearance_ref - clearance) / clearance_ref
  double clearance_ref_m = 1.5;    ///< clearance beyond which no extra cost is paid [m]
  double shortcut_margin_m = 0.1;  ///< a shortcut may not pass closer to obstacles than the A* path's minimum clearance minus this [m]
  double max_segment_m = 1.0;      ///< waypoints at most this far apart (stop-and-scan, thesis 4.6) [m]
  /// [collision] model = footprint: the SE(2) A* is weighted A*, f = g + w h,
  /// its path costing at most w times the optimum. Its heuristic ignores the
  /// 32 bins, so with w = 1 it expanded every bin of every cell within the
  /// optimum's slack (0.65 M states, 0.46 s for 61 m on a 1,000 m^2 map);
  /// w = 1.1: 12 k states, 7 ms, path cost +0.1 %. 1 = optimal.
  double footprint_heuristic_weight = 1.1;
  /// Footprint paths: a turn in place of at most this much, before a
  /// translation, is made on that translation instead (Path::turn_on_way)
  /// where the rectangle keeps the turn margin at every yaw between along it,
  /// else on the footprint translation before it; and a translation where
  /// every yaw keeps it, before a narrow one or at the goal, turns to the yaw
  /// needed there from any yaw (a lead-in, Path::kTurnFromAnyYaw)
  /// (scanning while driving, issue 15: turns in place took a quarter of a
  /// continuous run's time). 0 = off; < 0 (auto, "auto" in the ini) = off
  /// here, resolved by the exploration loop by its scan mode [deg].
  double turn_on_the_way_deg = -1;
  /// @brief A* cost per metre at a cell with this clearance [m]:
  ///        1 + clearance_weight * max(0, clearance_ref - clearance) / clearance_ref.
  double costFactor(double clearance_m) const;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief A planned path.
struct Path
{
  std::vector<Eigen::Vector2d> cells_path;  ///< A* cell centres, start to goal [m]
  std::vector<Eigen::Vector2d> waypoints;   ///< after shortcutting and cutting into segments <= max_segment_m; first = start
  double length_m = 0;                      ///< length of the waypoint polyline [m]
  double min_clearance_m = 0;               ///< smallest clearance to occupied/unknown along it [m]
  /// Footprint model only (planFootprintPath), one per waypoint (the first,
  /// the start, included): the yaw to hold on the way to it [rad], and 1 where
  /// the planner's circle does not fit on that way (drive the rectangle).
  std::vector<double> yaws;
  std::vector<uint8_t> narrow;
  /// Where the robot turns to this waypoint's yaw on the way to it, not in
  /// place first (PathParams::turn_on_the_way_deg): kTurnFromPrevious (from
  /// the previous waypoint's yaw; the turn layer holds every yaw between
  /// along the way) or kTurnFromAnyYaw (a lead-in: from whatever yaw the
  /// robot has there; the turn layer holds every yaw along the way); else 0.
  std::vector<uint8_t> turn_on_way;
  static constexpr uint8_t kTurnFromPrevious = 1;
  static constexpr uint8_t kTurnFromAnyYaw = 2;
  std::optional<double> final_yaw;  ///< Footprint: the yaw to turn to at the goal [rad]
};

/// @brief A* over Free cells (8-connected) from `start` to `goal`, cost =
///        length x (1 + clearance term from the distance transform), then
///        line-of-sight shortcutting that keeps every straight piece inside
///        Free cells and never lowers the clearance below the A* path's
///        minimum minus shortcut_margin_m, then cut into segments.
/// @return empty when the goal is unreachable or not Free (the start may be
///         in MaybeCollision/Collision: the search leaves it by the cheapest way)
std::optional<Path> planPath(
    const CollisionSpace& cs, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
    const PathParams& p);

}  // namespace voxplore::exploration
