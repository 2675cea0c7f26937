/* voxplore — ExplorationLoop's account of the floor: what is known, what is
 * cut off from the robot (and planning again when it is shut in), the
 * frontiers left, stagnation, and a map that shut the robot in. */
#include <mrpt/core/format.h>
#include <voxplore/mission/ExplorationLoop.h>

#include <algorithm>
#include <string>

namespace voxplore::mission
{
namespace
{
/// The free floor known in G [m^2].
double knownFloorM2(const exploration::GroundGrid& g)
{
  const auto& st = g.state;
  return st.getResolution() * st.getResolution() *
         static_cast<double>(std::count(st.data().begin(), st.data().end(),
                                        exploration::GroundState::Free));
}

}  // namespace

void ExplorationLoop::replanShutIn(exploration::PlanResult& plan, double cut_off_m2,
                                   std::size_t step, const std::vector<Eigen::Vector2d>& approach)
{
  // Shut in: most of the known floor lies beyond the robot's reach (an
  // ordinary end leaves 4-8 % cut off: corners, under tables, behind
  // passages narrower than the robot).
  if (!plan.ground || cut_off_m2 < params_.cut_off_replan_m2 ||
      cut_off_m2 < 0.5 * knownFloorM2(*plan.ground))
    return;
  exploration::PlannerParams relaxed = planner_;
  relaxed.collision.swept_passage = true;
  const auto planRelaxed = [&] {
    return exploration::plan(slam_.octomap().tree(), slam_.currentPose(), relaxed, blacklist_,
                             step, swept_, {}, approach, slam_.octomap().lowObstacles(),
                             projectionCache(), looks_.get());
  };
  auto again = planRelaxed();
  message(mrpt::format("shut in: %.0f m^2 of known floor cut off from the robot (%s); planned "
                       "again trusting the swept path and without the %zu sensed point(s): %s",
                       cut_off_m2, exploration::toString(plan.done), sensed_obstacles_.size(),
                       again.ok() ? "a way out" : "still nothing"));
  // Then with the robot's rectangle instead of the thesis' circle (the
  // compact robot's circle needs 0.9 m of Free cells; a 0.85 m door whose
  // jambs the map drew 2-3 cm in closed it, b10 compact nearest: 408 of 409
  // m^2 cut off; the rectangle, turned, passes).
  if (!again.ok() && !relaxed.collision.usesFootprint(plan.ground->state.getResolution()))
  {
    relaxed.collision.model = exploration::CollisionParams::Model::Footprint;
    again = planRelaxed();
    message(std::string("shut in: planned again with the robot's footprint: ") +
            (again.ok() ? "a way out" : "still nothing"));
  }
  if (!again.ok()) return;
  sensed_obstacles_.clear();
  plan = std::move(again);
}

void ExplorationLoop::noteCutOff(double cut_off_m2)
{
  status_.known_floor_cut_off_m2 = cut_off_m2;
  // Under a few m^2 it is the floor beside furniture legs and in corners.
  if (cut_off_m2 >= 5.0)
    message(mrpt::format("%.0f m^2 of the %.0f m^2 of known free floor are cut off from the robot: "
                         "the planner's map closes the way there (a door narrowed or with unknown "
                         "jambs after drift, or a passage narrower than the planner's robot)",
                         cut_off_m2, status_.known_floor_m2));
}

bool ExplorationLoop::endShutIn(const std::string& detail, double cut_off_m2)
{
  // A known floor that fell by half or more is no explored building: the
  // robot's pose left the map's free space or the map closed round it, by
  // drift (willowgarage compact nbv: 1,057 -> 72 m^2 in one step at 1.1 m of
  // drift, coverage 0.03; issue 11) or by a registration through a wall (b1
  // compact nbv: 530 -> 0.07 m^2, ended "no frontier" at coverage 0).
  if (floorCollapsed(known_floor_))
  {
    status_.termination_reason = "the map shut the robot in";
    message(mrpt::format("the map shut the robot in: the free floor known in G fell from %.0f to %.1f m^2: %s",
                         *std::max_element(known_floor_.begin(), known_floor_.end() - 1),
                         known_floor_.back(), detail.c_str()));
    return true;
  }
  // The floor still in G, but the planner's robot cannot leave where it
  // stands (b7 compact nbv, seed 2: between two tables' legs, 146 of 146 m^2
  // cut off at coverage 0.40): not "no frontier", which reads as explored.
  if (!cutOffShutsIn(cut_off_m2, status_.known_floor_m2)) return false;
  message(mrpt::format("the map shut the robot in: %.0f of the %.0f m^2 of known free floor are "
                       "cut off from where it stands (%s)",
                       cut_off_m2, status_.known_floor_m2, status_.termination_reason.c_str()));
  status_.termination_reason = "the map shut the robot in";
  return true;
}

void ExplorationLoop::noteFrontiers(const exploration::PlanResult& plan)
{
  status_.frontiers_left.clear();
  status_.new_frontiers = 0;
  const double radius = planner_.sampling.blacklist_radius_m;
  if (plan.frontiers)
    for (const auto& f : plan.frontiers->frontiers)
    {
      status_.frontiers_left.emplace_back(f.center, f.size_m);
      status_.new_frontiers += std::none_of(planned_.begin(), planned_.end(), [&](const auto& c) {
        return (c - f.center).norm() <= radius;
      });
    }
  status_.small_pockets_only =
      plan.frontiers && onlySmallPockets(plan.frontiers->frontiers, params_.tail_pocket_m2);
  status_.unobservable_m2 = plan.retired_m2;
  if (!plan.ground) return;
  status_.known_floor_m2 = knownFloorM2(*plan.ground);
  known_floor_.push_back(status_.known_floor_m2);
  path_at_plan_.push_back(status_.path_length_m);
}

std::optional<double> ExplorationLoop::stagnationGain() const
{
  const auto k = static_cast<std::size_t>(params_.stagnation_steps);
  if (k == 0 || known_floor_.size() <= k) return std::nullopt;
  return known_floor_.back() - known_floor_[known_floor_.size() - 1 - k];
}

bool ExplorationLoop::onlySmallPockets(const std::vector<exploration::Frontier>& frontiers,
                                       double max_m2)
{
  return !frontiers.empty() &&
         std::all_of(frontiers.begin(), frontiers.end(),
                     [&](const exploration::Frontier& f) { return f.unknown_m2 < max_m2; });
}

std::optional<double> ExplorationLoop::floorGainOver(double window) const
{
  if (window <= 0 || path_at_plan_.size() < 2) return std::nullopt;
  // The latest earlier step at least `window` metres of driving back.
  const double back = path_at_plan_.back() - window;
  const auto it = std::upper_bound(path_at_plan_.begin(), path_at_plan_.end() - 1, back);
  if (it == path_at_plan_.begin()) return std::nullopt;
  const auto j = static_cast<std::size_t>(std::distance(path_at_plan_.begin(), it) - 1);
  return known_floor_.back() - known_floor_[j];
}

bool ExplorationLoop::cutOffShutsIn(double cut_off_m2, double known_floor_m2)
{
  // 5 m^2, as noteCutOff's floor beside furniture legs and in corners; half,
  // as floorCollapsed and replanShutIn.
  return cut_off_m2 >= 5.0 && cut_off_m2 > 0.5 * known_floor_m2;
}

bool ExplorationLoop::floorCollapsed(const std::vector<double>& known_floor)
{
  if (known_floor.size() < 2) return false;
  // Half, as replanShutIn's "more than half of the known floor cut off".
  return known_floor.back() < 0.5 * *std::max_element(known_floor.begin(), known_floor.end() - 1);
}

bool ExplorationLoop::stagnated()
{
  std::string why;
  if (const auto gain = stagnationGain(); gain && *gain < params_.stagnation_min_gain_m2)
    why = mrpt::format("%.1f m^2 of floor found in the last %d steps (< %.1f)", *gain,
                       params_.stagnation_steps, params_.stagnation_min_gain_m2);
  else if (const auto g = pathStagnationGain(); g && *g < params_.stagnation_path_min_gain_m2)
    why = mrpt::format("%.1f m^2 of floor found over the last %.0f m driven (< %.1f)", *g,
                       params_.stagnation_path_m, params_.stagnation_path_min_gain_m2);
  if (params_.stagnation_new_frontier_guard && status_.new_frontiers > 0) why.clear();
  double left_m = 0;
  for (const auto& f : status_.frontiers_left) left_m += f.second;
  if (!why.empty())
  {
    if (endShutIn(mrpt::format("%s; a wall drawn across the way the robot came, by pose drift; "
                               "%zu frontier(s) left, %.1f m",
                               why.c_str(), status_.frontiers_left.size(), left_m)))
      return true;
    status_.termination_reason = "stagnation";
    message(mrpt::format("stagnation: %s; %zu frontier(s) left, %.1f m", why.c_str(),
                         status_.frontiers_left.size(), left_m));
    return true;
  }
  const auto tail = floorGainOver(params_.tail_path_m);
  if (!status_.small_pockets_only || !tail || *tail >= params_.tail_min_gain_m2) return false;
  status_.termination_reason = "only small pockets left";
  message(mrpt::format("only small pockets left: %.1f m^2 of floor found over the last %.0f m driven "
                       "(< %.1f), and the %zu frontier(s) left (%.1f m) border only closed pockets of "
                       "unknown under %.1f m^2 each",
                       *tail, params_.tail_path_m, params_.tail_min_gain_m2,
                       status_.frontiers_left.size(), left_m, params_.tail_pocket_m2));
  return true;
}

}  // namespace voxplore::mission
