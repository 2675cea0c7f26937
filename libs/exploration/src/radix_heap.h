/* voxplore — a monotone priority queue on non-negative double keys (a radix
 * heap, Ahuja, Mehlhorn, Orlin and Tarjan 1990, on the keys' IEEE-754 bits)
 * for the frontier stage's Dijkstra (issue 12).
 *
 * Our own code, where a measured weakness of the library forces it: the
 * grid Dijkstra of findFrontiers settles every reachable cell of G, and
 * std::priority_queue's sift-down was most of the stage on 560 m^2 maps.
 * A Dijkstra pushes keys no smaller than the last one popped, which is all a
 * radix heap asks: a push is O(1), and each entry moves down at most once
 * per bit its key shares with the last popped key. The bits of non-negative
 * doubles order as their values. Internal to libs/exploration. */
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

namespace voxplore::exploration::detail
{
/// Pops its entries by ascending key (equal keys in no particular order).
/// Every key pushed must be >= 0 and >= the last key popped (or the floor
/// given to the constructor).
template <typename Value>
class RadixHeap
{
 public:
  explicit RadixHeap(double floor = 0.0) : last_(bits(floor)) {}

  bool empty() const { return size_ == 0; }

  void push(double key, const Value& v)
  {
    const uint64_t k = bits(key);
    buckets_[bucketOf(k)].push_back({k, v});
    ++size_;
  }

  /// The entry with the smallest key (the heap must not be empty).
  std::pair<double, Value> pop()
  {
    if (buckets_[0].empty())
    {
      std::size_t b = 1;
      while (buckets_[b].empty()) ++b;
      uint64_t m = buckets_[b].front().key;
      for (const Entry& e : buckets_[b]) m = e.key < m ? e.key : m;
      last_ = m;
      // Every entry of bucket b shares more leading bits with the new
      // minimum than with the old one: each goes to a lower bucket.
      for (const Entry& e : buckets_[b]) buckets_[bucketOf(e.key)].push_back(e);
      buckets_[b].clear();
    }
    const Entry e = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return {value(e.key), e.value};
  }

 private:
  struct Entry
  {
    uint64_t key;
    Value value;
  };
  static uint64_t bits(double d)
  {
    uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    return u;
  }
  static double value(uint64_t u)
  {
    double d;
    std::memcpy(&d, &u, sizeof d);
    return d;
  }
  /// 0 for the last key popped; else 1 + the highest bit where k differs from it.
  std::size_t bucketOf(uint64_t k) const
  {
    return k == last_ ? 0 : 64 - static_cast<std::size_t>(__builtin_clzll(k ^ last_));
  }

  std::array<std::vector<Entry>, 65> buckets_;
  uint64_t last_ = 0;
  std::size_t size_ = 0;
};

}  // namespace voxplore::exploration::detail
