/* voxplore — the exploration planner (thesis 4.5): from V and the robot pose
 * to the next best pose and a safe path, or "done". */
#pragma once

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/footprint.h>
#include <voxplore/exploration/looks.h>
#include <voxplore/exploration/path.h>
#include <voxplore/exploration/rooms.h>
#include <voxplore/exploration/scan_rating.h>
#include <voxplore/exploration/stages.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace voxplore::exploration
{
/// @brief Strategy: the thesis' next-best-view, or the classic nearest-frontier baseline.
enum class Strategy
{
  NextBestView,    ///< samples around the chosen frontier rated by entropy ray casting
  NearestFrontier  ///< drive to the chosen frontier's nearest Free cell to its centre (no rating)
};

/// @brief The order in which the next-best-view strategy takes frontiers
///        (the nearest strategy, the baseline, always takes the nearest).
enum class FrontierOrder
{
  Tour,    ///< the first stop of an open tour over travel distances (issue 12)
  Nearest  ///< the nearest by travel distance (thesis 4.5.4)
};

/// @brief All planner settings: [projection] [collision] [sampling] [rooms] [scan_rating] [path] [planner].
struct PlannerParams
{
  ProjectionParams projection;
  CollisionParams collision;
  SamplingParams sampling;
  RoomParams rooms;
  ScanRatingParams rating;
  PathParams path;
  Strategy strategy = Strategy::NextBestView;
  int seed = 1;  ///< [planner] seed of the pose sampler
  FrontierOrder frontier_order = FrontierOrder::Nearest;  ///< [planner] frontier_order = tour | nearest
  double tour_cell_m = 0.2;  ///< [planner] the tour's travel costs on blocks of about this side [m]
  /// [planner] frontier_tiers: next-best-view takes the frontiers longer
  /// than [sampling] th_f1_m first, then those longer than th_f2_m (thesis
  /// 4.5.4); false (the default since the forty-second session): one tier,
  /// every frontier longer than th_f2_m in frontier_order alone. The
  /// nearest strategy (the baseline) always keeps the thesis' tiers.
  bool frontier_tiers = false;

  void load(const mrpt::config::CConfigFileBase& cfg);
  void save(mrpt::config::CConfigFileBase& cfg) const;
  /// The robot's rectangle (not ini keys): G's swept-footprint columns, the
  /// collision rectangle, and r_coll_m = its circumradius (a [collision]
  /// r_coll_m key loaded afterwards wins).
  void setFootprint(double length_m, double width_m);
  /// The projection's keys with "auto" resolved at the map's resolution:
  /// obstacle_z_max_m auto is auto_obstacle_z_max_m where the planner plans
  /// the footprint with exact margins (CollisionParams::footprintTrimmed
  /// false), else off.
  ProjectionParams projectionInForce(double l_res_m) const;
  /// The frontier order's thresholds: `sampling`, with th_f1_m = th_f2_m
  /// (one tier) for next-best-view without frontier_tiers.
  SamplingParams frontierOrderInForce() const;
  static std::vector<std::string> sections()
  {
    return {"projection", "collision", "sampling", "rooms", "scan_rating", "path", "planner"};
  }
};

/// @brief Why planning ended without a target.
enum class DoneReason
{
  None,                ///< not done: there is a plan
  NoFrontier,          ///< no frontier at all: fully explored
  NoReachableFrontier, ///< frontiers exist but none passes th_f2 / is reachable
  AllSkipped           ///< every qualifying frontier had an empty sample space, no path, or is blacklisted
};
const char* toString(DoneReason r);

/// @brief Why a frontier tried by plan() gave no target.
enum class SkipReason
{
  NoGoal,     ///< nearest: no reachable cell at all
  NoSamples,  ///< nbv: the sample space (reachable cells seeing it) is empty
  NoGain,     ///< nbv: no sample would see an unknown voxel
  NoPath      ///< no candidate pose has a path
};
const char* toString(SkipReason r);

/// @brief Milliseconds per stage of one planning step.
struct PlanTimings
{
  double projection = 0, collision = 0, frontiers = 0, rooms = 0, tour = 0, sampling = 0, rating = 0,
         path = 0, total = 0;
};

/// @brief Result of one planning step: a plan, or done with its reason.
struct PlanResult
{
  DoneReason done = DoneReason::None;
  std::string message;                 ///< human-readable summary
  std::vector<Eigen::Vector2d> waypoints;  ///< start excluded, target last
  /// [collision] model = footprint only, one per waypoint: the yaw to hold on
  /// the way to it [rad] (turn there first), and 1 where the planner's circle
  /// does not fit on that way (drive the rectangle, not MRPT's circle).
  std::vector<double> waypoint_yaws;
  std::vector<uint8_t> waypoint_narrow;
  std::vector<uint8_t> waypoint_turn_on_way;  ///< Path::turn_on_way, one per waypoint
  mrpt::poses::CPose2D target;         ///< pose to reach (yaw at the frontier)
  std::optional<Frontier> frontier;    ///< the chosen frontier
  std::size_t frontier_index = 0;      ///< its index in frontiers->frontiers
  std::vector<mrpt::poses::CPose2D> samples;
  std::vector<ScanRating> ratings;     ///< one per sample (NextBestView)
  std::optional<Path> path;
  std::vector<std::size_t> skipped_frontiers;  ///< indices tried and skipped
  std::vector<SkipReason> skip_reasons;        ///< why, one per skipped_frontiers entry
  PlanTimings ms;
  // Layers, kept for rendering and inspection.
  std::shared_ptr<const GroundGrid> ground;
  std::shared_ptr<const CollisionSpace> space;
  std::shared_ptr<const FrontierMap> frontiers;
  std::shared_ptr<const FootprintSpace> footprint;  ///< [collision] model = footprint only
  std::shared_ptr<const RoomMap> rooms;             ///< G's rooms (segmentRooms)
  int32_t robot_room = -1;  ///< the room of the robot's cell (-1: none)
  /// One per frontier: its room (the room most of its cells lie in; -1: none).
  std::vector<int32_t> frontier_rooms;
  std::vector<Cell> sample_space;
  bool approached = false;  ///< the chosen frontier was approached (plan()'s `approach`)
  /// frontier_order = tour (next-best-view): the tour over the tier the
  /// chosen frontier was taken from (empty otherwise).
  FrontierTour tour;
  /// Row-major over G: 1 for the unknown cells taken from the frontiers as
  /// looked at and left unknown (plan()'s `looks`, SamplingParams::
  /// retire_looks); empty: none. retired_m2: the open unknown among them [m^2].
  std::vector<uint8_t> retired;
  double retired_m2 = 0;

  bool ok() const { return done == DoneReason::None; }
};

/// @brief Runs every stage. Deterministic: the sampler is seeded with
///        params.seed and the step counter passed in.
/// @param swept points the robot's centre has swept (map frame; see
///        ProjectionParams::swept_radius_m)
/// @param sensed_obstacles points (map frame) the driver sensed in the way
///        that V may not hold (below the projection's z_min, a pose error):
///        their cells of G are Occupied (not the robot's own)
/// @param approach next-best-view and the nearest strategy's view stand-off
///        (footprint model): a frontier whose centre lies within
///        blacklist_radius_m of one of these (planned before, and its view
///        did not clear it) is approached instead: the target is its
///        nearest reachable cell, the thesis' nearest target
/// @param low_obstacles cells of V's low obstacles (OctoMapLayer::
///        lowObstacles(), below the projection's z_min): those G holds Free
///        become Occupied, unless one of their 8 neighbours is Occupied by
///        V's columns (the base of that wall or furniture, whose returns leak
///        into the cell in front of it by range noise: stamping them
///        narrowed doors, omniRob b3 nearest 0.955 -> 0.679) or is the
///        robot's. Unknown cells too with [collision]
///        low_obstacles_on_unknown (a table base under its top, never seen
///        from above: otherwise a frontier no view clears); which unknown is
///        open is judged as if none had been stamped (GroundGrid::low_was):
///        stamps closing the unknown beside them took frontiers away (b4
///        omniRob nbv 0.968 -> 0.906, a room behind a 0.8 m opening).
/// @param projection_cache the projection's columns from the last step,
///        told where V changed since (projectToGround); nullptr: none.
/// @param looks the unknown cells looked at so far; its stops added since
///        the last plan are judged on this step's G first, then the cells
///        looked at SamplingParams::retire_looks times are no frontier
///        source (findFrontiers' `retired`); nullptr: none.
PlanResult plan(
    const octomap::OcTree& V, const mrpt::poses::CPose2D& robot, const PlannerParams& params,
    const std::vector<Eigen::Vector2d>& blacklist = {}, uint64_t step = 0,
    const SweptPath& swept = {}, const std::vector<Eigen::Vector2d>& sensed_obstacles = {},
    const std::vector<Eigen::Vector2d>& approach = {},
    const std::vector<Eigen::Vector2d>& low_obstacles = {},
    ProjectionCache* projection_cache = nullptr, FrontierLooks* looks = nullptr);

/// @brief plan()'s first stages only: G, the collision (and footprint)
///        space and the frontiers (PlanResult::ground, space, footprint,
///        frontiers, retired; done stays None and there is no target). A
///        few tens of ms where plan() rates views: for checking what is left
///        while the robot drives ([explore] replan_on_the_way). Arguments as
///        plan()'s.
PlanResult planLayers(const octomap::OcTree& V, const mrpt::poses::CPose2D& robot,
                      const PlannerParams& p, const SweptPath& swept,
                      const std::vector<Eigen::Vector2d>& sensed_obstacles,
                      const std::vector<Eigen::Vector2d>& low_obstacles,
                      ProjectionCache* projection_cache, FrontierLooks* looks);

/// @brief planLayers() on a G already projected (projectToGround with the
///        projection of `p`, at the robot's pose): the obstacles stamped,
///        then the collision space and the frontiers. planLayers() is
///        projectToGround() and this.
PlanResult planLayersOn(GroundGrid ground, const mrpt::poses::CPose2D& robot,
                        const PlannerParams& p, const SweptPath& swept,
                        const std::vector<Eigen::Vector2d>& sensed_obstacles,
                        const std::vector<Eigen::Vector2d>& low_obstacles, FrontierLooks* looks);

/// @brief How many of a plan's frontier cells (`frontier`'s, in the grid
///        `planned_on` it was found in) still border open unknown in `now`
///        (a 4-neighbour Unknown, or off the grid; with
///        `ignore_beside_obstacles`, as [collision]
///        ignore_unknown_beside_obstacles, not an Unknown cell beside an
///        Occupied one), looked up by their centres in `now` (a grown map's
///        grid has other bounds; a cell off `now` counts as bordering). The
///        cheap half of "has the robot seen the frontier it drives to"
///        ([explore] seen_gate): no collision space, no reachability.
std::size_t frontierCellsLeft(const Frontier& frontier, const GroundGrid& planned_on,
                              const GroundGrid& now, bool ignore_beside_obstacles);

/// @brief PNG of G with its layers in the thesis' colours (fig. 4.12): free
///        white, occupied black, unknown red (brown where retired as looked
///        at and left unknown), collision grey, maybe-collision
///        green, frontiers cyan, chosen frontier yellow,
///        reachable blue (each room its own shade of blue or green, the
///        robot's darker), sample space purple, samples orange, chosen pose and path magenta,
///        robot and travelled `trajectory` (optional) dark red. One pixel per cell, scaled by `scale`.
/// @throws std::runtime_error naming the path when it cannot be written.
void renderPlan(
    const PlanResult& r, const mrpt::poses::CPose2D& robot, const std::string& png_path,
    const std::vector<mrpt::poses::CPose2D>& trajectory = {}, int scale = 4);

}  // namespace voxplore::exploration
