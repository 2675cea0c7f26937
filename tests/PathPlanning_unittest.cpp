// Path generation (thesis 4.5.5): the path through a 3 m passage keeps to
// its centre line, waypoints are spaced <= max_segment_m and lie in free
// space, unreachable / non-free goals give no path, a start in collision
// space is left, open space gives one straight line, and the parameters.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <voxplore/exploration/path.h>

#include <cmath>

#include "exploration_test_maps.h"

using namespace voxplore::exploration;
using namespace voxplore::test;

namespace
{
constexpr double kRes = 0.1;

/// Room A [0,5) x [-4,4), a 3 m wide passage [5,11) x [-1.5,1.5) and room B
/// [11,16) x [-4,4), walls around, unknown outside.
GroundGrid passageWorld()
{
  GroundGrid g = makeGround(-1.0, 17.0, -5.0, 5.0, kRes, GroundState::Unknown);
  paint(g, -0.1, 16.1, -4.1, 4.1, GroundState::Occupied);
  paint(g, 0.0, 5.0, -4.0, 4.0, GroundState::Free);
  paint(g, 5.0, 11.0, -1.5, 1.5, GroundState::Free);
  paint(g, 11.0, 16.0, -4.0, 4.0, GroundState::Free);
  return g;
}

/// Calls f(point) every 1 cm along the polyline.
template <typename Fn>
void alongPolyline(const std::vector<Eigen::Vector2d>& pts, Fn&& f)
{
  for (std::size_t s = 0; s + 1 < pts.size(); ++s)
  {
    const int n = static_cast<int>((pts[s + 1] - pts[s]).norm() / 0.01) + 1;
    for (int k = 0; k <= n; ++k) f(pts[s] + (pts[s + 1] - pts[s]) * (double(k) / n));
  }
}
}  // namespace

TEST(PathPlanning, PathThroughA3mPassageKeepsToItsCentreLine)
{
  const CollisionSpace cs = computeCollisionSpace(passageWorld(), CollisionParams{});
  const Eigen::Vector2d start(2.0, 2.5), goal(14.0, -2.5);
  for (const double margin : {0.05, PathParams{}.shortcut_margin_m})
  {
    PathParams p;
    p.shortcut_margin_m = margin;
    const auto path = planPath(cs, start, goal, p);
    ASSERT_TRUE(path.has_value());
    int in_passage = 0;
    for (const Eigen::Vector2d& c : path->cells_path)
    {
      if (c.x() < 5.5 || c.x() > 10.5) continue;
      EXPECT_LE(std::abs(c.y()), kRes + 1e-9) << "A* cell " << c.transpose();
      ++in_passage;
    }
    EXPECT_GT(in_passage, 40);
    // The shortcut may not pass closer to the walls than the A* path minus the margin:
    // with margin <= half a cell it stays within one cell of the centre line.
    const double tol = margin <= kRes / 2 ? kRes : kRes + margin;
    alongPolyline(path->waypoints,
                  [&](const Eigen::Vector2d& q)
                  {
                    if (q.x() < 5.5 || q.x() > 10.5) return;
                    EXPECT_LE(std::abs(q.y()), tol + 1e-9)
                        << "margin " << margin << " at " << q.transpose();
                  });
  }
}

TEST(PathPlanning, WaypointsAreSpacedAndInFreeSpace)
{
  const CollisionSpace cs = computeCollisionSpace(passageWorld(), CollisionParams{});
  PathParams p;
  p.max_segment_m = 0.7;
  const Eigen::Vector2d start(2.0, 2.5), goal(14.0, -2.5);
  const auto path = planPath(cs, start, goal, p);
  ASSERT_TRUE(path.has_value());
  ASSERT_GE(path->waypoints.size(), 2u);
  EXPECT_EQ(path->waypoints.front(), start);
  EXPECT_EQ(path->waypoints.back(), goal);
  double length = 0;
  for (std::size_t k = 0; k + 1 < path->waypoints.size(); ++k)
  {
    const double d = (path->waypoints[k + 1] - path->waypoints[k]).norm();
    EXPECT_LE(d, p.max_segment_m + 1e-9);
    EXPECT_GT(d, 0.0);
    length += d;
  }
  EXPECT_NEAR(path->length_m, length, 1e-9);
  EXPECT_GT(length, (goal - start).norm());
  double min_clear = INFINITY;
  alongPolyline(path->waypoints,
                [&](const Eigen::Vector2d& q)
                {
                  EXPECT_EQ(at(cs.state, q.x(), q.y()), SpaceState::Free) << q.transpose();
                  min_clear = std::min(min_clear,
                                       double(std::min(at(cs.clearance_occ_m, q.x(), q.y()),
                                                       at(cs.clearance_unknown_m, q.x(), q.y()))));
                });
  EXPECT_NEAR(path->min_clearance_m, min_clear, 1e-6);
  EXPECT_GT(path->min_clearance_m, cs.radius_m);
}

TEST(PathPlanning, UnreachableOrNonFreeGoalGivesNoPath)
{
  GroundGrid g = passageWorld();
  paint(g, 8.0, 8.1, -1.5, 1.5, GroundState::Occupied);  // passage blocked
  const CollisionSpace cs = computeCollisionSpace(g, CollisionParams{});
  const Eigen::Vector2d start(2.0, 2.5);
  EXPECT_FALSE(planPath(cs, start, {14.0, -2.5}, PathParams{}).has_value());
  EXPECT_TRUE(planPath(cs, start, {3.0, -2.5}, PathParams{}).has_value());
  EXPECT_FALSE(planPath(cs, start, {0.2, 0.0}, PathParams{}).has_value()) << "goal in collision";
  EXPECT_FALSE(planPath(cs, start, {40.0, 0.0}, PathParams{}).has_value()) << "goal off the grid";
  EXPECT_FALSE(planPath(cs, {-40.0, 0.0}, start, PathParams{}).has_value()) << "start off the grid";
}

TEST(PathPlanning, StartInCollisionSpaceIsLeft)
{
  const CollisionSpace cs = computeCollisionSpace(passageWorld(), CollisionParams{});
  const Eigen::Vector2d start(0.3, 0.0), goal(3.0, 0.0);
  ASSERT_EQ(at(cs.state, start.x(), start.y()), SpaceState::Collision);
  const auto path = planPath(cs, start, goal, PathParams{});
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->waypoints.front(), start);
  EXPECT_EQ(path->waypoints.back(), goal);
  EXPECT_LT(path->length_m, 3.5);
}

TEST(PathPlanning, OpenSpaceGivesAStraightLineCutIntoSegments)
{
  const CollisionSpace cs = computeCollisionSpace(passageWorld(), CollisionParams{});
  PathParams p;
  const Eigen::Vector2d start(1.2, -2.9), goal(4.0, 2.6);
  const auto path = planPath(cs, start, goal, p);
  ASSERT_TRUE(path.has_value());
  const double d = (goal - start).norm();
  EXPECT_NEAR(path->length_m, d, 1e-9);
  EXPECT_EQ(path->waypoints.size(), static_cast<std::size_t>(std::ceil(d / p.max_segment_m)) + 1);
  EXPECT_GT(path->cells_path.size(), path->waypoints.size());
}

TEST(PathPlanning, ParamsRoundTripAndBadValuesThrow)
{
  mrpt::config::CConfigFileMemory cfg;
  PathParams p;
  p.max_segment_m = 0.75;
  p.saveToConfigFile(cfg, "path");
  PathParams q;
  q.loadFromConfigFile(cfg, "path");
  EXPECT_DOUBLE_EQ(q.max_segment_m, 0.75);
  EXPECT_DOUBLE_EQ(q.clearance_ref_m, p.clearance_ref_m);
  cfg.write("path", "max_segment_m", 0.0);
  EXPECT_THROW(q.loadFromConfigFile(cfg, "path"), std::exception);
}
