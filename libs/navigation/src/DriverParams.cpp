#include <mrpt/core/format.h>
#include <voxplore/common/config.h>
#include <voxplore/navigation/DriverParams.h>

#include <cmath>
#include <filesystem>
#include <system_error>

namespace voxplore::navigation
{
DriverParams DriverParams::forFootprint(double length_m, double width_m)
{
  DriverParams p;
  p.footprint_length_m = length_m;
  p.footprint_width_m = width_m;
  return p;
}

double DriverParams::robotRadius() const
{
  return std::hypot(0.5 * footprint_length_m, 0.5 * footprint_width_m) + shape_margin_m;
}

void DriverParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(footprint_length_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_width_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(shape_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_v_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_w, c, s);
  MRPT_LOAD_CONFIG_VAR(max_accel_mps2, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_angular_accel, c, s);
  MRPT_LOAD_CONFIG_VAR(min_obstacle_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_obstacle_height_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(obstacle_cell_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(dt_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(goal_tolerance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(blocked_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(progress_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_steps, int, c, s);
  MRPT_LOAD_CONFIG_VAR(straight_fallback, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(escape_clearance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(escape_speed_mps, double, c, s);
  MRPT_LOAD_CONFIG_VAR(escape_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_guard, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(guard_margin_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(guard_horizon_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(guard_hold_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_backoff_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(footprint_centring_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(yaw_tolerance, c, s);
  MRPT_LOAD_CONFIG_VAR(yaw_gain, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rotate_timeout_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(holonomic_method, string, c, s);
  MRPT_LOAD_CONFIG_VAR(ref_distance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(num_paths, int, c, s);
  MRPT_LOAD_CONFIG_VAR(t_ramp_max_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(target_slowdown, double, c, s);
  MRPT_LOAD_CONFIG_VAR(too_close_obstacle, double, c, s);
  MRPT_LOAD_CONFIG_VAR(secure_distance_start, double, c, s);
  MRPT_LOAD_CONFIG_VAR(secure_distance_end, double, c, s);
  MRPT_LOAD_CONFIG_VAR(verbose, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(navlog_dir, string, c, s);

  using common::requireValid;
  requireValid(footprint_length_m > 0, c, s, "footprint_length_m", "must be positive");
  requireValid(footprint_width_m > 0, c, s, "footprint_width_m", "must be positive");
  requireValid(shape_margin_m >= 0, c, s, "shape_margin_m", "must be >= 0");
  requireValid(max_v_mps > 0, c, s, "max_v_mps", "must be positive");
  requireValid(max_w > 0, c, s, "max_w", "must be positive");
  requireValid(max_accel_mps2 >= 0, c, s, "max_accel_mps2", "must be >= 0 (0 = no limit)");
  requireValid(max_angular_accel >= 0, c, s, "max_angular_accel", "must be >= 0 (0 = no limit)");
  requireValid(max_obstacle_height_m > min_obstacle_height_m, c, s, "max_obstacle_height_m",
               "must exceed min_obstacle_height_m");
  requireValid(obstacle_cell_m >= 0 && obstacle_cell_m <= 0.5, c, s, "obstacle_cell_m",
               "must be in [0, 0.5] m");
  requireValid(dt_s > 0 && dt_s <= 1.0, c, s, "dt_s", "must be in (0, 1] s");
  requireValid(goal_tolerance_m > 0, c, s, "goal_tolerance_m", "must be positive");
  requireValid(timeout_s > 0, c, s, "timeout_s", "must be positive");
  requireValid(blocked_timeout_s > 0, c, s, "blocked_timeout_s", "must be positive");
  requireValid(progress_min_m > 0, c, s, "progress_min_m", "must be positive");
  requireValid(max_steps > 0, c, s, "max_steps", "must be positive");
  requireValid(escape_clearance_m >= 0, c, s, "escape_clearance_m", "must be >= 0");
  requireValid(escape_speed_mps > 0 && escape_speed_mps <= max_v_mps, c, s, "escape_speed_mps",
               "must be in (0, max_v_mps]");
  requireValid(escape_timeout_s > 0, c, s, "escape_timeout_s", "must be positive");
  requireValid(guard_margin_m >= 0 && guard_margin_m <= 0.5, c, s, "guard_margin_m",
               "must be in [0, 0.5] m");
  requireValid(guard_horizon_s >= dt_s, c, s, "guard_horizon_s",
               "must be at least dt_s (a command is held for dt_s)");
  requireValid(guard_hold_s >= dt_s, c, s, "guard_hold_s", "must be at least dt_s");
  requireValid(footprint_backoff_m >= 0, c, s, "footprint_backoff_m", "must be >= 0");
  requireValid(footprint_centring_m >= 0 && footprint_centring_m <= 0.5, c, s,
               "footprint_centring_m", "must be in [0, 0.5]");
  requireValid(yaw_tolerance > 0, c, s, "yaw_tolerance", "must be positive");
  requireValid(yaw_gain > 0 && yaw_gain * dt_s < 2.0, c, s, "yaw_gain",
               "must be positive and below 2 / dt_s (else the rotation oscillates)");
  requireValid(rotate_timeout_s > 0, c, s, "rotate_timeout_s", "must be positive");
  // CHolonomicVFF never moves the robot with our PTG (DESIGN.md): not offered.
  requireValid(holonomic_method == "CHolonomicND" || holonomic_method == "CHolonomicFullEval", c, s,
               "holonomic_method", "must be CHolonomicND or CHolonomicFullEval");
  requireValid(ref_distance_m > robotRadius(), c, s, "ref_distance_m",
               "must exceed the robot radius (footprint circumradius + shape_margin_m)");
  requireValid(num_paths >= 5 && num_paths <= 721, c, s, "num_paths", "must be in [5, 721]");
  requireValid(t_ramp_max_s > 0, c, s, "t_ramp_max_s", "must be positive");
  requireValid(target_slowdown > 0 && target_slowdown <= 1, c, s, "target_slowdown",
               "must be in (0, 1]");
  requireValid(too_close_obstacle > 0 && too_close_obstacle < 1, c, s, "too_close_obstacle",
               "must be in (0, 1)");
  requireValid(secure_distance_start >= 0 && secure_distance_end > secure_distance_start &&
                   secure_distance_end <= 1,
               c, s, "secure_distance_end",
               "need 0 <= secure_distance_start < secure_distance_end <= 1");
  std::error_code ec;
  requireValid(navlog_dir.empty() || !std::filesystem::exists(navlog_dir, ec) ||
                   std::filesystem::is_directory(navlog_dir, ec),
               c, s, "navlog_dir", "names an existing file, not a directory: '" + navlog_dir + "'");
}

void DriverParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(footprint_length_m, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_width_m, c, s);
  MRPT_SAVE_CONFIG_VAR(shape_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_v_mps, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_w, c, s);
  MRPT_SAVE_CONFIG_VAR(max_accel_mps2, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_angular_accel, c, s);
  MRPT_SAVE_CONFIG_VAR(min_obstacle_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_obstacle_height_m, c, s);
  MRPT_SAVE_CONFIG_VAR(obstacle_cell_m, c, s);
  MRPT_SAVE_CONFIG_VAR(dt_s, c, s);
  MRPT_SAVE_CONFIG_VAR(goal_tolerance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(blocked_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(progress_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_steps, c, s);
  MRPT_SAVE_CONFIG_VAR(straight_fallback, c, s);
  MRPT_SAVE_CONFIG_VAR(escape_clearance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(escape_speed_mps, c, s);
  MRPT_SAVE_CONFIG_VAR(escape_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_guard, c, s);
  MRPT_SAVE_CONFIG_VAR(guard_margin_m, c, s);
  MRPT_SAVE_CONFIG_VAR(guard_horizon_s, c, s);
  MRPT_SAVE_CONFIG_VAR(guard_hold_s, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_backoff_m, c, s);
  MRPT_SAVE_CONFIG_VAR(footprint_centring_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(yaw_tolerance, c, s);
  MRPT_SAVE_CONFIG_VAR(yaw_gain, c, s);
  MRPT_SAVE_CONFIG_VAR(rotate_timeout_s, c, s);
  MRPT_SAVE_CONFIG_VAR(holonomic_method, c, s);
  MRPT_SAVE_CONFIG_VAR(ref_distance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(num_paths, c, s);
  MRPT_SAVE_CONFIG_VAR(t_ramp_max_s, c, s);
  MRPT_SAVE_CONFIG_VAR(target_slowdown, c, s);
  MRPT_SAVE_CONFIG_VAR(too_close_obstacle, c, s);
  MRPT_SAVE_CONFIG_VAR(secure_distance_start, c, s);
  MRPT_SAVE_CONFIG_VAR(secure_distance_end, c, s);
  MRPT_SAVE_CONFIG_VAR(verbose, c, s);
  MRPT_SAVE_CONFIG_VAR(navlog_dir, c, s);
}

namespace
{
// One ini writer for the MRPT sections, values as text.
struct MrptIni
{
  mrpt::config::CConfigFileBase& out;
  void put(const std::string& sec, const std::string& key, const std::string& value)
  {
    out.write(sec, key, value);
  }
  void put(const std::string& sec, const std::string& key, double value)
  {
    out.write(sec, key, mrpt::format("%.9g", value));
  }
};

// [CAbstractNavigator], [CWaypointsNavigator], [CAbstractPTGBasedReactive].
void writeNavigatorSections(const DriverParams& p, MrptIni& ini)
{
  // StopAndScanDriver decides "blocked" itself: MRPT's no-approach alarm
  // only after the whole waypoint timeout, and MRPT's "target inside
  // obstacles" check is off (distance 0): it tests the target against the
  // obstacles of the previous step at the current pose, so a robot turning at
  // 45 deg/s sees a free target 5 cm beyond its radius as blocked.
  const std::string an = "CAbstractNavigator";
  ini.put(an, "dist_to_target_for_sending_event", 0.0);
  ini.put(an, "alarm_seems_not_approaching_target_timeout", p.timeout_s + 1.0);
  ini.put(an, "dist_check_target_is_blocked", 0.0);
  ini.put(an, "hysteresis_check_target_is_blocked", 3.0);

  const std::string wn = "CWaypointsNavigator";  // unused: one waypoint at a time
  ini.put(wn, "max_distance_to_allow_skip_waypoint", -1.0);
  ini.put(wn, "min_timesteps_confirm_skip_waypoints", 1.0);
  ini.put(wn, "waypoint_angle_tolerance", 5.0);
  ini.put(wn, "multitarget_look_ahead", 0.0);

  const std::string pr = "CAbstractPTGBasedReactive";
  ini.put(pr, "robotMax_V_mps", p.max_v_mps);
  ini.put(pr, "robotMax_W_degps", mrpt::RAD2DEG(p.max_w));
  ini.put(pr, "holonomic_method", p.holonomic_method);
  ini.put(pr, "motion_decider_method", "CMultiObjMotionOpt_Scalarization");
  ini.put(pr, "ref_distance", p.ref_distance_m);
  ini.put(pr, "speedfilter_tau", 0.0);
  ini.put(pr, "secure_distance_start", p.secure_distance_start);
  ini.put(pr, "secure_distance_end", p.secure_distance_end);
  ini.put(pr, "use_delays_model", "false");
  ini.put(pr, "max_distance_predicted_actual_path", 0.15);
  ini.put(pr, "min_normalized_free_space_for_ptg_continuation", 0.2);
  ini.put(pr, "enable_obstacle_filtering", "false");  // static worlds: keep every point
  ini.put(pr, "evaluate_clearance", "false");
  ini.put(pr, "max_dist_for_timebased_path_prediction", 2.0);
}

// [CHolonomicND], [CHolonomicFullEval].
void writeHolonomicSections(const DriverParams& p, MrptIni& ini)
{
  const std::string nd = "CHolonomicND";
  ini.put(nd, "WIDE_GAP_SIZE_PERCENT", 0.25);
  ini.put(nd, "MAX_SECTOR_DIST_FOR_D2_PERCENT", 0.25);
  ini.put(nd, "RISK_EVALUATION_SECTORS_PERCENT", 0.10);
  ini.put(nd, "RISK_EVALUATION_DISTANCE", 0.4);
  ini.put(nd, "TOO_CLOSE_OBSTACLE", p.too_close_obstacle);
  ini.put(nd, "TARGET_SLOW_APPROACHING_DISTANCE", p.target_slowdown);
  // [0] free space, [1] distance in sectors, [2] closer to target, [3] hysteresis
  ini.put(nd, "factorWeights", "1.0 0.5 2.0 0.4");

  const std::string fe = "CHolonomicFullEval";
  ini.put(fe, "factorWeights", "[0.25 0.1 1 0.05 0.5 1 1]");
  ini.put(fe, "factorNormalizeOrNot", "[0 0 0 0 1 1 0]");
  ini.put(fe, "TOO_CLOSE_OBSTACLE", p.too_close_obstacle);
  ini.put(fe, "TARGET_SLOW_APPROACHING_DISTANCE", p.target_slowdown);
  ini.put(fe, "OBSTACLE_SLOW_DOWN_DISTANCE", 0.15);
  ini.put(fe, "HYSTERESIS_SECTOR_COUNT", 5.0);
  ini.put(fe, "clearance_threshold_ratio", 0.10);
  ini.put(fe, "gap_width_ratio_threshold", 0.20);
  ini.put(fe, "PHASE_COUNT", 3.0);
  ini.put(fe, "PHASE1_FACTORS", "[6]");
  ini.put(fe, "PHASE1_THRESHOLD", 0.5);
  ini.put(fe, "PHASE2_FACTORS", "[4]");
  ini.put(fe, "PHASE2_THRESHOLD", 0.7);
  ini.put(fe, "PHASE3_FACTORS", "[0 2]");
  ini.put(fe, "PHASE3_THRESHOLD", 0.7);
}

// [CMultiObjectiveMotionOptimizerBase], [CMultiObjMotionOpt_Scalarization]:
// candidate scores (exprtk), after MRPT's reactive2d_config.ini.
void writeMotionDeciderSections(MrptIni& ini)
{
  const std::string mo = "CMultiObjectiveMotionOptimizerBase";
  ini.put(mo, "score1_name", "target_distance");
  ini.put(mo, "score1_formula",
          "var effective_trg_d_norm := max(0,target_d_norm-move_cur_d); "
          "if(collision_free_distance>effective_trg_d_norm, 1/(1+effective_trg_d_norm^2), 0)");
  ini.put(mo, "score2_name", "collision_free_distance_score");
  ini.put(mo, "score2_formula",
          "var effective_trg_d_norm := max(0,target_d_norm-move_cur_d); "
          "if (collision_free_distance>(effective_trg_d_norm+0.05), 1.0, collision_free_distance)");
  ini.put(mo, "score3_name", "euclidean_nearness");
  ini.put(mo, "score3_formula", "1/(1+dist_eucl_min^2)");
  ini.put(mo, "score4_name", "hysteresis_score");
  ini.put(mo, "score4_formula", "hysteresis");
  ini.put(mo, "score5_name", "path_index_near_target");
  ini.put(mo, "score5_formula",
          "var dif:=abs(target_k-move_k); if (dif>(num_paths/2)) { dif:=num_paths-dif; }; "
          "exp(-abs(dif / (num_paths/10.0)));");
  ini.put(mo, "score6_name", "ptg_priority_score");
  ini.put(mo, "score6_formula", "ptg_priority");
  ini.put("CMultiObjMotionOpt_Scalarization", "scalar_score_formula",
          "ptg_priority_score*(0.3*target_distance + 0.5*collision_free_distance_score + "
          "8.0*euclidean_nearness + 0.1*hysteresis_score + 0.2*path_index_near_target)");
}

// [CReactiveNavigationSystem]: obstacle heights, the PTG, the robot shape.
void writeReactiveSection(const DriverParams& p, MrptIni& ini)
{
  const std::string rn = "CReactiveNavigationSystem";
  ini.put(rn, "min_obstacles_height", p.min_obstacle_height_m);
  ini.put(rn, "max_obstacles_height", p.max_obstacle_height_m);
  ini.put(rn, "PTG_COUNT", 1.0);
  ini.put(rn, "PTG0_Type", "CPTG_Holo_Blend");
  ini.put(rn, "PTG0_num_paths", static_cast<double>(p.num_paths));
  ini.put(rn, "PTG0_refDistance", p.ref_distance_m);
  ini.put(rn, "PTG0_T_ramp_max", p.t_ramp_max_s);
  ini.put(rn, "PTG0_v_max_mps", p.max_v_mps);
  ini.put(rn, "PTG0_w_max_dps", mrpt::RAD2DEG(p.max_w));
  ini.put(rn, "PTG0_score_priority", 1.0);
  // CPTG_Holo_Blend is a circular-robot PTG: it uses the circle; the polygon
  // (the footprint plus the margin) is given for completeness.
  const double hl = 0.5 * p.footprint_length_m + p.shape_margin_m;
  const double hw = 0.5 * p.footprint_width_m + p.shape_margin_m;
  ini.put(rn, "RobotModel_shape2D_xs", mrpt::format("%.6f %.6f %.6f %.6f", -hl, hl, hl, -hl));
  ini.put(rn, "RobotModel_shape2D_ys", mrpt::format("%.6f %.6f %.6f %.6f", hw, hw, -hw, -hw));
  ini.put(rn, "RobotModel_circular_shape_radius", p.robotRadius());
}
}  // namespace

void DriverParams::writeMrptConfig(mrpt::config::CConfigFileBase& out) const
{
  MrptIni ini{out};
  writeNavigatorSections(*this, ini);
  writeHolonomicSections(*this, ini);
  writeMotionDeciderSections(ini);
  writeReactiveSection(*this, ini);
}

}  // namespace voxplore::navigation
