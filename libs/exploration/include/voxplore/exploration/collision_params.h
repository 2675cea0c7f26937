/* voxplore — [collision]: the planner's robot model and its margins (thesis
 * 4.5.2, and the footprint planning of issue 13). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <string>

namespace voxplore::exploration
{
/// @brief ini section [collision].
struct CollisionParams : public mrpt::config::CLoadableOptions
{
  double r_coll_m = 0.698;  ///< robot collision radius sqrt((l/2)^2 + (w/2)^2) (omniRob) [m]
  /// Unknown cells 4-adjacent to an occupied cell (unseen wall bases) make
  /// no MaybeCollision disc (it closes narrow corridors); the obstacle's own
  /// Collision band covers them. false = thesis 4.5.2.
  bool ignore_unknown_beside_obstacles = true;
  /// Unknown pockets in which no cell lies deeper than this from known space
  /// (and that do not touch the grid border) are closed: wall interiors, the
  /// unseen backs of furniture. Closed unknown makes no MaybeCollision and no
  /// frontier. 0 = every unknown cell is open (thesis) [m].
  double min_open_unknown_depth_m = 0.10;
  /// plan(): low obstacle cells (OctoMapLayer) are stamped Occupied where
  /// the voxel columns left them Unknown too, not only Free: a table base
  /// under its top (the columns never seen) is an obstacle, not a frontier
  /// (turtlebot3_house, the compact robot's footprint: the run did not end).
  /// The unknown round them stays open as the columns have it.
  bool low_obstacles_on_unknown = true;
  /// The robot model the planner plans for (ini key "model"): Circle is the
  /// thesis (4.5.2: a disc of r_coll_m, so no passage narrower than about
  /// 2 r_coll); Footprint plans in (x, y, yaw) with the rectangle (footprint.h);
  /// Auto is Footprint when the planner's circle is wider than
  /// auto_footprint_above_m (usesFootprint), else Circle.
  enum class Model
  {
    Circle,
    Footprint,
    Auto
  };
  /// Footprint by default for both robots since the twenty-sixth session:
  /// the compact robot's footprint with its "auto" margin (0.05 m) and
  /// low-obstacle replans against its circle, b1-b10 both strategies:
  /// coverage_2d mean / worst nbv 0.952 / 0.854 -> 0.978 / 0.970, nearest
  /// 0.966 / 0.941 -> 0.977 / 0.964, 0 collisions, path +14 % / +5 %;
  /// turtlebot3_house 0.30 -> 0.97 (BENCHMARKS.md twenty-sixth session).
  Model model = Model::Footprint;
  /// Model::Auto: plan with the footprint when the planner circle's diameter
  /// 2 (r_coll + sqrt(2) l_res) exceeds this [m]. An office door is 0.8-1.0
  /// m wide: a wider circle closes the building's rooms to the robot (the
  /// omniRob's 1.54 m circle: 0.02-0.94 coverage of 10 generated buildings,
  /// its footprint 0.66-0.97, BENCHMARKS.md), a narrower one passes them
  /// (the compact robot's 0.76 m circle, which misses turtlebot3_house's
  /// courtyard behind a 0.70 m door).
  double auto_footprint_above_m = 1.0;
  /// @brief The planner circle's diameter 2 (r_coll + sqrt(2) l_res) on a
  ///        map of resolution l_res_m [m].
  double plannerCircleDiameter(double l_res_m) const;
  /// @brief The model planned with on a map of resolution l_res_m: Circle or
  ///        Footprint (Auto resolved, see model).
  Model modelInForce(double l_res_m) const;
  /// @brief modelInForce(l_res_m) == Model::Footprint.
  bool usesFootprint(double l_res_m) const { return modelInForce(l_res_m) == Model::Footprint; }
  static const char* toString(Model m);
  /// The rectangle (length along the robot's +X, width) [m]; not ini keys,
  /// set from the robot profile like r_coll_m.
  double footprint_length_m = 1.200, footprint_width_m = 0.712;
  /// Footprint: kept from every occupied / open unknown cell at the cell
  /// centres [m]. kAuto (ini "auto", the default): marginInForce().
  double footprint_margin_m = kAuto;
  /// "auto" footprint_margin_m: auto_margin_max_m where the robot still
  /// passes auto_door_m with it and exact margins (the compact robot: 0.61
  /// m at 5 cm), else auto_margin_min_m (the omniRob, whose doors leave no
  /// room for more). The wider margin keeps the body off what the planner's
  /// band and cameras miss: the band above the camera ring (0.60-0.65 m) and
  /// a sloped surface's 3 cm contour (aws_small_house nbv: 1 collision at
  /// 0.02, none at 0.05; BENCHMARKS.md twenty-sixth session) [m].
  double auto_margin_min_m = 0.02;
  double auto_margin_max_m = 0.05;  ///< see auto_margin_min_m [m]
  double footprint_turn_margin_m = 0.05;  ///< Footprint: ... while turning in place (and preferred) [m]
  int yaw_bins = 32;                 ///< Footprint: yaw bins over [0, 180) deg, 2..64
  /// Footprint: an occupied (or open unknown) cell counts as a square of this
  /// share of its side round its centre. 1: the whole cell, an exact bound of
  /// the surface in it (up to a cell wider than the surface: a 0.85 m door
  /// maps to 0.80 m and closes to the rectangle plus margins); below 1 the
  /// surface is assumed in the cell's middle, and the footprint guard's
  /// margin round the sensed points is what keeps the body off it.
  /// 0.5 by default since the twenty-third session: on the 26 omniRob
  /// building runs coverage_2d mean/worst nbv 0.964/0.932 -> 0.971/0.942,
  /// nearest 0.959/0.885 -> 0.968/0.920, runs >= 0.95 20 -> 24 of 26
  /// (BENCHMARKS.md twenty-second session). kAuto (ini "auto", the
  /// default): see footprintTrimmed().
  double footprint_square_share = kAuto;
  /// Footprint: the same for turning in place (clear_turn, with
  /// footprint_turn_margin_m). Whole cells by default whatever
  /// footprint_square_share says: with half squares for both, the plans
  /// turned where the guard held the body (b3 omniRob nearest 0.955 ->
  /// 0.614, BENCHMARKS.md seventeenth session).
  double footprint_turn_square_share = 1.0;
  /// Footprint: the share of a bin's yaw width, round its centre, at which a
  /// state must keep footprint_margin_m to be clear for translation (1: every
  /// yaw of the bin; 0: the bin's centre yaw, the yaw a footprint path holds:
  /// the 1.2 m body's corners swing 2.9 cm over a 5.6 deg bin, which closed
  /// 0.85-0.90 m doors). Turning in place always keeps the turn margin over
  /// the whole bin. 0.35 (the default, sixteenth session): +-1 deg of a
  /// 5.6 deg bin, what the drive holds (the guard keeps the real body off
  /// what the cameras sense); with footprint_lateral_m it took the omniRob
  /// through 21 of 29 doors under 0.90 m instead of 8 (BENCHMARKS.md).
  double footprint_bin_span = 0.35;
  /// Footprint: a state is clear for translation also when the rectangle
  /// fits moved up to this far sideways (across the bin's centre yaw, the
  /// way the robot drives in that bin) from the cell centre: states lie on
  /// cell centres, and a door whose middle falls between two centres lost
  /// up to a cell of its width (b1, omniRob: a 0.90 m door mapped 0.80 m
  /// wide was 1 mm too narrow at both centres). The driver's footprint
  /// centring moves the body that far sideways where the sensed points ask
  /// for it. 0: cell centres only; kAuto (ini "auto", the default): half a
  /// cell when footprintTrimmed(), else 0 [m].
  double footprint_lateral_m = kAuto;
  /// footprint_margin_m / footprint_square_share / footprint_lateral_m
  /// "auto": the value resolved at the map's resolution (marginInForce,
  /// squareShareInForce, lateralInForce).
  static constexpr double kAuto = -1.0;
  /// "auto" margins: the narrowest door the robot must pass [m]. Exact
  /// margins (whole squares, cell centres) while exactDoorM fits it, else
  /// trimmed (half squares, half a cell sideways): the omniRob needs 0.902
  /// m at 5 cm (trimmed), the compact robot 0.61 m with its 5 cm margin
  /// (exact: trimmed it hit furniture legs, aws_small_house nearest 5
  /// collisions, exact 0).
  double auto_door_m = 0.85;
  /// @brief The door the rectangle needs with exact margins on a map of
  ///        resolution l_res_m: footprint_width_m + 2 margin + 3 l_res_m,
  ///        margin = marginInForce(l_res_m) [m].
  double exactDoorM(double l_res_m) const { return doorWithMargin(marginInForce(l_res_m), l_res_m); }
  /// @brief footprint_width_m + 2 margin_m + 3 l_res_m [m].
  double doorWithMargin(double margin_m, double l_res_m) const
  {
    return footprint_width_m + 2.0 * margin_m + 3.0 * l_res_m;
  }
  /// @brief footprint_margin_m, "auto" resolved: auto_margin_max_m when
  ///        doorWithMargin(auto_margin_max_m) fits auto_door_m, else
  ///        auto_margin_min_m [m].
  double marginInForce(double l_res_m) const;
  /// @brief Whether "auto" margins are trimmed: exactDoorM(l_res_m) > auto_door_m.
  bool footprintTrimmed(double l_res_m) const { return exactDoorM(l_res_m) > auto_door_m; }
  /// @brief footprint_square_share, "auto" resolved: 0.5 trimmed, else 1.
  double squareShareInForce(double l_res_m) const;
  /// @brief footprint_lateral_m, "auto" resolved: l_res_m / 2 trimmed, else 0.
  double lateralInForce(double l_res_m) const;
  /// Circle model: the cells round the poses the robot's centre has swept
  /// (the cell and its 8 neighbours) are Free when they keep r_coll_m +
  /// swept_passage_margin_m from every occupied cell centre: the robot's
  /// body was there. The thesis' reachability runs over Free cells only (a
  /// band of MaybeCollision at its rim), so a door whose jambs are unknown
  /// (a double wall after drift: thick enough to be open unknown) is
  /// MaybeCollision from side to side, and shut a robot that had driven in
  /// through it in one room: the run ended "no frontier" (b5, compact, nbv,
  /// finish_room: 0.748). false = thesis.
  bool swept_passage = false;
  double swept_passage_margin_m = 0.05;  ///< kept beyond r_coll_m on the swept cells [m]
  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};
}  // namespace voxplore::exploration
