// The frontier stage's monotone queue (libs/exploration/src/radix_heap.h):
// it must pop keys in ascending order under a Dijkstra's pushes, and a grid
// Dijkstra on it must give the distances a binary heap gives, bit for bit
// (issue 12: the frontier stage switches to it once the escape is over).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "radix_heap.h"

namespace
{
using voxplore::exploration::detail::RadixHeap;

/// 8-connected grid Dijkstra (1 and sqrt(2) steps) over the cells with
/// open[i], from `start`, on queue Q (push(key, cell), pop() -> (key, cell)).
template <typename Q>
std::vector<double> gridDistances(const std::vector<uint8_t>& open, int nx, int ny, int start, Q q)
{
  const int dx[8] = {1, -1, 0, 0, 1, 1, -1, -1}, dy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  std::vector<double> dist(open.size(), -1.0);
  dist[start] = 0;
  q.push(0.0, start);
  while (!q.empty())
  {
    const auto [d, i] = q.pop();
    if (d > dist[i]) continue;
    for (int k = 0; k < 8; ++k)
    {
      const int x = i % nx + dx[k], y = i / nx + dy[k];
      if (x < 0 || y < 0 || x >= nx || y >= ny || !open[x + y * nx]) continue;
      const double nd = d + (k < 4 ? 1.0 : std::sqrt(2.0));
      const int j = x + y * nx;
      if (dist[j] >= 0 && dist[j] <= nd) continue;
      dist[j] = nd;
      q.push(nd, j);
    }
  }
  return dist;
}

struct BinaryHeap
{
  std::priority_queue<std::pair<double, int>, std::vector<std::pair<double, int>>,
                      std::greater<std::pair<double, int>>>
      q;
  void push(double k, int v) { q.push({k, v}); }
  bool empty() const { return q.empty(); }
  std::pair<double, int> pop()
  {
    const auto top = q.top();
    q.pop();
    return top;
  }
};
}  // namespace

TEST(RadixHeap, PopsAscendingUnderMonotonePushes)
{
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> step(0.0, 3.0);
  std::uniform_int_distribution<int> kind(0, 3);
  RadixHeap<int> h;
  BinaryHeap ref;
  double last = 0;
  int pushed = 0;
  for (int round = 0; round < 20000; ++round)
  {
    const int n = kind(rng);
    for (int k = 0; k < n; ++k, ++pushed)
    {
      // Ties (0 and exact repeats), the grid's steps, and arbitrary gaps.
      const double key = k == 0 ? last : k == 1 ? last + 1.0 : k == 2 ? last + std::sqrt(2.0)
                                                                       : last + step(rng);
      h.push(key, pushed);
      ref.push(key, pushed);
    }
    if (!ref.empty() && kind(rng) != 0)
    {
      const double got = h.pop().first, want = ref.pop().first;
      ASSERT_EQ(got, want) << "round " << round;
      last = got;
    }
  }
  while (!ref.empty()) ASSERT_EQ(h.pop().first, ref.pop().first);
  EXPECT_TRUE(h.empty());
}

TEST(RadixHeap, AGridDijkstraGivesTheBinaryHeapsDistancesBitForBit)
{
  std::mt19937 rng(9);
  for (const double wall : {0.0, 0.2, 0.4})
  {
    const int nx = 173, ny = 121;
    std::bernoulli_distribution blocked(wall);
    std::vector<uint8_t> open(static_cast<std::size_t>(nx) * ny);
    for (auto& c : open) c = blocked(rng) ? 0 : 1;
    const int start = nx / 2 + (ny / 2) * nx;
    open[start] = 1;
    struct Radix
    {
      RadixHeap<int> h{0.0};
      void push(double k, int v) { h.push(k, v); }
      bool empty() const { return h.empty(); }
      std::pair<double, int> pop() { return h.pop(); }
    };
    const auto a = gridDistances(open, nx, ny, start, BinaryHeap{});
    const auto b = gridDistances(open, nx, ny, start, Radix{});
    std::size_t reached = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
      ASSERT_EQ(a[i], b[i]) << "cell " << i << " walls " << wall;
      reached += a[i] >= 0;
    }
    EXPECT_GT(reached, open.size() / 3);
  }
}
