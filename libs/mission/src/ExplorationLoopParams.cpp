// The exploration loop's ini section [explore] (ExplorationLoopParams): its
// keys, their checks and auto values. Split from ExplorationLoop.cpp.
#include <voxplore/common/config.h>
#include <voxplore/mission/ExplorationLoop.h>

#include <optional>
#include <string>

namespace voxplore::mission
{
double ExplorationLoopParams::turnOnTheWayDegInForce(double configured, ScanMode mode)
{
  if (configured >= 0) return configured;
  return mode == ScanMode::Continuous ? 150.0 : 0.0;
}

void ExplorationLoopParams::loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
                                               const std::string& s)
{
  MRPT_LOAD_CONFIG_VAR(max_steps, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_sim_time_s, double, c, s);
  MRPT_LOAD_CONFIG_VAR(max_failures_per_target, int, c, s);
  MRPT_LOAD_CONFIG_VAR(max_plans_per_target, int, c, s);
  MRPT_LOAD_CONFIG_VAR(min_progress_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(approach_replanned, bool, c, s);
  if (const std::string v = c.read_string(s, "low_obstacle_replan", ""); !v.empty())
  {
    const std::optional<bool> b = common::parseBoolWord(v);
    common::requireValid(v == "auto" || b.has_value(), c, s, "low_obstacle_replan",
                         "expected auto, true or false");
    low_obstacle_replan = !b ? Switch::Auto : *b ? Switch::On : Switch::Off;
  }
  if (const std::string v = c.read_string(s, "scan_mode", ""); !v.empty())
  {
    common::requireValid(v == "stop_and_scan" || v == "continuous", c, s, "scan_mode",
                         "expected stop_and_scan or continuous");
    scan_mode = v == "continuous" ? ScanMode::Continuous : ScanMode::StopAndScan;
  }
  MRPT_LOAD_CONFIG_VAR(scan_rate_hz, double, c, s);
  MRPT_LOAD_CONFIG_VAR(scan_every_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(scan_every_deg, double, c, s);
  MRPT_LOAD_CONFIG_VAR(pass_tolerance_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(replan_on_the_way, bool, c, s);
  if (const std::string v = c.read_string(s, "replan_at_stops", ""); !v.empty())
  {
    const std::optional<bool> b = common::parseBoolWord(v);
    common::requireValid(v == "auto" || b.has_value(), c, s, "replan_at_stops",
                         "expected auto, true or false");
    replan_at_stops = !b ? Switch::Auto : *b ? Switch::On : Switch::Off;
  }
  MRPT_LOAD_CONFIG_VAR(seen_gate, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(seen_gate_verify, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(seen_gate_fraction, double, c, s);
  common::requireValid(seen_gate_fraction > 0 && seen_gate_fraction <= 1, c, s,
                       "seen_gate_fraction", "must be in (0, 1]");
  MRPT_LOAD_CONFIG_VAR(half_turn_views, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(scan_latency_s, double, c, s);
  common::requireValid(scan_latency_s >= 0 && scan_latency_s <= 5, c, s, "scan_latency_s",
                       "must be in [0, 5] [s]");
  common::requireValid(scan_rate_hz > 0 && scan_rate_hz <= 20, c, s, "scan_rate_hz",
                       "must be in (0, 20] (the O3D100's frame rate)");
  common::requireValid(scan_every_m >= 0, c, s, "scan_every_m", "must be >= 0");
  common::requireValid(scan_every_deg >= 0, c, s, "scan_every_deg", "must be >= 0");
  common::requireValid(pass_tolerance_m > 0, c, s, "pass_tolerance_m", "must be > 0");
  MRPT_LOAD_CONFIG_VAR(stagnation_new_frontier_guard, bool, c, s);
  MRPT_LOAD_CONFIG_VAR(stagnation_steps, int, c, s);
  MRPT_LOAD_CONFIG_VAR(stagnation_min_gain_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stagnation_path_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(stagnation_path_min_gain_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tail_path_m, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tail_min_gain_m2, double, c, s);
  MRPT_LOAD_CONFIG_VAR(tail_pocket_m2, double, c, s);
  common::requireValid(tail_path_m >= 0, c, s, "tail_path_m", "must be >= 0 (0 = off)");
  common::requireValid(tail_min_gain_m2 >= 0, c, s, "tail_min_gain_m2", "must be >= 0");
  common::requireValid(tail_pocket_m2 >= 0, c, s, "tail_pocket_m2", "must be >= 0");
  MRPT_LOAD_CONFIG_VAR(cut_off_replan_m2, double, c, s);
  common::requireValid(cut_off_replan_m2 >= 0, c, s, "cut_off_replan_m2", "must be >= 0");
  common::requireValid(stagnation_steps >= 0, c, s, "stagnation_steps", "must be >= 0");
  common::requireValid(stagnation_min_gain_m2 >= 0, c, s, "stagnation_min_gain_m2", "must be >= 0");
  common::requireValid(stagnation_path_m >= 0, c, s, "stagnation_path_m", "must be >= 0");
  common::requireValid(stagnation_path_min_gain_m2 >= 0, c, s, "stagnation_path_min_gain_m2",
                       "must be >= 0");
  common::requireValid(max_steps >= 0, c, s, "max_steps", "must be >= 0");
  common::requireValid(max_sim_time_s > 0, c, s, "max_sim_time_s", "must be > 0");
  common::requireValid(max_plans_per_target >= 0, c, s, "max_plans_per_target", "must be >= 0");
  common::requireValid(min_progress_m >= 0, c, s, "min_progress_m", "must be >= 0");
  common::requireValid(max_failures_per_target >= 1, c, s, "max_failures_per_target",
                       "must be >= 1");
}

bool ExplorationLoopParams::lowObstacleReplanInForce(const exploration::CollisionParams& col,
                                                     double l_res_m) const
{
  if (low_obstacle_replan != Switch::Auto) return low_obstacle_replan == Switch::On;
  return col.usesFootprint(l_res_m) && !col.footprintTrimmed(l_res_m);
}

bool ExplorationLoopParams::replanAtStopsInForce(bool nbv) const
{
  return replan_at_stops == Switch::Auto ? nbv : replan_at_stops == Switch::On;
}

void ExplorationLoopParams::saveToConfigFile(mrpt::config::CConfigFileBase& c,
                                             const std::string& s) const
{
  MRPT_SAVE_CONFIG_VAR(max_steps, c, s);
  MRPT_SAVE_CONFIG_VAR(max_sim_time_s, c, s);
  MRPT_SAVE_CONFIG_VAR(max_failures_per_target, c, s);
  MRPT_SAVE_CONFIG_VAR(max_plans_per_target, c, s);
  MRPT_SAVE_CONFIG_VAR(min_progress_m, c, s);
  MRPT_SAVE_CONFIG_VAR(approach_replanned, c, s);
  c.write(s, "low_obstacle_replan",
          low_obstacle_replan == Switch::Auto ? "auto"
          : low_obstacle_replan == Switch::On ? "true"
                                              : "false");
  c.write(s, "scan_mode", scan_mode == ScanMode::Continuous ? "continuous" : "stop_and_scan");
  MRPT_SAVE_CONFIG_VAR(scan_rate_hz, c, s);
  MRPT_SAVE_CONFIG_VAR(scan_every_m, c, s);
  MRPT_SAVE_CONFIG_VAR(scan_every_deg, c, s);
  MRPT_SAVE_CONFIG_VAR(pass_tolerance_m, c, s);
  MRPT_SAVE_CONFIG_VAR(replan_on_the_way, c, s);
  c.write(s, "replan_at_stops",
          replan_at_stops == Switch::Auto ? "auto"
          : replan_at_stops == Switch::On ? "true"
                                          : "false");
  MRPT_SAVE_CONFIG_VAR(seen_gate, c, s);
  MRPT_SAVE_CONFIG_VAR(seen_gate_verify, c, s);
  MRPT_SAVE_CONFIG_VAR(seen_gate_fraction, c, s);
  MRPT_SAVE_CONFIG_VAR(half_turn_views, c, s);
  MRPT_SAVE_CONFIG_VAR(scan_latency_s, c, s);
  MRPT_SAVE_CONFIG_VAR(stagnation_new_frontier_guard, c, s);
  MRPT_SAVE_CONFIG_VAR(stagnation_steps, c, s);
  MRPT_SAVE_CONFIG_VAR(stagnation_min_gain_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(tail_path_m, c, s);
  MRPT_SAVE_CONFIG_VAR(tail_min_gain_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(tail_pocket_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(stagnation_path_m, c, s);
  MRPT_SAVE_CONFIG_VAR(stagnation_path_min_gain_m2, c, s);
  MRPT_SAVE_CONFIG_VAR(cut_off_replan_m2, c, s);
}

}  // namespace voxplore::mission
