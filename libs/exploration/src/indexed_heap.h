/* voxplore — a 4-ary min-heap with decrease-key for the searches of
 * libs/exploration (issue 13).
 *
 * Our own code, where a measured weakness of the library forces it: the SE(2)
 * A* and its Dijkstra heuristic used std::priority_queue with lazy deletion,
 * and on the b10 map (twenty-eighth session, perf) 86 k of the A*'s 141 k
 * pops were stale copies of improved states, the heap's sift-down half of
 * the search's time. Here a state is in the heap at most once; lowering its
 * key moves it up. Internal to libs/exploration. */
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace voxplore::exploration::detail
{
/// A min-heap of `Item`s (`operator<`, a strict total order on the items in
/// it) that knows where each item is. `Handles` maps an item to its handle
/// (`uint32_t handle(const Item&)`) and a handle to the slot holding the
/// item's position (`int32_t& pos(uint32_t)`, -1 when not in the heap; the
/// caller sets it to -1 for new handles). Popping returns the minimum, so a
/// search pops its states in the order it would from a std::priority_queue
/// with lazy deletion, the stale copies left out.
template <typename Item, typename Handles>
class IndexedHeap
{
 public:
  /// @param storage  a vector to reuse (its capacity), emptied here
  IndexedHeap(Handles handles, std::vector<Item>&& storage)
      : h_(std::move(handles)), heap_(std::move(storage))
  {
    heap_.clear();
  }

  /// The storage, to hand to the next heap.
  std::vector<Item> release() && { return std::move(heap_); }

  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }

  /// Inserts `item`, or replaces the item of the same handle already in the
  /// heap, which must not be less than `item`.
  void pushOrDecrease(const Item& item)
  {
    const int32_t at = h_.pos(h_.handle(item));
    std::size_t i;
    if (at < 0)
    {
      i = heap_.size();
      heap_.push_back(item);
    }
    else
      i = static_cast<std::size_t>(at);
    siftUp(i, item);
  }

  /// Removes and returns the minimum; the heap must not be empty.
  Item pop()
  {
    const Item top = heap_.front();
    h_.pos(h_.handle(top)) = -1;
    const Item last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) siftDown(last);
    return top;
  }

 private:
  static constexpr std::size_t kArity = 4;  // fewer levels than 2, children on one cache line

  void place(std::size_t i, const Item& e)
  {
    heap_[i] = e;
    h_.pos(h_.handle(e)) = static_cast<int32_t>(i);
  }

  void siftUp(std::size_t i, const Item& e)
  {
    while (i > 0)
    {
      const std::size_t parent = (i - 1) / kArity;
      if (!(e < heap_[parent])) break;
      place(i, heap_[parent]);
      i = parent;
    }
    place(i, e);
  }

  /// Puts `e` at the root's place and moves it down.
  void siftDown(const Item& e)
  {
    const std::size_t n = heap_.size();
    std::size_t i = 0;
    for (;;)
    {
      const std::size_t first = i * kArity + 1;
      if (first >= n) break;
      const std::size_t end = first + kArity < n ? first + kArity : n;
      std::size_t best = first;
      for (std::size_t c = first + 1; c < end; ++c)
        if (heap_[c] < heap_[best]) best = c;
      if (!(heap_[best] < e)) break;
      place(i, heap_[best]);
      i = best;
    }
    place(i, e);
  }

  Handles h_;
  std::vector<Item> heap_;
};
}  // namespace voxplore::exploration::detail
