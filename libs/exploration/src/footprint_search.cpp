/* voxplore — the A* over (cell, yaw bin) for the robot's rectangle and the
 * cost from the start that guides it (footprint_search.h, issue 13). */
#include "footprint_search.h"

#include <mrpt/core/exceptions.h>

#include "indexed_heap.h"

#include <cmath>
#include <limits>
#include <vector>

namespace voxplore::exploration
{
namespace detail
{
namespace
{
constexpr double kSqrt2 = 1.4142135623730951;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

/// SE2Search's buffers between searches (one set per thread).
thread_local std::vector<int32_t> t_block;
thread_local std::vector<Node> t_nodes;

/// The A*'s open list: among equal f the deeper state first, then the lower
/// state index (the order of the (f, -g, state) tuples it used to hold).
struct OpenItem
{
  double f, neg_g;
  uint32_t state, node;  ///< node: the state's index in SE2Search::nodes
  bool operator<(const OpenItem& o) const
  {
    if (f != o.f) return f < o.f;
    if (neg_g != o.neg_g) return neg_g < o.neg_g;
    return state < o.state;
  }
};
struct OpenHandles
{
  std::vector<Node>* nodes;
  uint32_t handle(const OpenItem& i) const { return i.node; }
  int32_t& pos(uint32_t h) const { return (*nodes)[h].pos; }
};
thread_local std::vector<OpenItem> t_open;

/// costFromCell's open list.
struct CostItem
{
  float cost;
  uint32_t cell;
  bool operator<(const CostItem& o) const
  {
    return cost != o.cost ? cost < o.cost : cell < o.cell;
  }
};
struct CostHandles
{
  std::vector<int32_t>* pos_of;
  uint32_t handle(const CostItem& i) const { return i.cell; }
  int32_t& pos(uint32_t h) const { return (*pos_of)[h]; }
};
thread_local std::vector<CostItem> t_cost_open;
}  // namespace

void SE2Search::takeScratch()
{
  block.swap(t_block);
  nodes.swap(t_nodes);
}

void SE2Search::giveScratch()
{
  // The larger buffers stay (a search still alive on this thread may hold
  // the spare ones).
  if (block.capacity() > t_block.capacity()) block.swap(t_block);
  if (nodes.capacity() > t_nodes.capacity()) nodes.swap(t_nodes);
}

bool SE2Search::mayTranslate(int cx, int cy, int k, int bin) const
{
  const int x = cx + kDx[k], y = cy + kDy[k];
  if (x < 0 || y < 0 || x >= nx || y >= ny) return false;
  if (!allowed(static_cast<std::size_t>(x + y * nx), bin)) return false;
  return k < 4 || (allowed(static_cast<std::size_t>(x + cy * nx), bin) &&
                   allowed(static_cast<std::size_t>(cx + y * nx), bin));
}

std::vector<std::size_t> SE2Search::run(std::size_t start_cell, int start_bin,
                                        std::size_t goal_cell, const std::vector<float>& from_start,
                                        YawMask goal_bins)
{
  ASSERTMSG_(static_cast<double>(nx) * ny * bins < 4294967296.0,
             "SE2Search: the grid's cells x yaw bins exceed 2^32 states");
  IndexedHeap<OpenItem, OpenHandles> open(OpenHandles{&nodes}, std::move(t_open));
  const std::size_t s0 = start_cell * bins + start_bin;
  const YawMask seeds = fs.allowed(goal_cell) & fs.reach.data()[goal_cell] & goal_bins;
  for (int b = 0; b < bins; ++b)
  {
    if (!((seeds >> b) & 1u)) continue;
    const std::size_t t = goal_cell * bins + b;
    const std::size_t nt = nodeIndex(t);
    nodes[nt] = Node{0.0f, 0x7f};  // the goal: no move
    open.pushOrDecrease({p.footprint_heuristic_weight * from_start[goal_cell], 0.0,
                         static_cast<uint32_t>(t), static_cast<uint32_t>(nt)});
  }
  bool found = false;
  while (!open.empty())
  {
    const std::size_t u = open.pop().state;
    Node& nu = node(u);
    nu.how |= kClosedBit;
    if (u == s0)
    {
      found = true;
      break;
    }
    const double gu = nu.g;
    const std::size_t cell = u / bins;
    const int bin = static_cast<int>(u % bins);
    const int cx = static_cast<int>(cell % nx), cy = static_cast<int>(cell / nx);
    // Predecessor s reaches u by `move` at forward cost `cost`.
    const auto relax = [&](std::size_t s, std::size_t s_cell, double cost, uint8_t move)
    {
      const float h = from_start[s_cell];
      if (!std::isfinite(h)) return;
      const std::size_t ni = nodeIndex(s);
      Node& ns = nodes[ni];
      if (ns.how != kUnseen && (ns.how & kClosedBit)) return;
      const double ng = gu + cost;
      if (ng >= ns.g) return;
      ns.g = static_cast<float>(ng);
      ns.how = move;
      open.pushOrDecrease({ng + p.footprint_heuristic_weight * h, -ng, static_cast<uint32_t>(s),
                           static_cast<uint32_t>(ni)});
    };
    // Translations into u: from the cell one step back, in the same bin.
    const double into = res * factor(cell) * comfort(cell, bin);
    for (int k = 0; k < 8; ++k)
    {
      const int x = cx - kDx[k], y = cy - kDy[k];
      if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
      const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
      const std::size_t s = j * bins + bin;
      if (s != s0 && !allowed(j, bin)) continue;
      if (!mayTranslate(x, y, k, bin)) continue;
      relax(s, j, (k < 4 ? 1.0 : kSqrt2) * into, static_cast<uint8_t>(k));
    }
    // Turns into u: from the next bin either way, both turnable here.
    if (!turnable(cell, bin)) continue;
    const int up = (bin + 1) % bins, down = (bin + bins - 1) % bins;
    // Forward kTurnUp goes bin-1 -> bin: its source is `down`.
    if (turnable(cell, down)) relax(cell * bins + down, cell, turn_cost, kTurnUp);
    if (turnable(cell, up)) relax(cell * bins + up, cell, turn_cost, kTurnDown);
  }
  t_open = std::move(open).release();
  std::vector<std::size_t> states;
  if (!found) return states;
  for (std::size_t s = s0;;)
  {
    states.push_back(s);
    const uint8_t m = node(s).how & ~kClosedBit;
    if (m == 0x7f) break;
    const std::size_t cell = s / bins;
    const int bin = static_cast<int>(s % bins);
    if (m == kTurnUp)
      s = cell * bins + (bin + 1) % bins;
    else if (m == kTurnDown)
      s = cell * bins + (bin + bins - 1) % bins;
    else
    {
      const int x = static_cast<int>(cell % nx) + kDx[m], y = static_cast<int>(cell / nx) + kDy[m];
      s = (static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx) * bins + bin;
    }
  }
  return states;
}

std::vector<float> costFromCell(const CollisionSpace& cs, const FootprintSpace& fs,
                                const PathParams& p, const Cell& start)
{
  // Dijkstra over the cells holding a reached or escape state, from
  // `start`; a step costs its length times the clearance factor of the
  // cell entered (what the SE(2) translation into it costs at least; turns
  // cost more than nothing). Diagonals skip the corner test: a relaxation.
  const int nx = static_cast<int>(cs.state.getSizeX()), ny = static_cast<int>(cs.state.getSizeY());
  const double res = cs.state.getResolution();
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  std::vector<float> d(n, std::numeric_limits<float>::infinity());
  const auto& reach = fs.reach.data();
  const auto& escape = fs.escape.data();
  // +infinity where no state is reached or escapes: no step enters there.
  std::vector<float> step_cost(n, std::numeric_limits<float>::infinity());
  const auto& clear_turn = fs.clear_turn.data();
  for (std::size_t i = 0; i < n; ++i)
    if (reach[i] | escape[i])
      step_cost[i] = static_cast<float>(
          res * p.costFactor(cs.clearance(i)) *
          // SE2Search::comfort: double where no reached bin keeps the turn margin.
          ((clear_turn[i] & (reach[i] | escape[i])) ? 1.0 : 2.0));
  if (start.cx < 0 || start.cy < 0 || start.cx >= nx || start.cy >= ny) return d;
  const uint32_t r0 = static_cast<uint32_t>(start.cx + start.cy * nx);
  std::vector<int32_t> pos(n, -1);
  IndexedHeap<CostItem, CostHandles> open(CostHandles{&pos}, std::move(t_cost_open));
  d[r0] = 0;
  open.pushOrDecrease({0.0f, r0});
  while (!open.empty())
  {
    const auto [du, u] = open.pop();
    const int cx = static_cast<int>(u % nx), cy = static_cast<int>(u / nx);
    for (int k = 0; k < 8; ++k)
    {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= nx || y >= ny) continue;
      const std::size_t j = static_cast<std::size_t>(x) + static_cast<std::size_t>(y) * nx;
      const float nd = du + static_cast<float>(k < 4 ? 1.0 : kSqrt2) * step_cost[j];
      if (nd >= d[j]) continue;
      d[j] = nd;
      open.pushOrDecrease({nd, static_cast<uint32_t>(j)});
    }
  }
  t_cost_open = std::move(open).release();
  // Float sums may round a bound above a double-precision path cost by an
  // ulp: shave it off (a bound, not a distance).
  for (float& v : d)
    if (std::isfinite(v)) v *= 0.9999f;
  return d;
}
}  // namespace detail

std::vector<float> footprintCostFromStart(
    const CollisionSpace& cs, const FootprintSpace& fs, const PathParams& p)
{
  return detail::costFromCell(cs, fs, p, fs.robot);
}

}  // namespace voxplore::exploration
