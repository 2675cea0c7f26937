// The searches' open list (libs/exploration/src/indexed_heap.h): it must pop
// exactly what a std::priority_queue with lazy deletion pops once its stale
// copies are skipped, so that the SE(2) A* and its heuristic find the same
// paths and costs as before it (issue 13).
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "indexed_heap.h"

namespace
{
using voxplore::exploration::detail::IndexedHeap;

struct Item
{
  int key;  // few distinct values: many ties, broken by the handle
  uint32_t handle;
  bool operator<(const Item& o) const { return key != o.key ? key < o.key : handle < o.handle; }
  bool operator>(const Item& o) const { return o < *this; }
};

struct Handles
{
  std::vector<int32_t>* pos_of;
  uint32_t handle(const Item& i) const { return i.handle; }
  int32_t& pos(uint32_t h) const { return (*pos_of)[h]; }
};

/// One random search-like run: keys only go down while a handle is open,
/// popped handles never come back; returns the number of pops compared.
std::size_t compareWithLazyQueue(uint32_t seed, uint32_t n_handles, int key_range)
{
  std::mt19937 rng(seed);
  std::vector<int32_t> pos(n_handles, -1);
  IndexedHeap<Item, Handles> heap(Handles{&pos}, {});
  std::priority_queue<Item, std::vector<Item>, std::greater<>> lazy;
  std::vector<int> key(n_handles, key_range + 1);
  std::vector<char> closed(n_handles, 0);
  std::size_t pops = 0;
  // Drops the lazy queue's stale copies; false when nothing valid is left.
  const auto skipStale = [&]
  {
    while (!lazy.empty() && (closed[lazy.top().handle] || lazy.top().key != key[lazy.top().handle]))
      lazy.pop();
    return !lazy.empty();
  };
  for (int round = 0; round < 20000; ++round)
  {
    if (rng() % 3 != 0 || heap.empty())
    {
      const uint32_t h = rng() % n_handles;
      if (closed[h]) continue;
      const int k = static_cast<int>(rng() % static_cast<uint32_t>(key_range));
      if (k >= key[h]) continue;  // a search only pushes an improvement
      key[h] = k;
      heap.pushOrDecrease({k, h});
      lazy.push({k, h});
      continue;
    }
    const Item got = heap.pop();
    if (!skipStale()) ADD_FAILURE() << "the heap popped more than was pushed";
    if (lazy.empty()) return pops;
    const Item want = lazy.top();
    lazy.pop();
    closed[want.handle] = 1;
    EXPECT_EQ(got.handle, want.handle) << "pop " << pops << ", seed " << seed;
    EXPECT_EQ(got.key, want.key) << "pop " << pops << ", seed " << seed;
    EXPECT_EQ(pos[got.handle], -1);
    if (got.handle != want.handle) return pops;
    ++pops;
  }
  while (!heap.empty())
  {
    const Item got = heap.pop();
    if (!skipStale()) ADD_FAILURE() << "the heap popped more than was pushed";
    if (lazy.empty()) return pops;
    EXPECT_EQ(got.handle, lazy.top().handle);
    closed[lazy.top().handle] = 1;
    lazy.pop();
    ++pops;
  }
  EXPECT_FALSE(skipStale()) << "the heap lost an open handle";
  return pops;
}
}  // namespace

TEST(IndexedHeap, PopsWhatALazyPriorityQueuePopsTiesAndDecreasesIncluded)
{
  std::size_t pops = 0;
  for (uint32_t seed = 1; seed <= 20; ++seed)
  {
    pops += compareWithLazyQueue(seed, 500, 8);     // ties everywhere
    pops += compareWithLazyQueue(seed, 3000, 1 << 20);  // distinct keys, deep heap
  }
  EXPECT_GT(pops, 50000u);  // the comparison did happen (at most 70,000: every handle popped)
}

TEST(IndexedHeap, ReusedStorageStartsEmpty)
{
  std::vector<int32_t> pos(4, -1);
  std::vector<Item> storage{{1, 0}, {2, 1}};
  IndexedHeap<Item, Handles> heap(Handles{&pos}, std::move(storage));
  EXPECT_TRUE(heap.empty());
  heap.pushOrDecrease({5, 2});
  heap.pushOrDecrease({3, 3});
  heap.pushOrDecrease({1, 2});  // handle 2 lowered below handle 3
  EXPECT_EQ(heap.size(), 2u);
  EXPECT_EQ(heap.pop().handle, 2u);
  EXPECT_EQ(heap.pop().handle, 3u);
  EXPECT_TRUE(heap.empty());
}
