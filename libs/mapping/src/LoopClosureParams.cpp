// [loop_closure]: LoopClosureParams read from and written to ini files,
// each key checked with a message naming it (see LoopClosure.h).
#include <voxplore/common/config.h>
#include <voxplore/mapping/LoopClosure.h>

namespace voxplore::mapping
{
void LoopClosureParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(enabled, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(min_travel_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(search_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(submap_radius_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(submap_cell_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(submap_pass_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(anchor_check_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(anchor_check_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(anchor_pass_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(anchor_min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(drift_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_window_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_window_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(yaw_drift_per_m, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(min_window_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(max_window_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(min_goodness, double, c, s);
  MRPT_LOAD_CONFIG_VAR(min_points, int, c, s);
  MRPT_LOAD_CONFIG_VAR(margin, double, c, s);
  MRPT_LOAD_CONFIG_VAR(probe_ratio, double, c, s);
  MRPT_LOAD_CONFIG_VAR(probe_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(probe_tol_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(consistent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(consistent_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_within, int, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_xy_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(confirm_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_min_move_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(confirm_min_turn, c, s);
  MRPT_LOAD_CONFIG_VAR(confirm_when_consistent, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(chain_recent_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(implicit_min_old_share, double, c, s);
  MRPT_LOAD_CONFIG_VAR(implicit_min_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(rebuild_min_shift_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(octomap_rebuild_per_stop, int, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_sigma_floor_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_info_scale, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_min_std_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(edge_max_std_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(edge_min_std_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(edge_max_std_yaw, c, s);
  MRPT_LOAD_CONFIG_VAR(odometry_std_per_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR_DEGREES(odometry_std_yaw_per_m, c, s);
  MRPT_LOAD_CONFIG_VAR(max_iterations, int, c, s);
  using common::requireValid;
  requireValid(min_travel_m >= 0, c, s, "min_travel_m", "must be >= 0 m");
  requireValid(octomap_rebuild_per_stop >= 0, c, s, "octomap_rebuild_per_stop",
               "must be >= 0 keyframes (0 = the whole OctoMap at the closing stop)");
  requireValid(search_radius_m > 0, c, s, "search_radius_m", "must be > 0 m");
  requireValid(submap_radius_m >= search_radius_m, c, s, "submap_radius_m",
               "must be >= search_radius_m");
  requireValid(submap_cell_m > 0 && submap_cell_m < 1, c, s, "submap_cell_m", "must be in (0, 1) m");
  requireValid(submap_pass_m >= 0, c, s, "submap_pass_m", "must be >= 0 (0 = off)");
  requireValid(anchor_check_m >= 0, c, s, "anchor_check_m", "must be >= 0 (0 = off)");
  requireValid(anchor_check_yaw >= 0, c, s, "anchor_check_yaw", "must be >= 0");
  requireValid(anchor_pass_m > 0, c, s, "anchor_pass_m", "must be > 0 m");
  requireValid(anchor_min_goodness > 0 && anchor_min_goodness <= 1, c, s, "anchor_min_goodness",
               "must be in (0, 1]");
  requireValid(drift_per_m >= 0, c, s, "drift_per_m", "must be >= 0");
  requireValid(min_window_m > 0 && max_window_m >= min_window_m, c, s, "min_window_m",
               "must be > 0 and <= max_window_m");
  requireValid(min_window_yaw >= 0 && max_window_yaw >= min_window_yaw, c, s, "min_window_yaw",
               "must be >= 0 and <= max_window_yaw");
  requireValid(min_goodness > 0 && min_goodness <= 1, c, s, "min_goodness", "must be in (0, 1]");
  requireValid(min_points >= 0, c, s, "min_points", "must be >= 0 (0 = no limit)");
  requireValid(margin >= 0 && margin < 1, c, s, "margin", "must be in [0, 1)");
  requireValid(probe_ratio >= 0 && probe_ratio <= 1, c, s, "probe_ratio",
               "must be in [0, 1] (0 = off)");
  requireValid(probe_m > 0 && probe_tol_m > 0 && probe_tol_m < probe_m, c, s, "probe_m",
               "probe_m and probe_tol_m must be > 0 m, probe_tol_m < probe_m");
  requireValid(chain_recent_m >= 0, c, s, "chain_recent_m", "must be >= 0 m (0 = off)");
  requireValid(implicit_min_old_share >= 0 && implicit_min_old_share <= 1, c, s, "implicit_min_old_share",
               "must be in [0, 1]");
  requireValid(implicit_min_m >= 0, c, s, "implicit_min_m", "must be >= 0 m");
  requireValid(confirm_within >= 1, c, s, "confirm_within", "must be >= 1");
  requireValid(confirm_min_move_m >= 0, c, s, "confirm_min_move_m", "must be >= 0");
  requireValid(confirm_min_turn >= 0, c, s, "confirm_min_turn", "must be >= 0");
  requireValid(edge_min_std_m > 0 && edge_max_std_m >= edge_min_std_m, c, s, "edge_min_std_m",
               "must be > 0 and <= edge_max_std_m");
  requireValid(edge_min_std_yaw > 0 && edge_max_std_yaw >= edge_min_std_yaw, c, s,
               "edge_min_std_yaw", "must be > 0 and <= edge_max_std_yaw");
  requireValid(edge_info_scale > 0 && edge_sigma_floor_m > 0, c, s, "edge_info_scale",
               "edge_info_scale and edge_sigma_floor_m must be > 0");
  requireValid(odometry_std_per_m > 0 && odometry_std_yaw_per_m > 0, c, s, "odometry_std_per_m",
               "odometry_std_per_m and odometry_std_yaw_per_m must be > 0");
  requireValid(max_iterations >= 1, c, s, "max_iterations", "must be >= 1");
}

void LoopClosureParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(enabled, c, s);
  MRPT_SAVE_CONFIG_VAR(min_travel_m, c, s);
  MRPT_SAVE_CONFIG_VAR(search_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(submap_radius_m, c, s);
  MRPT_SAVE_CONFIG_VAR(submap_cell_m, c, s);
  MRPT_SAVE_CONFIG_VAR(submap_pass_m, c, s);
  MRPT_SAVE_CONFIG_VAR(anchor_check_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(anchor_check_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(anchor_pass_m, c, s);
  MRPT_SAVE_CONFIG_VAR(anchor_min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(drift_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR(min_window_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_window_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(yaw_drift_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(min_window_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(max_window_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(min_goodness, c, s);
  MRPT_SAVE_CONFIG_VAR(min_points, c, s);
  MRPT_SAVE_CONFIG_VAR(margin, c, s);
  MRPT_SAVE_CONFIG_VAR(probe_ratio, c, s);
  MRPT_SAVE_CONFIG_VAR(probe_m, c, s);
  MRPT_SAVE_CONFIG_VAR(probe_tol_m, c, s);
  MRPT_SAVE_CONFIG_VAR(consistent_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(consistent_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_within, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_xy_m, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(confirm_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_min_move_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(confirm_min_turn, c, s);
  MRPT_SAVE_CONFIG_VAR(confirm_when_consistent, c, s);
  MRPT_SAVE_CONFIG_VAR(chain_recent_m, c, s);
  MRPT_SAVE_CONFIG_VAR(implicit_min_old_share, c, s);
  MRPT_SAVE_CONFIG_VAR(implicit_min_m, c, s);
  MRPT_SAVE_CONFIG_VAR(rebuild_min_shift_m, c, s);
  MRPT_SAVE_CONFIG_VAR(octomap_rebuild_per_stop, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_sigma_floor_m, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_info_scale, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_min_std_m, c, s);
  MRPT_SAVE_CONFIG_VAR(edge_max_std_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(edge_min_std_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(edge_max_std_yaw, c, s);
  MRPT_SAVE_CONFIG_VAR(odometry_std_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR_DEGREES(odometry_std_yaw_per_m, c, s);
  MRPT_SAVE_CONFIG_VAR(max_iterations, c, s);
}

}  // namespace voxplore::mapping
