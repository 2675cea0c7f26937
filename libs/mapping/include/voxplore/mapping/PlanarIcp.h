/* voxplore — planar (x, y, yaw) ICP of a stop's cloud against the metaview (thesis 4.4.2). */
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/core/bits_math.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <string>
#include <functional>
#include <vector>

namespace voxplore::mapping
{
/// @brief ICP settings. ini section [icp].
struct IcpParams : public mrpt::config::CLoadableOptions
{
  bool enabled = true;             ///< false: odometry only (dead reckoning)
  double d_max_m = 0.5;            ///< correspondence search radius at the start (thesis d_max) [m]
  double d_max_final_m = 0.05;     ///< the radius anneals down to this [m]
  double alfa = 0.5;               ///< radius annealing factor per convergence (MRPT ALFA)
  int coarse_iterations = 15;      ///< stage 1, mrpt::slam::CICP (point-to-point) iterations; 0 skips it
  int decimation = 5;              ///< stage 1: CICP matches every N-th cloud point
  int max_iterations = 30;         ///< stage 2, point-to-line Gauss-Newton iterations at most (3x when a degenerate direction is fused with odometry)
  int max_points = 2000;           ///< stage 2: cloud points used (evenly subsampled)
  double huber_m = 0.02;           ///< stage 2: Huber kernel width on point-to-line residuals [m]
  double point_weight = 0.3;       ///< stage 2: weight of point-to-point pairs (metaview not line-like: legs, corners)
  double min_goodness = 0.5;       ///< accept only when this share of points found a pair
  /// A registration under min_goodness is accepted still when at least this
  /// share paired, it converged, is not degenerate, and agrees with odometry
  /// (correction within 2 odometry stds of the step, at least 2 cm; yaw
  /// within 2 deg): a stop that sees mostly new space (through a door, round
  /// a corner) pairs little of its cloud. Refused, it stayed out of the map,
  /// the next stop saw even more that the map lacked, and 92 stops in a row
  /// were refused (b3 compact nearest, pockets campaign: ATE 0.17 m, 0.54).
  /// 0 = min_goodness only.
  double low_overlap_min_goodness = 0.25;
  double max_correction_xy_m = 0.5;  ///< accept only corrections of the odometry prediction up to this [m]
  double max_correction_yaw = mrpt::DEG2RAD(10.0);  ///< ... and this [rad] (ini: deg)
  /// SlamIcp: max_correction_xy_m widens to this many odometry stds
  /// (odometryStdXy summed over the steps since the last stop ICP
  /// registered), for registrations at least confirm_min_goodness good and
  /// not degenerate. A 170 deg turn's odometry came 0.67 m off (3.7 stds):
  /// ICP found it, the fixed 0.5 m refused it, and every later stop, off by as
  /// much and with less of the map in view, was refused too (b3 compact nbv:
  /// 29 stops in a row, the map frozen, the run over at 0.06). 0 = the fixed
  /// limit only.
  double correction_gate_sigmas = 4;
  /// A registration refused only for its correction (beyond max_correction_*)
  /// is taken after all when the next stop, registered from the prediction
  /// carrying the same correction, agrees (SlamIcp): odometry that turned
  /// 10-12 deg off over one long drive otherwise kept 4-14 stops in a row
  /// on dead reckoning (measured in generated buildings).
  bool confirm_large_corrections = true;
  double confirm_xy_m = 0.10;                 ///< the next stop agrees within this [m] ...
  double confirm_yaw = mrpt::DEG2RAD(2.0);    ///< ... and this [rad] (ini: deg)
  double confirm_min_goodness = 0.7;          ///< both registrations at least this good
  /// A correction beyond max_correction_* (through the gate or confirmed by
  /// the next stop) needs a cloud of at least this many points: a few
  /// hundred points of one wall or cabinet pair fully (goodness 1) after a
  /// shift along a look-alike structure. willowgarage, compact robot: of 5
  /// gated corrections from 55-314 points (out of the open areas where no
  /// wall is in range), 2 moved the pose 0.5-0.8 m further off the truth and
  /// 3 left it 0.5-2.7 m off; every gated or confirmed correction of the 80
  /// campaign runs had over 9,000. 0 = any cloud.
  int large_correction_min_points = 1000;
  /// @brief Whether a cloud of `points` may correct beyond max_correction_*
  ///        (large_correction_min_points; alignPlanar's gate and SlamIcp's
  ///        confirmation both ask this).
  bool largeCorrectionAllowed(std::size_t points) const
  {
    return static_cast<double>(points) >= large_correction_min_points;
  }
  /// SlamIcp: an accepted registration that moved the prediction by more
  /// than hold_sigmas odometry stds (summed since the last registered stop)
  /// and more than hold_min_m, at a goodness under hold_sure_goodness, is
  /// held instead: the stop stays out of the map at its prediction until the
  /// next stop, registered from the prediction carrying the same correction,
  /// agrees (as confirm_large_corrections). An omniRob standing in a 0.86 m
  /// door, one camera blind against a jamb, registered 0.25 m (36 stds) along
  /// the wall at goodness 0.58; the jambs mapped after sat 0.25 m from those
  /// mapped before and shut the door (b13 omniRob nbv: coverage 0.38).
  /// 0 = off.
  double hold_sigmas = 8;
  double hold_min_m = 0.10;         ///< ... and more than this [m] ...
  double hold_sure_goodness = 0.9;  ///< ... from a registration less good than this
  /// SlamIcp: a stop whose registration was refused or held, while its
  /// odometry prediction pairs at least as much of the cloud as that
  /// registration did (goodnessAt() at the prediction >= the registration's
  /// goodness, and >= min_goodness), keeps the prediction and
  /// enters the map: ICP made the fit worse, odometry is the better estimate.
  /// The b13 door stop paired 0.70 of its cloud at the prediction (4 cm from
  /// the truth) and 0.58 where ICP put it; refused, the stops into the room
  /// behind it found too little of the map to register and kept the map
  /// from growing there. false = refused stops stay out of the map.
  bool keep_fitting_prediction = true;
  /// ... and a stop refused for its goodness (it sees mostly new space)
  /// right after a held stop keeps the prediction too, however the
  /// registration paired, while the odometry std since the last registered
  /// stop is at most this [m]: a held stop at a new room's door (b5 omniRob
  /// nbv, half squares) left the room unmapped, and the 20 stops into it,
  /// pairing 0.27-0.57 of their clouds, were refused (the run ended at
  /// 0.09). After an ordinary refusal such a stop is refused: kept there, 6
  /// of 9 predictions pairing 0.28-0.47 put their stop 1.8-4.2 cm further off
  /// the truth, and the map with it (omniRob runs at the defaults).
  /// The same bound holds for a refused (not held) registration's prediction
  /// that fits better (keep_fitting_prediction): after 9 refused stops a
  /// prediction 11 cm off paired 0.54 of its cloud, was kept, and the run
  /// ended at 0.947 (b1 omniRob nbv). 0 = only a held stop's prediction.
  double keep_low_overlap_max_std_m = 0.03;
  bool degeneracy_check = true;    ///< detect directions the scene does not constrain
  double degeneracy_ratio = 0.03;  ///< smallest/largest translational information eigenvalue below this = degenerate
  /// Along a degenerate direction, weigh the scene's weak information
  /// against the odometry increment's uncertainty (a prior whose standard
  /// deviation comes from the motion model below) instead of keeping the
  /// prediction whole. Needs the step's odometry std (alignPlanar's
  /// `odometry_std_m`; SlamIcp gives it): a turning step's odometry is
  /// 10-25 cm off along a corridor where a door jamb still fixes the
  /// position to 1-2 cm (generated buildings, compact robot); a straight
  /// step in a featureless corridor keeps its odometry as before.
  bool degenerate_fusion = true;
  /// The odometry increment's xy standard deviation (MRPT's Gaussian motion
  /// model, CActionRobotMovement2D, applied to the whole increment):
  /// max(odometry_std_xy_min_m, per_m x distance + per_rad x |turn|).
  double odometry_std_xy_per_m = 0.01;    ///< [m per m]
  double odometry_std_xy_per_rad = 0.0573;  ///< [m per rad]
  double odometry_std_xy_min_m = 0.005;   ///< [m]
  /// The standard deviation of one stage-2 pair when it is weighed against
  /// odometry: the residual noise (about 1 cm) over the square root of the
  /// share of independent pairs (loop closure's edge_info_scale, 0.05) [m].
  double pair_std_m = 0.045;
  /// When the odometry increment's std (above) is at least this and the
  /// registration from the prediction is accepted, ICP also starts from the
  /// prediction shifted by multi_start_scale x std along +-x and +-y (map
  /// frame), and the best accepted result wins when its paired share beats
  /// the prediction's by multi_start_margin. A 0.97 m step
  /// turning 88 deg (odometry 21 cm off) converged 10 cm and 1.1 deg off
  /// (goodness 0.968) even against the true map, where the truth pairs
  /// 0.998 (willowgarage, compact robot). 0 = one start (the prediction),
  /// the default: in a map already torn by drift a start pairs more of the
  /// cloud 20-35 cm off (willowgarage replay: ATE 0.266 m without, 0.349
  /// with 0.04); in the generated buildings it fixed 19 stops (up to 21
  /// cm) and worsened 13 (up to 5 cm). BENCHMARKS.md, twelfth session.
  double multi_start_min_std_m = 0.0;
  double multi_start_scale = 1.5;   ///< the starts' offset in stds
  double multi_start_margin = 0.01; ///< paired share a start must gain over the prediction's result
  /// Stage 2 holds the odometry prediction's translation with this weight,
  /// counted in point-to-line pairs along each axis (the cloud has at most
  /// max_points): where the walls say little (along a corridor) the
  /// prediction keeps the position, elsewhere the scene dominates. 0 = off.
  double odometry_prior_pairs = 0.0;
  /// SlamIcp gives odometry_prior_pairs in full to steps up to this long
  /// (translation + 1 m x turn); a longer step L gets (this / L)^2 of it [m].
  double odometry_prior_step_m = 0.5;
  /// Stage 2 pairs a cloud point with a line of the reference only when both
  /// were seen from the same side of it (needs the reference's viewpoints).
  /// Without it a wall seen from its far side (after a door) slides onto
  /// its near face, a wall thickness away: measured on generated buildings
  /// (0.15 m walls), steps jumped by 0.13-0.15 m at 17 of 390 stops.
  bool same_side_only = true;
  double normal_radius_m = 0.25;   ///< neighbourhood of the metaview line fits (normals, information matrix) [m]
  /// A neighbourhood that is no line over normal_radius_m (a corner, or a
  /// wall's two faces) is fitted again over this radius (below the wall
  /// thickness), so that each face keeps its line; 0 = not [m].
  double normal_radius_small_m = 0.10;
  int min_points = 50;             ///< fewer cloud points: no ICP (keep odometry, flag)
  /// Stage 2 that has not converged within max_iterations is accepted only
  /// when its last update moved less than this (translation [m], or rotation
  /// [rad] times 1 m); else it is rejected as not converged.
  double max_unconverged_step_m = 0.01;
  /// After a rejected registration (a wrong prediction: odometry jump,
  /// kidnap) search poses around the prediction (relocalizePlanar).
  bool relocalize = true;
  double relocalize_radius_m = 1.5;  ///< search radius around the prediction [m]
  double relocalize_yaw = mrpt::DEG2RAD(45.0);  ///< search half-width in yaw [rad] (ini: deg)
  double relocalize_min_goodness = 0.85;  ///< accept a relocalisation only with this goodness
  /// ... and only when no other, distinct pose scores within this goodness of it (ambiguity)
  double relocalize_margin = 0.15;
  /// SlamIcp's body check: a registration (ICP, relocalisation, a confirmed
  /// or kept prediction) that puts more than body_max_voxels occupied voxels
  /// of the OctoMap inside the robot's body rectangle (body_length_m x
  /// body_width_m, the robot's footprint, shrunk by body_margin_m on each
  /// side, between body_z_min_m and body_z_max_m) is refused: the robot
  /// cannot stand in a mapped wall. 0 x 0 = off (voxplore-explore sets the
  /// robot's footprint unless the ini does).
  double body_length_m = 0;
  double body_width_m = 0;
  double body_margin_m = 0.05;     ///< [m]
  double body_z_min_m = 0.10;      ///< [m]
  double body_z_max_m = 0.60;      ///< [m]
  int body_max_voxels = 1;
  /// After a registration refused for the body (the scene offered a wrong
  /// minimum near the prediction) relocalisation accepts from this goodness
  /// (instead of relocalize_min_goodness), among poses whose body is clear.
  double body_relocalize_min_goodness = 0.75;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s) override;
  void saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const override;
};

/// @brief Where each reference point was seen from: the robot's (x, y) in the
///        map frame when the point entered the map, index-aligned with the
///        reference map's points.
using Viewpoints = std::vector<Eigen::Vector2f>;

/// @brief Outcome of one registration.
struct IcpResult
{
  mrpt::poses::CPose2D pose;        ///< refined T_map_robot (= the prediction when not accepted)
  mrpt::poses::CPose2D icp_pose;    ///< what ICP converged to (before degeneracy handling)
  double goodness = 0;              ///< share of cloud points with a metaview point within d_max_final_m
  /// Share of the cloud points paired within d_max_final_m (goodness without
  /// the points refused for the side of their line: a cloud laid onto a
  /// wall's other face scores on goodness, not here).
  double paired_share = 0;
  unsigned iterations = 0;          ///< stage 1 + stage 2 iterations
  bool converged = false;           ///< stage 2 reached a fixed point at d_max_final_m
  double last_step_m = 0;           ///< stage 2's last update: translation [m] or rotation [rad] x 1 m, the larger
  double rms_m = 0;                 ///< point-to-line RMS residual of the final pairs [m]
  bool accepted = false;            ///< false: the prediction was kept
  /// Refused only because the correction exceeded max_correction_* (converged,
  /// good enough, finite): a candidate for confirmation by the next stop.
  bool over_correction_limit = false;
  std::string reason;               ///< why not accepted / what was adjusted
  bool degenerate = false;          ///< a translation direction was unconstrained
  Eigen::Vector2d degenerate_dir{0, 0};  ///< unit vector (map frame) of that direction
  double info_ratio = 0;            ///< smallest / largest translational information eigenvalue
  std::size_t pairs = 0;            ///< correspondences in the information matrix
  /// Which start won (alignPlanarMultiStart): 0 = the prediction, 1-4 the
  /// shifted starts (+x, -x, +y, -y); starts tried (1 = only the prediction).
  unsigned start = 0, starts_tried = 1;
  /// Point-to-line information J^T J at the solution (map-frame x, y and yaw
  /// about the robot; unscaled by the noise): the pose-graph edge's information.
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
};

/// @brief Registers `cloud_robot` (robot frame) against `reference_map`
///        (map frame) starting from `predicted`, in two stages:
///        1. mrpt::slam::CICP (2D, classic point-to-point) for a few
///           iterations from d_max_m: robust to a poor start;
///        2. our point-to-line Gauss-Newton refinement (normals of the
///           metaview, Huber weights, radius annealed to d_max_final_m).
///        Stage 2 exists because of a measured weakness of CICP on our data:
///        point-to-point converges slowly on sampled surfaces (300 iterations,
///        about 1 s per stop, on dlr_test_room; at 100 iterations the replay
///        ATE is 3.8 cm), while point-to-line converges in a few iterations.
///        The result is accepted when it is finite, stage 2 converged (or
///        its last update was below max_unconverged_step_m), goodness >=
///        min_goodness and the correction is within max_correction_*;
///        otherwise the prediction is kept and `reason` says why. With degeneracy_check, the point-to-line information
///        matrix at the solution (normals from the metaview) is analysed:
///        along a direction whose information is below degeneracy_ratio of
///        the strongest one (a featureless corridor) the odometry prediction
///        is kept and ICP's correction is used only across it; with
///        degenerate_fusion and `odometry_std_m` > 0 the prediction is
///        instead a prior of that standard deviation along the direction,
///        weighed against the scene's information there (pair_std_m per
///        pair), and the solution is the information-weighted one. With
///        `reference_viewpoints` (and same_side_only) stage 2 ignores pairs
///        of a cloud point and a reference line seen from opposite sides.
///        `start`, when given, is where ICP starts instead of the prediction
///        (the correction limits and the odometry prior still refer to the
///        prediction). `gate_xy_m` > max_correction_xy_m (SlamIcp: IcpParams::
///        correction_gate_sigmas odometry stds) takes a larger correction, up
///        to it, when the registration is at least confirm_min_goodness good
///        and not degenerate.
IcpResult alignPlanar(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const mrpt::poses::CPose2D& predicted, const IcpParams& params,
    const Viewpoints* reference_viewpoints = nullptr, double odometry_std_m = 0.0,
    const mrpt::poses::CPose2D* start = nullptr, double gate_xy_m = 0.0);

/// @brief alignPlanar() from the prediction and, when `odometry_std_m` >=
///        multi_start_min_std_m and that result is accepted and not
///        degenerate, from four starts multi_start_scale x odometry_std_m
///        away from it (+-x, +-y, map frame): the accepted, non-degenerate
///        result with the highest paired share replaces the prediction's
///        when it beats it by multi_start_margin. A refused registration is
///        left to relocalisation and confirmation (SlamIcp): a start taken
///        over a refused one at goodness 0.59 put a stop 0.45 m off. Our own
///        (not MRPT's): a multi-hypothesis start within the odometry
///        uncertainty, cheaper than relocalizePlanar's search grid.
IcpResult alignPlanarMultiStart(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const mrpt::poses::CPose2D& predicted, const IcpParams& params,
    const Viewpoints* reference_viewpoints, double odometry_std_m, double gate_xy_m = 0.0);

/// @brief Goodness (IcpResult::goodness: share of the cloud with a
///        reference point within d_max_final_m, seen from the same side when
///        `reference_viewpoints` are given) of `cloud_robot` placed at `pose`,
///        without registering it.
double goodnessAt(const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
                  const mrpt::poses::CPose2D& pose, const IcpParams& p,
                  const Viewpoints* reference_viewpoints = nullptr);

/// @brief The xy standard deviation of an odometry increment `step` (robot
///        frame) under params' motion model (odometry_std_xy_*) [m].
double odometryStdXy(const mrpt::poses::CPose2D& step, const IcpParams& params);

/// @brief Relocalisation after a rejected alignPlanar(): scores seeds on a
///        grid round `predicted` (relocalize_radius_m in x, y; relocalize_yaw
///        in yaw) by the share of a subsample of the cloud within 0.1 m of
///        the reference, refines the best distinct seeds with alignPlanar()
///        (correction limits widened to the search window, min_goodness =
///        relocalize_min_goodness) and accepts the best refined pose only
///        when it is not degenerate and no distinct pose (> 0.2 m or 5 deg
///        away) comes within relocalize_margin of its goodness. A refined
///        pose that `admissible` (when given) refuses is no candidate at all
///        (SlamIcp: the robot's body would stand in a mapped obstacle).
/// @return the accepted result (reason "relocalized: ..."), or a rejected
///         one keeping `predicted` with the reason
IcpResult relocalizePlanar(
    const mrpt::maps::CPointsMap& reference_map, const mrpt::maps::CPointsMap& cloud_robot,
    const mrpt::poses::CPose2D& predicted, const IcpParams& params,
    const Viewpoints* reference_viewpoints = nullptr,
    const std::function<bool(const mrpt::poses::CPose2D&)>& admissible = {});

}  // namespace voxplore::mapping
