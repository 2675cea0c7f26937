/* voxplore — the 2D stages of the exploration planner (thesis 4.5.1 - 4.5.4):
 * each a pure function with a Parameters struct. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/collision_params.h>
#include <voxplore/exploration/grid.h>
#include <voxplore/mapping/map_changes.h>

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace octomap
{
class OcTree;
}

namespace voxplore::exploration
{
/// @brief Poses (x, y, yaw) [m, m, rad] the robot's centre has occupied, in the
///        map frame: the floor under its body there is free.
using SweptPath = std::vector<Eigen::Vector3d>;

// ---------------------------------------------------------------- 1. projection
/// @brief ini section [projection].
struct ProjectionParams : public mrpt::config::CLoadableOptions
{
  double z_min_m = 0.10;  ///< voxels of a column from this height (floor excluded) [m]
  double z_max_m = 0.50;  ///< ... up to this height [m]
  /// Occupied voxels from z_max_m up to this height make their column
  /// Occupied too; unknown ones there do not make it Unknown (the Free rule
  /// stays the band's): what the cameras see between the band and their
  /// ring (0.60 m) is kept off the body, what they cannot see does not
  /// close the floor. <= z_max_m: off (the thesis) [m]. kAuto (ini "auto",
  /// the default): PlannerParams::projectionInForce resolves it;
  /// projectToGround takes kAuto as off.
  double obstacle_z_max_m = kAuto;
  /// obstacle_z_max_m auto: this height where the planner plans the
  /// footprint with exact margins (the compact robot), off elsewhere (the
  /// omniRob, whose doors leave no cell to spare) [m].
  double auto_obstacle_z_max_m = 0.60;
  static constexpr double kAuto = -1.0;
  int th_free = 70;       ///< free below (0..255 scale, p = value/255)
  int th_occ = 240;       ///< occupied above (0..255 scale)
  double margin_m = 1.0;  ///< grid extends this far past the map's bounds [m]
  /// Exploration region (ini key "region": x0 y0 x1 y1 x2 y2 ..., a simple
  /// polygon in the map frame [m]); columns outside it are Occupied (virtual
  /// walls: no frontier, no sample, no path leaves it). Empty: unbounded.
  std::vector<Eigen::Vector2d> region;
  /// Columns within this distance of a point the robot's centre has swept
  /// (projectToGround's `swept`) count as free unless occupied: the robot's
  /// body was there. It ties the robot to the known map where the cameras,
  /// blind within ~1 m, left a ring of unknown round it (after stops that
  /// were not integrated). 0 = off [m].
  double swept_radius_m = 0.15;
  /// The robot's footprint (length along its +X, width) [m]; not an ini key,
  /// set from the robot profile. With swept_footprint, the columns under
  /// this rectangle at every swept pose, shrunk by swept_footprint_margin_m
  /// on each side, count as free unless occupied too: the cameras look
  /// outward from the body's rim and never see the floor under it, and the
  /// omniRob's blind slivers there (0.3 m from its centre, across a 2 m
  /// corridor) closed the corridor to its planner (generated building 7).
  double footprint_length_m = 0, footprint_width_m = 0;
  bool swept_footprint = true;           ///< false: swept_radius_m only (the thesis has neither)
  double swept_footprint_margin_m = 0.05;  ///< the rectangle is shrunk by this on each side [m]
  /// With a ProjectionCache, visit only the voxels of the columns V changed
  /// since the cache's last projection (the same grid either way); false:
  /// every column every time.
  bool incremental = true;
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief G: ground states and where the robot is in it.
struct GroundGrid
{
  Grid<GroundState> state;
  Cell robot;
  /// Cells plan() stamped Occupied as low obstacles (OctoMapLayer's low
  /// cells), one byte per cell of `state` holding what the voxel columns
  /// made of it: 0 = not stamped, 1 = Free, 2 = Unknown. Empty: none.
  /// Which unknown is open (frontiers, MaybeCollision) is judged as if they
  /// had not been stamped, and they themselves are closed.
  std::vector<uint8_t> low_was;
};

/// @brief What projectToGround keeps from one call to the next so that it
///        visits only the voxel columns V changed in between (issue 12: the
///        planning step at building scale). Its cost was the per-column tally
///        of every leaf in the z band; the caller tells the cache where V
///        changed (markChanged, e.g. from OctoMapLayer::changedSince), and the
///        other columns' tallies are the last call's. The grid is the one a
///        full projection gives (tested). Our own: OctoMap's change detection
///        records occupancy flips only, not the projection's th_free.
class ProjectionCache
{
 public:
  ProjectionCache();
  ~ProjectionCache();
  ProjectionCache(ProjectionCache&&) noexcept;
  ProjectionCache& operator=(ProjectionCache&&) noexcept;

  /// @brief V's voxels in `keys` (OctoMap keys) changed since the last projection.
  void markChanged(const mapping::KeyBox& keys);
  /// @brief Where V changed is not known: the next projection visits every column.
  void markAllChanged();
  /// @brief Projections that visited every column / only the changed ones.
  std::size_t fullTallies() const;
  std::size_t partialTallies() const;

  struct State;  ///< projection_columns.cpp's

 private:
  friend GroundGrid projectToGround(const octomap::OcTree&, const mrpt::poses::CPose2D&,
                                    const ProjectionParams&, const SweptPath&, ProjectionCache*);
  std::unique_ptr<State> s_;
};

/// @brief Algorithm 2: flood fill from the robot's column over voxel columns
///        [z_min, z_max] of V; a column is occupied if any voxel > th_occ,
///        unknown if any voxel is >= th_free or has never been observed,
///        else free (and its 4 neighbours are queued). The robot's own
///        column counts as free, even when occupied (the robot stands there;
///        the cameras cannot see it). Columns outside p.region (when set) are
///        Occupied. Cells the fill does not reach stay Unknown. The grid covers V's bounds plus margin and
///        the robot; its resolution is V's.
///        With `cache` (and p.incremental), only the columns it was told V
///        changed in are visited again; it must see every change to V (and
///        only this V) between calls.
GroundGrid projectToGround(
    const octomap::OcTree& V, const mrpt::poses::CPose2D& robot, const ProjectionParams& p,
    const SweptPath& swept = {}, ProjectionCache* cache = nullptr);

/// @brief Obstacles the voxel columns do not show, stamped Occupied into G
///        (map frame points; none on the robot's cell). `sensed` (points the
///        driver's sensors held the robot for): wherever they fall. `low`
///        (OctoMapLayer's low obstacle cells, below the projection's band):
///        where G holds Free, or Unknown too with `low_on_unknown`, unless the
///        robot's cell or a cell the columns made Occupied is among their 8
///        neighbours (a wall's own foot); each records what it was in
///        g.low_was (left empty when there are none).
void stampObstacles(GroundGrid& g, const std::vector<Eigen::Vector2d>& sensed,
                    const std::vector<Eigen::Vector2d>& low, bool low_on_unknown);
/// @brief stampObstacles' rule for the low obstacle cell c (in g): whether
///        it is stamped, with `robot` as the robot's cell. g.low_was's own
///        stamps (a G stamped already) do not count as columns.
bool lowObstacleStamps(const GroundGrid& g, const Cell& c, const Cell& robot, bool low_on_unknown);

// ------------------------------------------------------------ 2. collision space
// CollisionParams ([collision]): collision_params.h.

/// @brief Space classes and clearances.
struct CollisionSpace
{
  Grid<SpaceState> state;
  Grid<float> clearance_occ_m;      ///< distance from the cell centre to the nearest occupied cell centre [m]
  Grid<float> clearance_unknown_m;  ///< ... to the nearest unknown cell centre [m]
  /// @brief The smaller of both clearances at row-major cell i [m].
  float clearance(std::size_t i) const
  {
    return std::min(clearance_occ_m.data()[i], clearance_unknown_m.data()[i]);
  }
  double radius_m = 0;              ///< r_coll + sqrt(2) l_res, the radius used
  /// Row-major over `state`: 1 for the Unknown cells that stand for
  /// unexplored space (CollisionParams: not beside an obstacle, not in a thin
  /// closed pocket); the sources of MaybeCollision and of frontiers.
  std::vector<uint8_t> open_unknown;
  /// The states are the rectangle's (applyFootprint): frontier cells are
  /// grown by this, along known free cells bordering open unknown (the
  /// rectangle reaches a door's middle only; the frontier is the whole
  /// door). 0: the thesis' frontier cells only [m].
  double frontier_grow_m = 0;
};

/// @brief thesis 4.5.2 with exact Euclidean distance transforms (no per-cell
///        disc loops): free cells within r_coll + sqrt(2) l_res of an
///        occupied cell are Collision, else of an unknown cell MaybeCollision.
CollisionSpace computeCollisionSpace(const GroundGrid& g, const CollisionParams& p);

/// @brief CollisionParams::swept_passage on cs (circle model): the Collision
///        and MaybeCollision cells of the 3 x 3 blocks round the swept
///        poses' cells with clearance_occ_m >= r_coll_m +
///        swept_passage_margin_m become Free.
/// @return the cells opened
std::size_t openSweptPassages(CollisionSpace& cs, const SweptPath& swept, const CollisionParams& p);

// -------------------------------------------------------------------- 3. frontiers
/// @brief One frontier: 8-connected reachable free cells bordering unknown space.
struct Frontier
{
  int id = 0;
  std::vector<Cell> cells;
  double size_m = 0;          ///< cells x l_res
  /// The opening it faces [m]: its cells and the known free cells that
  /// border open unknown within the planner circle's radius of them (circle
  /// model; the footprint model's cells are grown already: = size_m). A
  /// 0.9 m door gives the compact robot's 0.76 m circle a frontier of 2-4
  /// reachable cells, its opening is the door.
  double opening_m = 0;
  double distance_m = 0;      ///< BFS travel distance from the robot to its nearest cell [m]
  /// The open unknown it borders [m^2]: the area of the 4-connected pockets
  /// of CollisionSpace::open_unknown next to its cells (infinity when one
  /// reaches the grid's border). A door to an unseen room faces tens of
  /// m^2; the floor under a table or behind a cabinet a pocket of under 1 m^2
  /// that no pose the robot reaches may ever clear.
  double unknown_m2 = 0;
  Eigen::Vector2d centroid{0, 0};  ///< mean of its cell centres [m]
  Eigen::Vector2d center{0, 0};    ///< its cell nearest to the centroid [m] (lies on the frontier)
  /// Known free floor the planner's robot does not reach, bordering open
  /// unknown, within UnreachedFrontiers::within_m of where it does: to be
  /// seen from there (findFrontiers' `unreached`).
  bool unreached = false;
};

/// @brief Reachability and frontiers.
struct FrontierMap
{
  Grid<float> distance_m;    ///< travel distance from the robot [m]; -1 where not reached
  Grid<uint8_t> reachable;   ///< 1: the robot centre can get here (Free, connected to the robot)
  std::vector<Frontier> frontiers;  ///< sorted by distance_m, then size
};

/// @brief The 4-connected pockets of open unknown (CollisionSpace::
///        open_unknown, row-major, nx x ny): a pocket per cell (-1: not open
///        unknown) and each pocket's cells, -1 for a pocket touching the
///        grid's border (open to the unknown beyond it).
struct UnknownPockets
{
  std::vector<int32_t> label;
  std::vector<int64_t> cells;
};
UnknownPockets openUnknownPockets(const uint8_t* open_unknown, int nx, int ny);

/// @brief Where findFrontiers looks for unreached frontiers.
struct UnreachedFrontiers
{
  double within_m = 0;        ///< over G's Free cells from a reached cell [m]; 0 = none
  double min_depth_m = 1.0;   ///< a cell of the frontier at least this far from the reach [m]
  double min_unknown_m2 = 0;  ///< bordering a closed pocket of open unknown this large [m^2]
};

/// @brief thesis 4.5.3: BFS from the robot over Free cells (reachable space),
///        continued one band into MaybeCollision cells; frontier cells are
///        reached Free/MaybeCollision cells with an open Unknown 4-neighbour
///        (CollisionSpace::open_unknown: unseen wall bases and thin closed
///        pockets are no frontier), grouped 8-connected. Distances: 8-connected BFS, 1 per straight
///        step and sqrt(2) per diagonal (Dijkstra on the grid).
///        `retired` (optional, row-major over G): open unknown cells marked 1
///        are no frontier source (FrontierLooks::retiredMask).
///        `unreached` (within_m > 0; SamplingParams::unreached_frontiers):
///        after them, sorted by distance, the frontiers of Free cells of G
///        the search did not reach, within within_m of a reached cell over
///        Free cells of G, with a cell at least min_depth_m from the reach
///        (not the floor along a wall the rectangle cannot reach), that
///        border a pocket of open unknown of at least min_unknown_m2 not
///        reaching the grid's border (a room, not the outside), in no frontier
///        before them (Frontier::unreached). Our own (thesis 4.5.3 keeps
///        reachable cells only).
FrontierMap findFrontiers(const GroundGrid& g, const CollisionSpace& cs,
                          const std::vector<uint8_t>* retired = nullptr,
                          const UnreachedFrontiers& unreached = {});

/// @brief Known free floor the robot cannot get to [m^2]: the Free cells of G
///        farther than cs.radius_m + l_res from every reachable cell (no
///        robot centre the planner allows brings its body there). The
///        projection's flood fill joins every Free cell of G to the robot's,
///        so floor beyond that is floor the collision space cut off: a door
///        the map closes (drift, unknown jambs), a passage narrower than the
///        planner's robot.
double cutOffFloorM2(const GroundGrid& g, const CollisionSpace& cs, const FrontierMap& fm);

// ---------------------------------------------------------- 4. choice and samples
/// @brief ini section [sampling].
struct SamplingParams : public mrpt::config::CLoadableOptions
{
  double th_f1_m = 1.0;         ///< prefer the nearest frontier longer than this [m]
  double th_f2_m = 0.25;        ///< else the nearest longer than this [m]; else done
  double d_min_sample_m = 1.0;  ///< sample space: at least this far from the frontier [m]
  double d_max_sample_m = 3.0;  ///< ... at most this far [m]
  int max_samples = 15;         ///< pose samples per frontier
  double min_sample_dist_m = 0.5;  ///< samples at least this far apart [m]
  double blacklist_radius_m = 0.5; ///< a frontier whose centre is this close to a failed target is skipped [m]
  /// [collision] model = footprint, nearest strategy: the target is the
  /// reachable cell nearest to the frontier's centre among those this far
  /// from every frontier cell (up to 1 m farther) that see one of them (the
  /// nearest reachable cell when there is none). The rectangle may stand 2 cm
  /// from open unknown, but the cameras see no floor within about 0.9 m of
  /// their rim: a target at the frontier saw nothing new and was given up.
  /// The circle keeps its own stand-off (r_coll): with this stand-off the
  /// compact robot's nearest runs ended early (b2 0.89 -> 0.12, b3 0.98 ->
  /// 0.04, BENCHMARKS.md fifteenth session). 0 = off [m].
  double view_standoff_m = 1.5;
  /// Line of sight to a frontier (sample space, view stand-off) is blocked
  /// by Unknown cells that are not open unknown too (beside an occupied cell
  /// or in a thin pocket: CollisionSpace::open_unknown), not only by
  /// Occupied ones (thesis fig. 4.15). A wall is mapped as two faces with
  /// gaps round an unseen interior; the 4-connected walk slipped through
  /// the gaps and the target stood in the next room, "seeing" a corridor
  /// through the wall (b2, omniRob, nearest: three frontiers of a branch
  /// corridor given up that way, 0.75).
  bool sight_blocked_by_unknown = false;
  /// The same rule for the view stand-off alone (standoffGoal; the sample
  /// space keeps sight_blocked_by_unknown). The stand-off target is the
  /// ring cell nearest the frontier's centre, so the first cell whose sight
  /// slips through a wall wins; where it did, the frontiers were given up
  /// after two plans (omniRob, nearest, b1-b10: see BENCHMARKS.md,
  /// seventeenth session).
  bool standoff_sight_blocked_by_unknown = true;
  /// The tiers (th_f1, th_f2) judge a frontier by the opening it faces
  /// (Frontier::opening_m), not by its reachable cells only: the compact
  /// robot's circle reaches 0.1-0.2 m of a 0.9 m door's frontier, below
  /// th_f2, and the room behind it was never entered (b1 compact nbv, 0.88).
  bool judge_opening = false;
  /// Next-best-view: a sample's utility is its gain x exp(-travel_cost_per_m
  /// x its travel distance from the robot over G), the information gain
  /// discounted by the drive to it (Gonzalez-Banos and Latombe's NBV
  /// utility); candidates are tried by utility. 0 = by gain alone (thesis
  /// 4.5.5): the best view of a frontier was often on its far side, and the
  /// nbv robot drove 1.40x the nearest baseline's path (compact, b1-b5);
  /// 0.15: 0.96x at equal coverage; on b6-b10 path -27 %, omniRob b1-b5
  /// -31 %, coverage up (BENCHMARKS.md, thirteenth and fourteenth sessions) [1/m].
  double travel_cost_per_m = 0.15;
  /// Next-best-view: the samples of this many frontiers (the chosen one and
  /// the next ones in the same order) are rated together and the best
  /// utility among them wins; 1 = the chosen frontier only (thesis).
  int frontiers_rated = 1;
  /// Next-best-view, [collision] model = footprint: a sample is rated at the
  /// yaw the robot will stand at there (FootprintSpace::nearestReachedYaw
  /// of the yaw facing the frontier), and that yaw is its target's. false =
  /// rated facing the frontier (thesis 4.5.5), a yaw the rectangle often
  /// cannot take: the omniRob beside a door in a 2.2 m corridor was rated
  /// at -58 deg and stood at -79 deg, twice, and the room was never entered.
  bool rate_reached_yaw = false;
  /// Once no frontier the planner's robot reaches gives a target, the
  /// frontiers of known free floor it does not reach (within d_max_sample_m
  /// of where it does over G's Free cells, reaching unreached_min_depth_m
  /// beyond it, bordering a pocket of open unknown of at least
  /// unreached_min_unknown_m2 that does not reach the grid's border: a
  /// room, not the outside) are viewed from where it does, by both
  /// strategies (Frontier::unreached). A room seen through a door only at a
  /// slant stays open unknown just behind it, and the omniRob's rectangle,
  /// which keeps its margin from open unknown, cannot enter it: the run
  /// ended "no frontier" with the room unseen (b5 omniRob nearest: two
  /// rooms, 41 m^2 of known floor cut off, coverage 0.929). false =
  /// reachable frontiers only (thesis 4.5.3).
  bool unreached_frontiers = false;
  double unreached_min_unknown_m2 = 8.0;  ///< ... [m^2]
  double unreached_min_depth_m = 1.0;     ///< ... [m]
  /// @brief The length the tiers judge frontier f by [m].
  /// judge_opening only for frontiers that border at least this much open
  /// unknown (Frontier::unknown_m2; a door to an unseen room), the others by
  /// their cells: judge_opening gave every sliver 0.75-0.95 m. 0 = all [m^2].
  double judge_opening_min_unknown_m2 = 0;
  /// A frontier bordering less open unknown than this (Frontier::unknown_m2:
  /// a closed pocket under a table, behind furniture, at a wall's foot) is
  /// not chosen: the robot crossed the building for such slivers after the
  /// rooms were seen (issue 12's tail). 0 = every frontier (thesis) [m^2].
  double enclosed_unknown_m2 = 0;
  /// An open unknown cell of G that this many stops looked at (FrontierLooks:
  /// in 2D sight over Free cells within look_range_m, its band in a
  /// camera's view) and left unknown, in a closed pocket of open unknown
  /// (4-connected) smaller than retire_pocket_m2, is no frontier source: the
  /// floor under a table, behind a cabinet, that no view clears (issue 12's
  /// tail: after coverage 0.975 b9 compact nbv drove 200 m for 0.001 more).
  /// A door to an unseen room faces a large pocket and stays. 0 = never
  /// (thesis), the default: with 2 (6 m, 2 m^2) on 15 campaign runs the
  /// nbv runs kept their path and coverage, the nearest ones drove 12 %
  /// more for 0.007 less coverage; the tail's slivers face the robot's side
  /// of a pocket no stop had looked at yet (BENCHMARKS.md, thirtieth session).
  int retire_looks = 0;
  double look_range_m = 6.0;      ///< a look reaches this far from the robot's centre [m]
  double retire_pocket_m2 = 2.0;  ///< only pockets smaller than this are retired; 0 = any [m^2]
  double look_spacing_m = 0.5;    ///< looks at a cell count from stops at least this far apart [m]
  double judgedLength(const Frontier& f) const
  {
    return judge_opening && f.unknown_m2 >= judge_opening_min_unknown_m2 ? f.opening_m : f.size_m;
  }
  /// Is f a closed pocket that enclosed_unknown_m2 leaves alone?
  bool enclosed(const Frontier& f) const { return f.unknown_m2 < enclosed_unknown_m2; }
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Is p closer than r to one of `points` (a blacklisted target)?
bool nearAny(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& points, double r);

/// @brief thesis 4.5.4 "unknown border selection": index into frontiers of
///        the nearest frontier longer than th_f1, else longer than th_f2,
///        skipping `skip` (indices) and frontiers near a blacklisted point.
/// @return empty when none qualifies (exploration done)
/// @param rank optional, one per frontier: chosen by least rank instead of
///        least distance (the tour's order), within each threshold tier.
/// @param first optional, one per frontier: the frontiers marked 1 and
///        longer than th_f2 come before both tiers (the robot's room,
///        RoomParams::finish_room), by the same key.
std::optional<std::size_t> chooseFrontier(
    const std::vector<Frontier>& frontiers, const SamplingParams& p,
    const std::vector<Eigen::Vector2d>& blacklist, const std::vector<std::size_t>& skip = {},
    const std::vector<double>* rank = nullptr, const std::vector<uint8_t>* first = nullptr);

/// @brief An order of frontiers to visit (issue 12).
struct FrontierTour
{
  std::vector<std::size_t> order;  ///< indices into FrontierMap::frontiers, the next first
  double length_m = 0;             ///< travel from the robot through all of them [m]
};

/// @brief Open tour (a path from node 0 through every node, no return) over
///        the cost matrix d (square; d[i][j] from i to j): nearest insertion,
///        then 2-opt. Node 0 stays first.
/// @return node indices, 0 first
std::vector<int> openTour(const std::vector<std::vector<double>>& d);

/// @brief The tour from the robot's cell through the centres of the
///        frontiers `nodes` (indices into fm.frontiers), on travel costs over
///        the cells the robot's BFS reached (fm.distance_m >= 0) in blocks of
///        about cell_m (Dijkstra, 8-connected).
///        Frontiers not connected to the robot cost 1e5 m and come last.
FrontierTour frontierTour(const FrontierMap& fm, const Cell& robot,
                          const std::vector<std::size_t>& nodes, double cell_m);

/// @brief Sample space: reachable Free cells whose distance to the nearest
///        frontier cell is in [d_min_sample, d_max_sample] and that see at
///        least one frontier cell along a 4-connected Bresenham line not
///        blocked by an Occupied cell (thesis fig. 4.15).
std::vector<Cell> sampleSpace(
    const GroundGrid& g, const CollisionSpace& cs, const FrontierMap& fm, const Frontier& f,
    const SamplingParams& p);

/// @brief The nearest strategy's viewing stand-off (footprint model,
///        SamplingParams::view_standoff_m > 0): of the reachable cells
///        between view_standoff_m and view_standoff_m + 1 m of the frontier
///        that see it (sampleSpace, the sight blocked by unknown cells that
///        are not open unknown when standoff_sight_blocked_by_unknown or
///        sight_blocked_by_unknown), the one nearest the frontier's centre.
/// @return none when no cell of that ring sees the frontier
std::optional<Eigen::Vector2d> standoffGoal(
    const GroundGrid& g, const CollisionSpace& cs, const FrontierMap& fm, const Frontier& f,
    const SamplingParams& p);

/// @brief Up to max_samples random cells of the sample space, pairwise at
///        least min_sample_dist apart (drawn from `rng` only: deterministic
///        for a seed); yaw towards the frontier's center.
std::vector<mrpt::poses::CPose2D> samplePoses(
    const Grid<SpaceState>& grid, const std::vector<Cell>& space, const Frontier& f,
    const SamplingParams& p, std::mt19937_64& rng);

}  // namespace voxplore::exploration
