#include <mrpt/system/CTicTac.h>
#include <octomap/OcTree.h>
#include <voxplore/exploration/Planner.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace voxplore::exploration
{
using mrpt::poses::CPose2D;

const char* toString(DoneReason r)
{
  switch (r)
  {
    case DoneReason::None:
      return "none";
    case DoneReason::NoFrontier:
      return "no frontier";
    case DoneReason::NoReachableFrontier:
      return "no reachable frontier";
    case DoneReason::AllSkipped:
      return "all frontiers skipped";
  }
  return "?";
}

const char* toString(SkipReason r)
{
  switch (r)
  {
    case SkipReason::NoGoal:
      return "no reachable cell";
    case SkipReason::NoSamples:
      return "no sample space";
    case SkipReason::NoGain:
      return "no gain";
    case SkipReason::NoPath:
      return "no path";
  }
  return "?";
}

namespace
{
/// The reachable Free cell nearest to `p` (the nearest-frontier baseline's target).
std::optional<Eigen::Vector2d> nearestReachable(const FrontierMap& fm, const Eigen::Vector2d& p)
{
  const auto& g = fm.reachable;
  std::optional<Eigen::Vector2d> best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int cy = 0; cy < static_cast<int>(g.getSizeY()); cy++)
    for (int cx = 0; cx < static_cast<int>(g.getSizeX()); cx++)
    {
      if (!*g.cellByIndex(cx, cy)) continue;
      const Eigen::Vector2d c = cellCenter(g, {cx, cy});
      const double d2 = (c - p).squaredNorm();
      if (d2 < best_d2)
      {
        best_d2 = d2;
        best = c;
      }
    }
  return best;
}

/// The room most of the frontier's cells lie in (-1: none; ties: the lower index).
int32_t majorityRoom(const RoomMap& rooms, const Frontier& f)
{
  std::vector<std::pair<int32_t, int>> counts;
  for (const Cell& c : f.cells)
  {
    const int32_t room = rooms.roomAt(c);
    if (room < 0) continue;
    auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& e) { return e.first == room; });
    if (it == counts.end()) counts.emplace_back(room, 1);
    else ++it->second;
  }
  std::pair<int32_t, int> best{-1, 0};
  for (const auto& e : counts)
    if (e.second > best.second || (e.second == best.second && e.first < best.first)) best = e;
  return best.first;
}

double yawTowards(const Eigen::Vector2d& from, const Eigen::Vector2d& to)
{
  return std::atan2(to.y() - from.y(), to.x() - from.x());
}

/// A pose to try, with the frontier it looks at and its utility.
struct Candidate
{
  CPose2D pose;
  std::size_t frontier = 0;
  double utility = 0;
  /// Rated at pose's yaw where the robot will stand (rate_reached_yaw): the
  /// path ends in that yaw's bin.
  bool stand_at_yaw = false;
};

/// Each sample's yaw becomes the one the robot will stand at there (the
/// reached bin nearest the yaw facing the frontier), so that it is rated
/// for the view it will have (SamplingParams::rate_reached_yaw).
void standAtReachedYaws(const FootprintSpace& fs, std::vector<CPose2D>& samples)
{
  for (auto& s : samples)
  {
    Cell c;
    if (!cellOf(fs.reach, Eigen::Vector2d(s.x(), s.y()), c)) continue;
    const std::size_t nx = fs.reach.getSizeX();
    const std::size_t i = static_cast<std::size_t>(c.cx) + static_cast<std::size_t>(c.cy) * nx;
    if (const auto yaw = fs.nearestReachedYaw(i, s.phi())) s.phi(*yaw);
  }
}

/// The nearest strategy's target views its frontier from the stand-off
/// (footprint model, SamplingParams::view_standoff_m), not from the frontier.
bool nearestStandsOff(const PlanResult& r, const PlannerParams& p)
{
  return r.footprint && p.sampling.view_standoff_m > 0;
}

/// The candidate poses for frontier fi, appended to `out`: the nearest
/// strategy's (or an approached frontier's) goal, or next-best-view's rated
/// samples with a gain, whose utility is gain x exp(-travel_cost_per_m x
/// their travel distance from the robot). Returns why there is none.
std::optional<SkipReason> candidatesFor(
    const octomap::OcTree& V, const PlannerParams& p, std::size_t fi, uint64_t step, bool approach,
    PlanResult& r, std::vector<Candidate>& out)
{
  const Frontier& f = r.frontiers->frontiers[fi];
  mrpt::system::CTicTac tic;
  if (p.strategy == Strategy::NearestFrontier || approach)
  {
    std::optional<Eigen::Vector2d> goal;
    if (nearestStandsOff(r, p) && !approach)
      goal = standoffGoal(*r.ground, *r.space, *r.frontiers, f, p.sampling);
    if (!goal) goal = nearestReachable(*r.frontiers, f.centroid);
    if (!goal) return SkipReason::NoGoal;
    out.push_back({CPose2D(goal->x(), goal->y(), yawTowards(*goal, f.center)), fi, 1.0});
    return std::nullopt;
  }
  const auto space = sampleSpace(*r.ground, *r.space, *r.frontiers, f, p.sampling);
  r.sample_space.insert(r.sample_space.end(), space.begin(), space.end());
  std::seed_seq seq{static_cast<uint32_t>(p.seed), static_cast<uint32_t>(step), static_cast<uint32_t>(fi)};
  std::mt19937_64 rng(seq);
  auto samples = samplePoses(r.space->state, space, f, p.sampling, rng);
  const bool stand_at_yaw = r.footprint && p.sampling.rate_reached_yaw;
  if (stand_at_yaw) standAtReachedYaws(*r.footprint, samples);
  r.ms.sampling += 1e3 * tic.Tac();
  if (samples.empty()) return SkipReason::NoSamples;
  tic.Tic();
  const std::vector<ScanRating> ratings = rateScans(V, samples, p.rating);
  r.ms.rating += 1e3 * tic.Tac();
  r.samples.insert(r.samples.end(), samples.begin(), samples.end());
  r.ratings.insert(r.ratings.end(), ratings.begin(), ratings.end());
  if (!bestRated(ratings)) return SkipReason::NoGain;  // nothing to learn around this frontier
  const Eigen::Vector2d robot_xy = cellCenter(r.frontiers->distance_m, r.ground->robot);
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    if (ratings[i].gain <= 0) continue;
    double u = ratings[i].gain;
    if (p.sampling.travel_cost_per_m > 0)
    {
      // Travel over G from the robot (the frontier search's Dijkstra); the
      // straight line where it has none (not expected: samples are reachable).
      const Eigen::Vector2d xy(samples[i].x(), samples[i].y());
      Cell c;
      double d = (xy - robot_xy).norm();
      if (cellOf(r.frontiers->distance_m, xy, c))
      {
        const float dc = *r.frontiers->distance_m.cellByIndex(c.cx, c.cy);
        if (dc >= 0) d = dc;
      }
      u *= std::exp(-p.sampling.travel_cost_per_m * d);
    }
    out.push_back({samples[i], fi, u, stand_at_yaw});
  }
  return std::nullopt;
}

/// Plans a path to the candidates by decreasing utility (stable: ties keep
/// their order); the first with a path fills r.
bool pathToBest(const CPose2D& robot, const PlannerParams& p, std::vector<Candidate> candidates,
                PlanResult& r, std::vector<float>& footprint_cost)
{
  mrpt::system::CTicTac tic;
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.utility > b.utility; });
  const Eigen::Vector2d start(robot.x(), robot.y());
  for (const auto& cand : candidates)
  {
    const CPose2D& c = cand.pose;
    const Eigen::Vector2d goal(c.x(), c.y());
    // The SE(2) A*'s heuristic, once per step for every candidate.
    if (r.footprint && footprint_cost.empty())
      footprint_cost = footprintCostFromStart(*r.space, *r.footprint, p.path);
    auto path = r.footprint ? planFootprintPath(*r.space, *r.footprint, robot, goal, c.phi(),
                                                p.path, &footprint_cost, cand.stand_at_yaw)
                            : planPath(*r.space, start, goal, p.path);
    if (!path) continue;
    r.path = std::move(path);
    r.target = r.path->final_yaw ? CPose2D(c.x(), c.y(), *r.path->final_yaw) : c;
    const std::size_t first = r.path->waypoints.size() > 1 ? 1 : 0;
    r.waypoints.assign(r.path->waypoints.begin() + first, r.path->waypoints.end());
    if (r.footprint)
    {
      r.waypoint_yaws.assign(r.path->yaws.begin() + first, r.path->yaws.end());
      r.waypoint_narrow.assign(r.path->narrow.begin() + first, r.path->narrow.end());
      r.waypoint_turn_on_way.assign(r.path->turn_on_way.begin() + first, r.path->turn_on_way.end());
    }
    r.frontier = r.frontiers->frontiers[cand.frontier];
    r.frontier_index = cand.frontier;
    r.ms.path += 1e3 * tic.Tac();
    return true;
  }
  r.ms.path += 1e3 * tic.Tac();
  return false;
}

/// "n no path, m no gain" over the skipped frontiers.
std::string skipSummary(const std::vector<SkipReason>& reasons)
{
  std::ostringstream os;
  const char* sep = "";
  for (const auto k :
       {SkipReason::NoGoal, SkipReason::NoSamples, SkipReason::NoGain, SkipReason::NoPath})
  {
    const auto n = std::count(reasons.begin(), reasons.end(), k);
    if (n == 0) continue;
    os << sep << n << " " << toString(k);
    sep = ", ";
  }
  return os.str();
}
}  // namespace

PlanResult plan(
    const octomap::OcTree& V, const CPose2D& robot, const PlannerParams& p,
    const std::vector<Eigen::Vector2d>& blacklist, uint64_t step,
    const SweptPath& swept, const std::vector<Eigen::Vector2d>& sensed_obstacles,
    const std::vector<Eigen::Vector2d>& approach, const std::vector<Eigen::Vector2d>& low_obstacles,
    ProjectionCache* projection_cache, FrontierLooks* looks)
{
  mrpt::system::CTicTac total, tic;
  PlanResult r = planLayers(V, robot, p, swept, sensed_obstacles, low_obstacles, projection_cache,
                            looks);
  const auto ground = r.ground;
  const auto space = r.space;
  const auto fm = r.frontiers;
  tic.Tic();
  auto rooms = std::make_shared<RoomMap>(segmentRooms(*ground, *space, p.rooms));
  r.rooms = rooms;
  r.robot_room = rooms->roomAt(ground->robot);
  r.frontier_rooms.reserve(fm->frontiers.size());
  for (const Frontier& f : fm->frontiers) r.frontier_rooms.push_back(majorityRoom(*rooms, f));
  // finish_room (next-best-view): the robot's room's frontiers first.
  std::vector<uint8_t> in_room;
  if (p.rooms.finish_room && p.strategy == Strategy::NextBestView && r.robot_room >= 0)
    for (const int32_t room : r.frontier_rooms) in_room.push_back(room == r.robot_room);
  r.ms.rooms = 1e3 * tic.Tac();

  if (fm->frontiers.empty())
  {
    r.done = DoneReason::NoFrontier;
    r.message = "no frontier: the reachable space is fully explored";
  }
  std::vector<float> footprint_cost;  // footprintCostFromStart, when first needed
  // frontier_order = tour: each threshold tier's frontiers ranked by an open
  // tour from the robot (the tier of th_f1, then the rest above th_f2; one
  // tier without frontier_tiers: `order` has th_f1 = th_f2).
  const SamplingParams order = p.frontierOrderInForce();
  std::vector<double> rank;
  std::vector<FrontierTour> tours;
  const bool by_tour = p.strategy == Strategy::NextBestView &&
                       p.frontier_order == FrontierOrder::Tour && !fm->frontiers.empty();
  if (by_tour)
  {
    tic.Tic();
    rank.assign(fm->frontiers.size(), std::numeric_limits<double>::infinity());
    std::vector<std::size_t> tier1, tier2;
    for (std::size_t i = 0; i < fm->frontiers.size(); ++i)
    {
      const Frontier& f = fm->frontiers[i];
      const double length = order.judgedLength(f);
      if (f.unreached || length <= order.th_f2_m || order.enclosed(f) ||
          nearAny(f.center, blacklist, order.blacklist_radius_m))
        continue;
      (length > order.th_f1_m ? tier1 : tier2).push_back(i);
    }
    for (const auto* tier : {&tier1, &tier2})
    {
      tours.push_back(frontierTour(*fm, ground->robot, *tier, p.tour_cell_m));
      const auto& order = tours.back().order;
      for (std::size_t k = 0; k < order.size(); ++k) rank[order[k]] = static_cast<double>(k);
    }
    r.ms.tour = 1e3 * tic.Tac();
  }
  // The unreached frontiers (SamplingParams::unreached_frontiers) wait
  // until the reached ones give no target. They have no tour rank
  // (infinity), so chooseFrontier then takes them in their order, by
  // distance, with or without `rank`.
  std::vector<std::size_t> held;
  for (std::size_t i = 0; i < fm->frontiers.size(); ++i)
    if (fm->frontiers[i].unreached) held.push_back(i);
  const auto skipping = [&](std::vector<std::size_t> skip)
  {
    skip.insert(skip.end(), held.begin(), held.end());
    return skip;
  };
  const std::vector<double>* ranks = by_tour ? &rank : nullptr;
  while (r.done == DoneReason::None)
  {
    const auto fi = chooseFrontier(fm->frontiers, order, blacklist, skipping(r.skipped_frontiers),
                                   ranks, in_room.empty() ? nullptr : &in_room);
    if (!fi && !held.empty())
    {
      held.clear();
      continue;
    }
    if (!fi)
    {
      r.done = r.skipped_frontiers.empty() ? DoneReason::NoReachableFrontier : DoneReason::AllSkipped;
      std::ostringstream os;
      os << fm->frontiers.size() << " frontier(s), none longer than " << p.sampling.th_f2_m
         << " m and not blacklisted" << (r.skipped_frontiers.empty() ? "" : " left after skipping ")
         << (r.skipped_frontiers.empty() ? "" : std::to_string(r.skipped_frontiers.size()));
      if (p.sampling.enclosed_unknown_m2 > 0)
        os << "; " << std::count_if(fm->frontiers.begin(), fm->frontiers.end(),
                                    [&](const Frontier& f) { return p.sampling.enclosed(f); })
           << " border(s) only closed pockets of open unknown under " << p.sampling.enclosed_unknown_m2
           << " m^2";
      if (!r.skip_reasons.empty()) os << ": " << skipSummary(r.skip_reasons);
      if (r.footprint && !r.footprint->reach.data()[r.footprint->robot.cx + r.footprint->robot.cy *
                                                      r.footprint->reach.getSizeX()])
        os << "; the robot's footprint reaches no state (blocked where it stands)";
      r.message = os.str();
      break;
    }
    // Approached: next-best-view's rated views, and the nearest strategy's
    // view stand-off (footprint model), give way to the frontier's nearest
    // reachable cell once a view did not clear it (b12 omniRob nearest: a
    // stand-off in the corridor saw a 0.99 m door's room at a slant twice,
    // the frontier was blacklisted and the room never entered).
    const bool views_from_afar = p.strategy == Strategy::NextBestView || nearestStandsOff(r, p);
    const auto approached = [&](std::size_t i) {
      const Eigen::Vector2d fc = fm->frontiers[i].center;
      return views_from_afar &&
             std::any_of(approach.begin(), approach.end(), [&](const Eigen::Vector2d& a) {
               return (a - fc).norm() <= p.sampling.blacklist_radius_m;
             });
    };
    // The frontiers rated together: the chosen one and, next-best-view with
    // frontiers_rated > 1, the next ones in the same order (an approached
    // frontier is tried on its own, as the nearest strategy's).
    std::vector<std::size_t> batch{*fi};
    r.approached = approached(*fi);
    if (p.strategy == Strategy::NextBestView && !r.approached && p.sampling.frontiers_rated > 1)
    {
      std::vector<std::size_t> skip = r.skipped_frontiers;
      skip.push_back(*fi);
      while (batch.size() < static_cast<std::size_t>(p.sampling.frontiers_rated))
      {
        const auto fj = chooseFrontier(fm->frontiers, order, blacklist, skipping(skip), ranks,
                                       in_room.empty() ? nullptr : &in_room);
        if (!fj) break;
        skip.push_back(*fj);
        if (!approached(*fj)) batch.push_back(*fj);
      }
    }
    std::vector<Candidate> candidates;
    std::vector<std::optional<SkipReason>> why(batch.size());
    r.samples.clear();  // the images show the last batch's
    r.ratings.clear();
    r.sample_space.clear();
    for (std::size_t k = 0; k < batch.size(); ++k)
      why[k] = candidatesFor(V, p, batch[k], step, r.approached, r, candidates);
    if (!candidates.empty() && pathToBest(robot, p, std::move(candidates), r, footprint_cost))
    {
      if (by_tour && !r.frontier->unreached)
        r.tour = tours[order.judgedLength(*r.frontier) > order.th_f1_m ? 0 : 1];
      std::ostringstream os;
      os << "frontier " << r.frontier_index << " (" << r.frontier->size_m << " m";
      if (p.sampling.judge_opening) os << ", opening " << r.frontier->opening_m << " m";
      os << ", " << r.frontier->distance_m << " m away" << (r.approached ? ", approached" : "")
         << (r.frontier->unreached ? ", unreached: viewed from the reach" : "");
      if (batch.size() > 1) os << ", best of " << batch.size() << " rated";
      os << "): target (" << r.target.x() << ", " << r.target.y() << "), path "
         << r.path->length_m << " m in " << r.waypoints.size() << " waypoints";
      r.message = os.str();
      break;
    }
    for (std::size_t k = 0; k < batch.size(); ++k)
    {
      r.skipped_frontiers.push_back(batch[k]);
      r.skip_reasons.push_back(why[k] ? *why[k] : SkipReason::NoPath);
    }
  }
  r.ms.total = 1e3 * total.Tac();
  return r;
}

}  // namespace voxplore::exploration
