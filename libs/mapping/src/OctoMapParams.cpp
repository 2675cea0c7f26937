/* voxplore — OctoMapParams: ini section [octomap] (thesis 4.4.3). */
#include <mrpt/config/CConfigFileBase.h>
#include <voxplore/common/config.h>
#include <voxplore/mapping/OctoMapLayer.h>

#include <string>

namespace voxplore::mapping
{
void OctoMapParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(l_res_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(th_free, int, c, s);
  MRPT_LOAD_CONFIG_VAR(th_occ, int, c, s);
  MRPT_LOAD_CONFIG_VAR(start_value, int, c, s);
  MRPT_LOAD_CONFIG_VAR(prob_hit, double, c, s);
  MRPT_LOAD_CONFIG_VAR(prob_miss, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clamp_min, double, c, s);
  MRPT_LOAD_CONFIG_VAR(clamp_max, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(invalid_free_range_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(start_box_x_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(start_box_y_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(start_box_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacle_min_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacle_max_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacle_floor_z_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacle_min_hits, int, c, s);
  MRPT_LOAD_CONFIG_VAR(low_obstacle_min_share, double, c, s);
  using common::requireValid;
  requireValid(l_res_m > 0, c, s, "l_res_m", "must be > 0");
  requireValid(start_value == 128, c, s, "start_value",
               "OctoMap starts every voxel at p = 0.5, i.e. 128 on the 0..255 scale; "
               "other priors are not supported");
  requireValid(th_free >= 0 && th_free < start_value, c, s, "th_free",
               "need 0 <= th_free < start_value");
  requireValid(th_occ > start_value && th_occ <= 255, c, s, "th_occ",
               "need start_value < th_occ <= 255");
  requireValid(prob_hit > 0.5 && prob_hit < 1, c, s, "prob_hit", "need 0.5 < prob_hit < 1");
  requireValid(prob_miss > 0 && prob_miss < 0.5, c, s, "prob_miss", "need 0 < prob_miss < 0.5");
  requireValid(clamp_min > 0 && clamp_min < probOf(th_free), c, s, "clamp_min",
               "need 0 < clamp_min < th_free / 255 (else no voxel can ever become free)");
  requireValid(clamp_max > clamp_min && clamp_max < 1 && clamp_max > probOf(th_occ), c, s,
               "clamp_max",
               "need th_occ / 255 < clamp_max < 1 (else no voxel can ever become occupied)");
  requireValid(max_range_m > 0, c, s, "max_range_m", "must be > 0");
  requireValid(invalid_free_range_m >= 0, c, s, "invalid_free_range_m", "must be >= 0");
  requireValid(start_box_x_m >= 0, c, s, "start_box_x_m", "must be >= 0");
  requireValid(start_box_y_m >= 0, c, s, "start_box_y_m", "must be >= 0");
  requireValid(start_box_z_m >= 0, c, s, "start_box_z_m", "must be >= 0");
  requireValid(low_obstacle_min_z_m >= 0, c, s, "low_obstacle_min_z_m", "must be >= 0 (0 = off)");
  if (low_obstacle_min_z_m > 0)
  {
    requireValid(low_obstacle_max_z_m > low_obstacle_min_z_m, c, s, "low_obstacle_max_z_m",
                 "need low_obstacle_max_z_m > low_obstacle_min_z_m");
    requireValid(low_obstacle_floor_z_m <= low_obstacle_min_z_m, c, s, "low_obstacle_floor_z_m",
                 "need low_obstacle_floor_z_m <= low_obstacle_min_z_m");
    requireValid(low_obstacle_min_hits >= 1, c, s, "low_obstacle_min_hits", "must be >= 1");
    requireValid(low_obstacle_min_share > 0 && low_obstacle_min_share <= 1, c, s,
                 "low_obstacle_min_share", "need 0 < low_obstacle_min_share <= 1");
  }
}

void OctoMapParams::saveToConfigFile(mrpt::config::CConfigFileBase& c, const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(l_res_m, c, s);
  MRPT_SAVE_CONFIG_VAR(th_free, c, s);
  MRPT_SAVE_CONFIG_VAR(th_occ, c, s);
  MRPT_SAVE_CONFIG_VAR(start_value, c, s);
  MRPT_SAVE_CONFIG_VAR(prob_hit, c, s);
  MRPT_SAVE_CONFIG_VAR(prob_miss, c, s);
  MRPT_SAVE_CONFIG_VAR(clamp_min, c, s);
  MRPT_SAVE_CONFIG_VAR(clamp_max, c, s);
  MRPT_SAVE_CONFIG_VAR(max_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(invalid_free_range_m, c, s);
  MRPT_SAVE_CONFIG_VAR(start_box_x_m, c, s);
  MRPT_SAVE_CONFIG_VAR(start_box_y_m, c, s);
  MRPT_SAVE_CONFIG_VAR(start_box_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacle_min_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacle_max_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacle_floor_z_m, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacle_min_hits, c, s);
  MRPT_SAVE_CONFIG_VAR(low_obstacle_min_share, c, s);
}

}  // namespace voxplore::mapping
