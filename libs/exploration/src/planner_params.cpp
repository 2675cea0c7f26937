/* voxplore — the planner's parameters: the sections of planner.ini and the
 * values resolved from the robot and the map (split from Planner.cpp). */
#include <voxplore/common/config.h>
#include <voxplore/exploration/Planner.h>

#include <cmath>
#include <optional>
#include <set>
#include <string>

namespace voxplore::exploration
{
void PlannerParams::load(const mrpt::config::CConfigFileBase& cfg)
{
  common::loadChecked(projection, cfg, "projection");
  common::loadChecked(collision, cfg, "collision");
  common::loadChecked(sampling, cfg, "sampling");
  common::loadChecked(rooms, cfg, "rooms");
  std::set<std::string> cam_keys;
  for (int i = 0; i < 64; i++) cam_keys.insert("cam" + std::to_string(i) + "_pose");
  common::assertKnownKeys(cfg, "scan_rating", rating, cam_keys);
  common::assertNumericValues(cfg, "scan_rating", rating);
  rating.loadFromConfigFile(cfg, "scan_rating");
  common::loadChecked(path, cfg, "path");
  common::assertKnownKeys(cfg, "planner",
                          std::set<std::string>{"strategy", "seed", "frontier_order", "tour_cell_m",
                                                "frontier_tiers"});
  const std::string s = cfg.read_string("planner", "strategy", "nbv");
  common::requireValid(s == "nbv" || s == "nearest", cfg, "planner", "strategy", "expected nbv or nearest");
  strategy = s == "nbv" ? Strategy::NextBestView : Strategy::NearestFrontier;
  seed = static_cast<int>(common::readDoubleStrict(cfg, "planner", "seed", seed));
  const std::string o = cfg.read_string("planner", "frontier_order", "nearest");
  common::requireValid(o == "tour" || o == "nearest", cfg, "planner", "frontier_order",
                       "expected tour or nearest");
  frontier_order = o == "tour" ? FrontierOrder::Tour : FrontierOrder::Nearest;
  tour_cell_m = common::readDoubleStrict(cfg, "planner", "tour_cell_m", tour_cell_m);
  common::requireValid(tour_cell_m > 0 && tour_cell_m <= 0.2, cfg, "planner", "tour_cell_m",
                       "must be in (0, 0.2] (larger blocks may join the two sides of a wall)");
  const std::string tiers = cfg.read_string("planner", "frontier_tiers", frontier_tiers ? "true" : "false");
  const std::optional<bool> t = common::parseBoolWord(tiers);
  common::requireValid(t.has_value(), cfg, "planner", "frontier_tiers", "expected true or false");
  frontier_tiers = *t;
}

SamplingParams PlannerParams::frontierOrderInForce() const
{
  SamplingParams out = sampling;
  if (strategy == Strategy::NextBestView && !frontier_tiers) out.th_f1_m = out.th_f2_m;
  return out;
}

void PlannerParams::setFootprint(double length_m, double width_m)
{
  projection.footprint_length_m = collision.footprint_length_m = length_m;
  projection.footprint_width_m = collision.footprint_width_m = width_m;
  collision.r_coll_m = std::hypot(0.5 * length_m, 0.5 * width_m);
}

ProjectionParams PlannerParams::projectionInForce(double l_res_m) const
{
  ProjectionParams out = projection;
  if (out.obstacle_z_max_m == ProjectionParams::kAuto)
    out.obstacle_z_max_m =
        collision.usesFootprint(l_res_m) && !collision.footprintTrimmed(l_res_m)
            ? out.auto_obstacle_z_max_m
            : 0.0;
  return out;
}

void PlannerParams::save(mrpt::config::CConfigFileBase& cfg) const
{
  projection.saveToConfigFile(cfg, "projection");
  collision.saveToConfigFile(cfg, "collision");
  sampling.saveToConfigFile(cfg, "sampling");
  rooms.saveToConfigFile(cfg, "rooms");
  rating.saveToConfigFile(cfg, "scan_rating");
  path.saveToConfigFile(cfg, "path");
  cfg.write("planner", "strategy", strategy == Strategy::NextBestView ? "nbv" : "nearest");
  cfg.write("planner", "seed", seed);
  cfg.write("planner", "frontier_order", frontier_order == FrontierOrder::Tour ? "tour" : "nearest");
  cfg.write("planner", "tour_cell_m", tour_cell_m);
  cfg.write("planner", "frontier_tiers", frontier_tiers);
}

}  // namespace voxplore::exploration
