/* voxplore — the robot's rectangle in (x, y, yaw): a collision space per yaw
 * bin, reachability over position and yaw, and paths whose waypoints carry
 * the yaw to hold (issue 13; the thesis' future work 6.2: "the robot might
 * only fit through if it is rotated correctly"). Our own code: MRPT's
 * planners and PTGs know the robot as a circle. */
#pragma once

#include <mrpt/poses/CPose2D.h>
#include <voxplore/exploration/path.h>
#include <voxplore/exploration/stages.h>

#include <cstdint>
#include <optional>
#include <vector>

namespace voxplore::exploration
{
/// @brief Per cell, one bit per yaw bin. The rectangle centred on the robot
///        is symmetric under a half turn, so the bins cover [0, pi): bin k
///        holds the yaws [k - 1/2, k + 1/2] * pi / bins (modulo pi).
using YawMask = uint64_t;

/// @brief The orientation collision space and what the robot reaches in it.
struct FootprintSpace
{
  int bins = 0;           ///< yaw bins over [0, pi), 2..64
  double length_m = 0;    ///< the rectangle along the robot's +X [m]
  double width_m = 0;     ///< ... along +Y [m]
  double margin_m = 0;    ///< kept from every occupied / open unknown cell [m]
  /// Bit k: at the cell centre, at every yaw of bin k, the rectangle grown by
  /// margin_m touches no Occupied cell (each cell a full square of G).
  Grid<YawMask> clear_occ;
  /// ... and no open Unknown cell (CollisionSpace::open_unknown) either.
  Grid<YawMask> clear;
  /// clear with turn_margin_m: turning in place between two bins needs both
  /// here (the footprint guard holds a turn that brings a corner within its
  /// margin of a sensed point; the map is off by up to a cell). Also the
  /// states the path prefers: a translation outside it costs double.
  Grid<YawMask> clear_turn;
  double turn_margin_m = 0;  ///< >= margin_m [m]
  /// Bit k: the state (cell, k) is reached from the robot's state by moving
  /// to an 8-neighbour in the same bin (a diagonal move needs both cells
  /// beside it in that bin too) or turning in place to the next bin, through
  /// `clear` states, after an escape from the start through states clear of
  /// occupied cells by escape_margin_m when the start is not clear (the
  /// cameras leave unknown round the body at first).
  Grid<YawMask> reach;
  /// The escape: states the start reaches through states clear of occupied
  /// cells by escape_margin_m, up to the first turnable state, and the clear
  /// ones among them (what planFootprintPath may enter besides `clear`, and
  /// turn between besides `clear_turn` when it finds no path otherwise: the
  /// search follows every state the reach holds).
  Grid<YawMask> escape;
  /// The margin the escape keeps from occupied cells [m]: margin_m, or less
  /// (down to -2 cells) when the start state is within margin_m of one.
  double escape_margin_m = 0;
  /// The start was blocked even 2 cells inside the margin (occupied cells
  /// under the body: a pose or map error of decimetres): the escape ignored
  /// the occupied cells under the rectangle at the robot's pose.
  bool escape_ignored_occupied = false;
  /// The start was clear but boxed in (no turnable state reached through
  /// clear ones, or a reach shorter than the body): the escape went through
  /// states clear of occupied cells by margin_m, turning without
  /// turn_margin_m, up to the first turnable state not reached.
  bool escape_boxed_in = false;
  Cell robot;         ///< the robot's cell
  int robot_bin = 0;  ///< the bin of the robot's yaw

  double binWidth() const;
  /// @brief Yaw of bin k's centre [rad], in [0, pi).
  double binYaw(int k) const;
  /// @brief The bin holding `yaw_rad` (any angle).
  int binOf(double yaw_rad) const;
  /// @brief Bits of every bin.
  YawMask allBins() const;
  /// @brief States the search may enter at row-major cell i: clear or escape.
  YawMask allowed(std::size_t i) const { return clear.data()[i] | escape.data()[i]; }
  /// @brief Bins between which the search may turn at cell i: clear_turn or escape.
  YawMask turnable(std::size_t i) const { return clear_turn.data()[i] | escape.data()[i]; }
  /// @brief The bins one bin off a bin of m, either way (circularly).
  YawMask neighbourBins(YawMask m) const;
  /// @brief The bins of `allowed` that turning in place from `seed` reaches
  ///        (circularly connected runs of `allowed` holding a bit of seed).
  YawMask turnClosure(YawMask seed, YawMask allowed) const;
  /// @brief The yaw nearest `yaw_rad` at which the robot stands at the cell
  ///        with row-major index i: `yaw_rad` itself when its bin is reached
  ///        there, else the centre of the nearest reached bin, the half turn
  ///        of it nearer `yaw_rad` (what planFootprintPath's final yaw
  ///        turns to). Empty when no bin is reached at the cell.
  std::optional<double> nearestReachedYaw(std::size_t i, double yaw_rad) const;
};

/// @brief The orientation collision space of the rectangle
///        (p.footprint_length_m x p.footprint_width_m, grown by
///        p.footprint_margin_m, and by p.footprint_turn_margin_m for turning) on G, with p.yaw_bins bins, and its
///        reachability from `robot`. Exact at the cell centres for every yaw of
///        a bin: each obstacle cell is a square of G's resolution, tested
///        analytically against the rectangle (a precomputed mask per cell
///        offset, stamped from the border cells of the occupied and of the
///        open unknown space only).
///        `swept` (the poses the robot's centre has held, map frame): their
///        states, and those of the 4-connected cells between consecutive
///        poses, count as clear of unknown and turnable where no occupied
///        square lies within the margin (the body was there; the cameras
///        never see the floor round it).
/// @throws std::logic_error (ASSERTMSG_) on yaw_bins outside 2..64 or a
///         footprint <= 0.
FootprintSpace computeFootprintSpace(
    const GroundGrid& g, const CollisionSpace& cs, const CollisionParams& p,
    const mrpt::poses::CPose2D& robot, const SweptPath& swept = {});

/// @brief Keeps `fs`'s layers (left empty) for the next computeFootprintSpace
///        on this thread: it fills them in place instead of faulting in
///        fresh pages. Up to five layers are kept (the memory of one space).
void recycleFootprintSpace(FootprintSpace&& fs);

/// @brief Footprint model: the states of cs become those of the rectangle.
///        Free: some bin reached (the robot can stand there); MaybeCollision:
///        not reached, some bin clear of occupied cells but none clear of open
///        unknown (the band frontiers are found in); Collision: otherwise.
///        Occupied and Unknown stay. The circle's clearance grids stay (the
///        path cost and the narrow-passage test use them).
void applyFootprint(CollisionSpace& cs, const FootprintSpace& fs);

/// @brief A* over (cell, yaw bin) from `start` to any bin at `goal`'s cell
///        through states FootprintSpace::allowed, turning only between
///        clear_turn bins and escape bins that are not clear (and, when that
///        finds no path, between any FootprintSpace::turnable bins, as the
///        escape did): translations cost their length times
///        PathParams' clearance factor (doubled outside clear_turn), a turn by
///        one bin costs its arc at half the circumradius. Runs of one bin are shortcut by line
///        of sight (every sample's cell allows the bin) and cut into
///        max_segment_m pieces. Path::yaws holds the yaw to hold on the way to
///        each waypoint (the bin's yaw, or the half turn of it nearest the
///        previous yaw), Path::narrow whether the planner's circle
///        (CollisionSpace::radius_m) does not fit somewhere on that way.
///        final_yaw: `goal_yaw` when turning in place at the goal reaches its
///        bin, else the reachable bin's yaw nearest to it.
/// @return empty when the goal cell is off the grid or not reached.
/// @param cost_from_start footprintCostFromStart(cs, fs, p), shared by the
///        goals of one planning step (computed here when null or when `start`
///        is not in fs.robot's cell). The search runs from the goal back to
///        the start, guided by it (weighted A*, p.footprint_heuristic_weight:
///        the path costs at most that times the optimum).
/// @param end_in_goal_bin the path ends in goal_yaw's bin (turning in place
///        at the goal on the way when it must) where one exists, else as
///        above: a target rated at goal_yaw is seen from there
///        (SamplingParams::rate_reached_yaw).
std::optional<Path> planFootprintPath(
    const CollisionSpace& cs, const FootprintSpace& fs, const mrpt::poses::CPose2D& start,
    const Eigen::Vector2d& goal, double goal_yaw, const PathParams& p,
    const std::vector<float>* cost_from_start = nullptr, bool end_in_goal_bin = false);

/// @brief Does the rectangle keep the turn margin (FootprintSpace::clear_turn,
///        whole bins) at every yaw from yaw0 to yaw1 (unwrapped: that way
///        round; a whole turn or more: every yaw) all along a-b (samples half
///        a cell apart)? False where a-b leaves the grid.
/// @param in_proportion Only at the yaws of a turn made in proportion to
///        the way (StopAndScanDriver's turn on the way): at each sample, the
///        yaws from the one a sample before to the one a sample after.
bool turnClearAlong(const CollisionSpace& cs, const FootprintSpace& fs, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b, double yaw0, double yaw1, bool in_proportion = false);

/// @brief Does the rectangle hold `yaw` (FootprintSpace::clear, the
///        translation layer of its bin) all along a-b (samples half a cell
///        apart)? False where a-b leaves the grid.
bool holdClearAlong(const CollisionSpace& cs, const FootprintSpace& fs, const Eigen::Vector2d& a,
                    const Eigen::Vector2d& b, double yaw);

/// @brief Where a footprint translation from `from` to `to` that starts in
///        yaw0 and holds yaw1 (unwrapped from yaw0: that way round) makes
///        the turn, in proportion, on its first 0.6, 0.3, 0.15 or 0.1 m (longest
///        first, at most half the way): where turnClearAlong() holds the turn
///        there and holdClearAlong() yaw1 on to `to`. Empty where none does.
///        Our own (the SE(2) search plans turns in place only): a turn in
///        place at a passage's mouth costs a stop and the rotation's tail.
std::optional<Eigen::Vector2d> turnFirstSplit(const CollisionSpace& cs, const FootprintSpace& fs,
                                              const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                              double yaw0, double yaw1);

/// @brief The first waypoint after waypoint k not at its position (after the
///        turns in place there); w.size() when there is none.
std::size_t nextTranslation(const std::vector<Eigen::Vector2d>& w, std::size_t k);

/// @brief Makes waypoint k of a footprint path (Path's or PlanResult's
///        parallel vectors) a lead-in to `yaw` (a footprint drive,
///        Path::kTurnFromAnyYaw) and erases waypoints k+1..m-1 (its turns in
///        place); waypoint m (< w.size()), when it turned on its way there
///        (Path::kTurnFromPrevious), turns no more: the robot arrives in its yaw.
void makeLeadIn(std::vector<Eigen::Vector2d>& w, std::vector<double>& yaws,
                std::vector<uint8_t>& narrow, std::vector<uint8_t>& turn_on_way, std::size_t k,
                std::size_t m, double yaw);

/// @brief Inserts a footprint waypoint (narrow) at index `at` of the four
///        parallel vectors of a path (Path, or a PlanResult's waypoints):
///        `point`, held in (or turned on its way to) `yaw`, `turn_on_way` as
///        Path::turn_on_way.
void insertWaypoint(std::vector<Eigen::Vector2d>& w, std::vector<double>& yaws,
                    std::vector<uint8_t>& narrow, std::vector<uint8_t>& turn_on_way, std::size_t at,
                    const Eigen::Vector2d& point, double yaw, uint8_t turn_on_way_at);

/// @brief Per cell (row-major over cs.state), a lower bound of the cost
///        planFootprintPath pays from fs.robot's cell to it: a Dijkstra over the
///        cells holding a reached or escape state, a step costing its length
///        times PathParams::costFactor of the cell entered; +infinity where the
///        robot cannot get. The SE(2) A*'s heuristic.
std::vector<float> footprintCostFromStart(
    const CollisionSpace& cs, const FootprintSpace& fs, const PathParams& p);

}  // namespace voxplore::exploration
