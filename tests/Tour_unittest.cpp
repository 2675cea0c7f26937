/* voxplore tests — the frontier tour (issue 12): an open tour from the robot
 * over travel distances, not the greedy hop to the nearest frontier. */
#include <gtest/gtest.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

using namespace voxplore::exploration;

namespace
{
using Matrix = std::vector<std::vector<double>>;

double cost(const Matrix& d, const std::vector<int>& p)
{
  double c = 0;
  for (std::size_t i = 1; i < p.size(); ++i) c += d[p[i - 1]][p[i]];
  return c;
}

Matrix euclidean(const std::vector<Eigen::Vector2d>& pts)
{
  Matrix d(pts.size(), std::vector<double>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j < pts.size(); ++j) d[i][j] = (pts[i] - pts[j]).norm();
  return d;
}

void expectOpenPathFromZero(const std::vector<int>& p, std::size_t n)
{
  ASSERT_EQ(p.size(), n);
  EXPECT_EQ(p.front(), 0);
  std::vector<int> sorted = p;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(sorted[i], static_cast<int>(i));
}

/// A free rectangle [x0, x1) x [y0, y1) in `reach`.
void freeBox(Grid<uint8_t>& reach, double x0, double x1, double y0, double y1)
{
  const double r = reach.getResolution();
  for (double y = y0 + 0.5 * r; y < y1; y += r)
    for (double x = x0 + 0.5 * r; x < x1; x += r)
    {
      Cell c;
      ASSERT_TRUE(cellOf(reach, Eigen::Vector2d(x, y), c));
      *reach.cellByIndex(c.cx, c.cy) = 1;
    }
}

Frontier frontierAt(double x, double y)
{
  Frontier f;
  f.center = f.centroid = Eigen::Vector2d(x, y);
  f.size_m = 2.0;
  return f;
}
}  // namespace

TEST(OpenTour, LeavesTheNearestStopForLaterWhenThatShortensTheWhole)
{
  // On a line: the robot at 0, stops at -1, +2, +3, -5. Greedy nearest
  // (-1, +2, +3, -5) travels 1 + 3 + 1 + 8 = 13; the best open tour goes
  // right first (+2, +3, -1, -5 or +3, +2, -1, -5): 11.
  const std::vector<Eigen::Vector2d> pts{{0, 0}, {-1, 0}, {2, 0}, {3, 0}, {-5, 0}};
  const Matrix d = euclidean(pts);
  const std::vector<int> p = openTour(d);
  expectOpenPathFromZero(p, pts.size());
  EXPECT_TRUE(p[1] == 2 || p[1] == 3) << p[1];
  EXPECT_DOUBLE_EQ(cost(d, p), 11.0);
}

TEST(OpenTour, IsTwoOptOptimalAndWithinFivePercentOfTheBestOnRandomRooms)
{
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 30.0);
  double sum_ratio = 0;
  const int kInstances = 60, kNodes = 8;
  for (int k = 0; k < kInstances; ++k)
  {
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < kNodes; ++i) pts.emplace_back(u(rng), u(rng));
    const Matrix d = euclidean(pts);
    const std::vector<int> p = openTour(d);
    expectOpenPathFromZero(p, pts.size());
    // No reversal of a stretch (the start fixed) shortens it.
    for (std::size_t i = 1; i + 1 < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j)
      {
        std::vector<int> q = p;
        std::reverse(q.begin() + i, q.begin() + j + 1);
        ASSERT_GE(cost(d, q), cost(d, p) - 1e-9);
      }
    // The best open tour by brute force.
    std::vector<int> perm(kNodes - 1);
    std::iota(perm.begin(), perm.end(), 1);
    double best = 1e18;
    do
    {
      std::vector<int> q{0};
      q.insert(q.end(), perm.begin(), perm.end());
      best = std::min(best, cost(d, q));
    } while (std::next_permutation(perm.begin(), perm.end()));
    const double ratio = cost(d, p) / best;
    EXPECT_LE(ratio, 1.25) << "instance " << k;
    sum_ratio += ratio;
  }
  EXPECT_LE(sum_ratio / kInstances, 1.05);
}

TEST(FrontierTour, MeasuresTravelRoundWallsNotStraightLines)
{
  // Two rooms side by side, x in [0, 4) and [4.6, 8.6), y in [0, 4), joined
  // only by a corridor along y in [8, 9) (x in [0, 8.6)) through two
  // passages at x in [0, 1). The robot in the left room at (3, 1); frontier
  // B just across the wall in the right room (5, 1), 2 m away in a straight
  // line, about 16 m by travel; frontier C at (1, 3.5) in the robot's room.
  Grid<uint8_t> reach;
  uint8_t zero = 0;
  reach.setSize(-0.5, 9.5, -0.5, 9.5, 0.05, &zero);
  freeBox(reach, 0.3, 3.7, 0.3, 3.7);
  freeBox(reach, 4.9, 8.3, 0.3, 3.7);
  freeBox(reach, 0.3, 8.3, 8.3, 8.7);
  freeBox(reach, 0.3, 0.7, 3.7, 8.3);
  freeBox(reach, 7.9, 8.3, 3.7, 8.3);
  FrontierMap fm;
  fm.reachable = reach;
  const float unreached = -1.f;
  fm.distance_m.setSize(-0.5, 9.5, -0.5, 9.5, 0.05, &unreached);
  auto d = fm.distance_m.begin();
  for (auto r = reach.begin(); r != reach.end(); ++r, ++d)
    if (*r) *d = 0.f;  // reached (the value is not used)
  fm.frontiers = {frontierAt(5.0, 1.0), frontierAt(1.0, 3.5)};
  Cell robot;
  ASSERT_TRUE(cellOf(reach, Eigen::Vector2d(3.0, 1.0), robot));
  const FrontierTour t = frontierTour(fm, robot, {0, 1}, 0.2);
  ASSERT_EQ(t.order.size(), 2u);
  EXPECT_EQ(t.order[0], 1u);  // the robot's own room first
  EXPECT_EQ(t.order[1], 0u);
  // robot -> C about 3.2 m, C -> B about 3.3 + 4.8 + 7.6 + 4.7 + 3.2 ~ 18 m: far
  // more than the straight lines (3.2 + 4.7).
  EXPECT_GT(t.length_m, 15.0);
  EXPECT_LT(t.length_m, 30.0);
  // A frontier the robot cannot reach comes last.
  fm.frontiers.push_back(frontierAt(9.2, 1.0));
  const FrontierTour u = frontierTour(fm, robot, {2, 0, 1}, 0.2);
  ASSERT_EQ(u.order.size(), 3u);
  EXPECT_EQ(u.order.back(), 2u);
}
