/* voxplore — reachable space and frontiers (thesis 4.5.3). */
#include <mrpt/core/exceptions.h>
#include <voxplore/common/distance_transform.h>
#include <voxplore/exploration/stages.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

#include "radix_heap.h"

namespace voxplore::exploration
{
namespace
{
constexpr double kSqrt2 = 1.4142135623730951;
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

/// Dijkstra state over the grid (row-major index = cx + cy * nx).
struct Search
{
  int nx = 0, ny = 0;
  const SpaceState* space = nullptr;
  const uint8_t* open_unknown = nullptr;  ///< CollisionSpace::open_unknown
  const uint8_t* retired = nullptr;       ///< findFrontiers' `retired`; nullptr: none
  int grow_cells = 0;           ///< CollisionSpace::frontier_grow_m in cells
  std::vector<double> dist;     ///< cells; < 0: not reached
  std::vector<uint8_t> escape;  ///< reached from a non-Free start through non-Free cells only
  bool free_settled = false;    ///< a Free cell has been settled: escaping stops
};

/// May the search step from cell `from` into cell `to`? Free cells expand
/// into Free and MaybeCollision; MaybeCollision cells (the band) only into
/// MaybeCollision; a non-Free start escapes through Collision/MaybeCollision
/// cells until the first Free cell is settled.
bool mayEnter(const Search& s, int from, int to)
{
  const SpaceState a = s.space[from], b = s.space[to];
  if (s.escape[from] && !s.free_settled)
    return b == SpaceState::Free || b == SpaceState::MaybeCollision || b == SpaceState::Collision;
  if (a == SpaceState::Free) return b == SpaceState::Free || b == SpaceState::MaybeCollision;
  if (a == SpaceState::MaybeCollision) return b == SpaceState::MaybeCollision;
  return false;
}

/// Relaxes the 8 neighbours of cell i, settled at distance d: push(nd, j)
/// for each neighbour j it brings closer.
template <typename Push>
void relaxNeighbours(Search& s, double d, int i, Push&& push)
{
  const int cx = i % s.nx, cy = i / s.nx;
  for (int k = 0; k < 8; ++k)
  {
    const int x = cx + kDx[k], y = cy + kDy[k];
    if (x < 0 || y < 0 || x >= s.nx || y >= s.ny) continue;
    const int j = x + y * s.nx;
    if (!mayEnter(s, i, j)) continue;
    if (k >= 4 &&
        (!mayEnter(s, i, cx + kDx[k] + cy * s.nx) || !mayEnter(s, i, cx + (cy + kDy[k]) * s.nx)))
      continue;
    const double nd = d + (k < 4 ? 1.0 : kSqrt2);
    if (s.dist[j] >= 0 && s.dist[j] <= nd) continue;
    s.dist[j] = nd;
    s.escape[j] = s.escape[i] && !s.free_settled && s.space[j] != SpaceState::Free;
    push(nd, j);
  }
}

/// 8-connected Dijkstra, 1 per straight step and sqrt(2) per diagonal one;
/// a diagonal step needs both cells beside it to be enterable (no corner
/// cutting). The escape from a non-Free start depends on the order in which
/// equal distances are settled, so a binary heap ordered by (distance, cell)
/// runs until the first Free cell is settled; from then on the escape is
/// fixed, the distances do not depend on that order (each is the smallest
/// of its closer neighbours' plus a step), and a radix heap takes over.
void runDijkstra(Search& s, int start)
{
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  s.dist[start] = 0;
  s.escape[start] = s.space[start] != SpaceState::Free;
  open.push({0.0, start});
  double last = 0;
  while (!open.empty() && !s.free_settled)
  {
    const auto [d, i] = open.top();
    open.pop();
    if (d > s.dist[i]) continue;
    last = d;
    if (s.space[i] == SpaceState::Free) s.free_settled = true;
    relaxNeighbours(s, d, i, [&](double nd, int j) { open.push({nd, j}); });
  }
  detail::RadixHeap<int> rest(last);
  for (; !open.empty(); open.pop()) rest.push(open.top().first, open.top().second);
  while (!rest.empty())
  {
    const auto [d, i] = rest.pop();
    if (d > s.dist[i]) continue;
    relaxNeighbours(s, d, i, [&](double nd, int j) { rest.push(nd, j); });
  }
}

/// An open Unknown cell (CollisionSpace::open_unknown), or off the grid.
bool isOpenUnknown(const Search& s, int x, int y)
{
  if (x < 0 || y < 0 || x >= s.nx || y >= s.ny) return true;  // off the grid: unknown
  return s.open_unknown[x + y * s.nx] != 0 && !(s.retired && s.retired[x + y * s.nx]);
}

/// A known free cell (any space state but Occupied / Unknown) with an open
/// Unknown (or off-grid) 4-neighbour.
bool bordersOpenUnknown(const Search& s, int i)
{
  if (s.space[i] == SpaceState::Occupied || s.space[i] == SpaceState::Unknown) return false;
  const int cx = i % s.nx, cy = i / s.nx;
  for (int k = 0; k < 4; ++k)
    if (isOpenUnknown(s, cx + kDx[k], cy + kDy[k])) return true;
  return false;
}

/// Reached Free/MaybeCollision cell with an open Unknown (or off-grid)
/// 4-neighbour.
bool isFrontierCell(const Search& s, int i)
{
  if (s.dist[i] < 0) return false;
  if (s.space[i] != SpaceState::Free && s.space[i] != SpaceState::MaybeCollision) return false;
  return bordersOpenUnknown(s, i);
}

/// Spreads the labels (>= 0; -1: none) of `label` breadth-first, by up to
/// `grow_cells` 8-steps, over unlabelled known free cells that border open
/// unknown: a cell takes the label of the cell that reached it first.
void growAlongOpenBorder(const Search& s, std::vector<int32_t>& label, int grow_cells)
{
  std::vector<int> front, next;
  for (std::size_t i = 0; i < label.size(); ++i)
    if (label[i] >= 0) front.push_back(static_cast<int>(i));
  for (int step = 0; step < grow_cells && !front.empty(); ++step)
  {
    next.clear();
    for (const int i : front)
    {
      const int cx = i % s.nx, cy = i / s.nx;
      for (int k = 0; k < 8; ++k)
      {
        const int x = cx + kDx[k], y = cy + kDy[k];
        if (x < 0 || y < 0 || x >= s.nx || y >= s.ny) continue;
        const int j = x + y * s.nx;
        if (label[j] >= 0 || !bordersOpenUnknown(s, j)) continue;
        label[j] = label[i];
        next.push_back(j);
      }
    }
    front.swap(next);
  }
}

/// Footprint model: the frontier cells grown, along known free cells that
/// border open unknown, by up to `grow_cells` 8-steps (the rectangle reaches
/// a door's middle only; the door's whole width is its frontier).
void growFrontier(const Search& s, std::vector<uint8_t>& is_frontier, int grow_cells)
{
  std::vector<int32_t> label(is_frontier.size(), -1);
  for (std::size_t i = 0; i < is_frontier.size(); ++i)
    if (is_frontier[i]) label[i] = 0;
  growAlongOpenBorder(s, label, grow_cells);
  for (std::size_t i = 0; i < is_frontier.size(); ++i) is_frontier[i] = label[i] >= 0;
}

/// Fills size, distance, centroid and center of a frontier from its cells.
void describe(Frontier& f, const Search& s, const Grid<SpaceState>& g)
{
  const double res = g.getResolution();
  f.size_m = static_cast<double>(f.cells.size()) * res;
  f.distance_m = std::numeric_limits<double>::infinity();
  f.centroid.setZero();
  for (const Cell& c : f.cells)
  {
    const double d = s.dist[c.cx + c.cy * s.nx];
    if (d >= 0) f.distance_m = std::min(f.distance_m, d * res);
    f.centroid += cellCenter(g, c);
  }
  f.centroid /= static_cast<double>(f.cells.size());
  double best = std::numeric_limits<double>::infinity();
  for (const Cell& c : f.cells)
  {
    const double d2 = (cellCenter(g, c) - f.centroid).squaredNorm();
    if (d2 < best)
    {
      best = d2;
      f.center = cellCenter(g, c);
    }
  }
}

/// Footprint model: a frontier group longer than this many cells is cut
/// into pieces. The rectangle's band reaches along every wall that borders
/// unknown space, so the groups run round whole rooms (the circle's
/// collision band cuts them at the walls); the centre of such a group lies
/// in the room's middle, where there is nothing to see (building 1: the
/// nearest frontier baseline stopped after 0.55 m).
constexpr int kMaxFootprintFrontierCells = 40;

/// Cuts a group into pieces of kMaxFootprintFrontierCells cells in
/// breadth-first order (8-connected, within the group) from its cell nearest
/// to the robot: consecutive rings of the search, each piece compact.
std::vector<std::vector<Cell>> splitFrontier(const Search& s, const std::vector<Cell>& cells)
{
  std::vector<int8_t> mark(s.dist.size(), 0);  // 1: in the group, 2: visited
  std::size_t seed = 0;
  for (std::size_t k = 0; k < cells.size(); ++k)
  {
    const int i = cells[k].cx + cells[k].cy * s.nx;
    mark[i] = 1;
    const double d = s.dist[i], best = s.dist[cells[seed].cx + cells[seed].cy * s.nx];
    if (d >= 0 && (best < 0 || d < best)) seed = k;
  }
  std::vector<std::vector<Cell>> out;
  // The group is 8-connected: one search visits it all.
  std::vector<int> queue{cells[seed].cx + cells[seed].cy * s.nx};
  mark[queue.front()] = 2;
  for (std::size_t q = 0; q < queue.size(); ++q)
  {
    const int i = queue[q];
    const int cx = i % s.nx, cy = i / s.nx;
    if (q % kMaxFootprintFrontierCells == 0) out.emplace_back();
    out.back().push_back({cx, cy});
    for (int k = 0; k < 8; ++k)
    {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= s.nx || y >= s.ny) continue;
      const int j = x + y * s.nx;
      if (mark[j] != 1) continue;
      mark[j] = 2;
      queue.push_back(j);
    }
  }
  return out;
}

/// Frontier::opening_m of every frontier: its cells and the known free cells
/// that border open unknown within `grow_cells` 8-steps of them along such
/// cells (each cell counted for the frontier whose cells reach it first,
/// breadth-first from all frontiers at once).
void measureOpenings(const Search& s, std::vector<Frontier>& frontiers, int grow_cells, double res)
{
  std::vector<int32_t> owner(s.dist.size(), -1);
  for (std::size_t k = 0; k < frontiers.size(); ++k)
    for (const Cell& c : frontiers[k].cells)
    {
      int32_t& o = owner[static_cast<std::size_t>(c.cx + c.cy * s.nx)];
      if (o < 0) o = static_cast<int32_t>(k);
    }
  growAlongOpenBorder(s, owner, grow_cells);
  std::vector<std::size_t> count(frontiers.size(), 0);
  for (const int32_t o : owner)
    if (o >= 0) count[static_cast<std::size_t>(o)]++;
  for (std::size_t k = 0; k < frontiers.size(); ++k)
    frontiers[k].opening_m = static_cast<double>(count[k]) * res;
}

/// Frontier::unknown_m2 of every frontier: the sum of the areas of the
/// distinct pockets of open unknown (openUnknownPockets) next to its cells; a
/// pocket that touches the grid's border is unbounded.
/// `pockets`: openUnknownPockets of s.open_unknown.
void measureUnknownBehind(const Search& s, const UnknownPockets& pockets,
                          std::vector<Frontier>& frontiers, double res)
{
  const std::vector<int32_t>& pocket = pockets.label;
  std::vector<double> area;  // per pocket [m^2]; infinity: touches the border
  for (const int64_t cells : pockets.cells)
    area.push_back(cells < 0 ? std::numeric_limits<double>::infinity()
                             : static_cast<double>(cells) * res * res);
  std::vector<int32_t> seen;
  for (Frontier& f : frontiers)
  {
    seen.clear();
    f.unknown_m2 = 0;
    for (const Cell& c : f.cells)
      for (int k = 0; k < 4; ++k)
      {
        const int x = c.cx + kDx[k], y = c.cy + kDy[k];
        if (x < 0 || y < 0 || x >= s.nx || y >= s.ny)
        {
          f.unknown_m2 = std::numeric_limits<double>::infinity();
          continue;
        }
        const int32_t id = pocket[static_cast<std::size_t>(x + y * s.nx)];
        if (id < 0 || std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
        seen.push_back(id);
        f.unknown_m2 += area[static_cast<std::size_t>(id)];
      }
  }
}

/// Groups the cells marked in `is_frontier` 8-connected, in row-major order
/// of their first cell; with `split`, a group longer than
/// kMaxFootprintFrontierCells is cut into pieces.
std::vector<Frontier> groupCells(const Search& s, const Grid<SpaceState>& g,
                                 const std::vector<uint8_t>& is_frontier, bool split)
{
  const std::size_t n = s.dist.size();
  std::vector<uint8_t> taken(n, 0);
  std::vector<Frontier> out;
  std::vector<int> stack;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (!is_frontier[seed] || taken[seed]) continue;
    Frontier f;
    stack.assign(1, static_cast<int>(seed));
    taken[seed] = 1;
    while (!stack.empty())
    {
      const int i = stack.back();
      stack.pop_back();
      const int cx = i % s.nx, cy = i / s.nx;
      f.cells.push_back({cx, cy});
      for (int k = 0; k < 8; ++k)
      {
        const int x = cx + kDx[k], y = cy + kDy[k];
        if (x < 0 || y < 0 || x >= s.nx || y >= s.ny) continue;
        const int j = x + y * s.nx;
        if (!is_frontier[j] || taken[j]) continue;
        taken[j] = 1;
        stack.push_back(j);
      }
    }
    if (split && static_cast<int>(f.cells.size()) > kMaxFootprintFrontierCells)
    {
      for (auto& piece : splitFrontier(s, f.cells))
      {
        Frontier part;
        part.cells = std::move(piece);
        describe(part, s, g);
        out.push_back(std::move(part));
      }
      continue;
    }
    describe(f, s, g);
    out.push_back(std::move(f));
  }
  return out;
}

/// Groups the frontier cells (isFrontierCell, grown in the footprint model)
/// 8-connected, in row-major order of their first cell.
std::vector<Frontier> groupFrontiers(const Search& s, const Grid<SpaceState>& g)
{
  std::vector<uint8_t> is_frontier(s.dist.size(), 0);
  for (std::size_t i = 0; i < is_frontier.size(); ++i)
    is_frontier[i] = isFrontierCell(s, static_cast<int>(i));
  if (s.grow_cells > 0) growFrontier(s, is_frontier, s.grow_cells);
  return groupCells(s, g, is_frontier, s.grow_cells > 0);
}

/// The unreached frontiers (findFrontiers' `unreached`): Free cells of G that the
/// search `s` did not reach, within params.within_m of a reached cell over
/// Free cells of G (8-connected, no corner cutting), that border open
/// unknown and belong to no frontier of `reached`; grouped as the footprint
/// model's (`split`), their distance the nearest reached cell's plus the
/// way from it; kept when a cell of the group lies at least
/// params.min_depth_m beyond the reach and the pocket it borders is closed
/// and at least params.min_unknown_m2. Our own, not the thesis' (4.5.3
/// keeps reachable cells only).
std::vector<Frontier> unreachedFrom(const GroundGrid& g, const Search& s,
                                    const Grid<SpaceState>& grid,
                                    const std::vector<Frontier>& reached,
                                    const UnknownPockets& pockets,
                                    const UnreachedFrontiers& params)
{
  const double res = grid.getResolution();
  const double within = params.within_m / res + 1e-9;
  const auto& cells = g.state.data();
  const std::size_t n = cells.size();
  const auto gfree = [&](int i) { return cells[static_cast<std::size_t>(i)] == GroundState::Free; };
  const auto neighbour = [&](int i, int k) {
    const int x = i % s.nx + kDx[k], y = i / s.nx + kDy[k];
    return x < 0 || y < 0 || x >= s.nx || y >= s.ny ? -1 : x + y * s.nx;
  };
  Search u = s;  // dist becomes the way to the nearest reached cell plus its distance
  std::vector<double> extra(n, -1.0);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  // Seeds: the reached cells beside an unreached Free cell of G.
  for (int i = 0; i < static_cast<int>(n); ++i)
  {
    if (s.dist[i] < 0 || !gfree(i)) continue;
    for (int k = 0; k < 8; ++k)
    {
      const int j = neighbour(i, k);
      if (j < 0 || s.dist[j] >= 0 || !gfree(j)) continue;
      extra[i] = 0;
      open.push({0.0, i});
      break;
    }
  }
  while (!open.empty())
  {
    const auto [d, i] = open.top();
    open.pop();
    if (d > extra[static_cast<std::size_t>(i)]) continue;
    const int cx = i % s.nx, cy = i / s.nx;
    for (int k = 0; k < 8; ++k)
    {
      const int j = neighbour(i, k);
      if (j < 0 || s.dist[j] >= 0 || !gfree(j)) continue;
      if (k >= 4 && (!gfree(cx + kDx[k] + cy * s.nx) || !gfree(cx + (cy + kDy[k]) * s.nx)))
        continue;
      const double nd = d + (k < 4 ? 1.0 : kSqrt2);
      if (nd > within || (extra[j] >= 0 && extra[j] <= nd)) continue;
      extra[j] = nd;
      u.dist[j] = u.dist[i] + (k < 4 ? 1.0 : kSqrt2);
      open.push({nd, j});
    }
  }
  std::vector<uint8_t> is_frontier(n, 0);
  for (std::size_t i = 0; i < n; ++i)
    is_frontier[i] = extra[i] > 0 && bordersOpenUnknown(u, static_cast<int>(i));
  for (const Frontier& f : reached)
    for (const Cell& c : f.cells) is_frontier[static_cast<std::size_t>(c.cx + c.cy * s.nx)] = 0;
  // Only the unreached cells carry a distance: a piece's is its own cells'.
  for (std::size_t i = 0; i < n; ++i)
    if (extra[i] <= 0) u.dist[i] = -1;
  std::vector<Frontier> out = groupCells(u, grid, is_frontier, s.grow_cells > 0);
  measureUnknownBehind(u, pockets, out, res);
  // A pocket reaching the grid's border is the outside beyond an outer
  // wall's unseen base, not a room; within the rectangle's reach of a
  // reached cell lies the floor along walls and furniture (b5 omniRob
  // nearest, step 167: 89 unreached frontiers, 71 facing the outside, 7 of
  // the other 18 within 1 m of the reach).
  const double depth = params.min_depth_m / res - 1e-9;
  out.erase(std::remove_if(out.begin(), out.end(), [&](const Frontier& f) {
              const bool deep = std::any_of(f.cells.begin(), f.cells.end(), [&](const Cell& c) {
                return extra[static_cast<std::size_t>(c.cx + c.cy * s.nx)] >= depth;
              });
              return !deep || f.unknown_m2 < params.min_unknown_m2 || std::isinf(f.unknown_m2);
            }),
            out.end());
  for (Frontier& f : out) f.unreached = true;
  std::stable_sort(out.begin(), out.end(), [](const Frontier& a, const Frontier& b)
                   { return a.distance_m < b.distance_m; });
  return out;
}
}  // namespace

FrontierMap findFrontiers(const GroundGrid& g, const CollisionSpace& cs,
                          const std::vector<uint8_t>* retired, const UnreachedFrontiers& unreached)
{
  const Grid<SpaceState>& grid = cs.state;
  Search s;
  s.nx = static_cast<int>(grid.getSizeX());
  s.ny = static_cast<int>(grid.getSizeY());
  ASSERTMSG_(inGrid(grid, g.robot.cx, g.robot.cy), "findFrontiers: the robot cell is off the grid");
  s.space = grid.data().data();
  ASSERT_EQUAL_(cs.open_unknown.size(), grid.data().size());
  s.open_unknown = cs.open_unknown.data();
  if (retired && !retired->empty()) ASSERT_EQUAL_(retired->size(), grid.data().size());
  s.retired = retired && !retired->empty() ? retired->data() : nullptr;
  s.grow_cells = static_cast<int>(std::ceil(cs.frontier_grow_m / grid.getResolution() - 1e-9));
  s.dist.assign(grid.data().size(), -1.0);
  s.escape.assign(grid.data().size(), 0);
  runDijkstra(s, g.robot.cx + g.robot.cy * s.nx);

  FrontierMap fm;
  const double res = grid.getResolution();
  const float minus_one = -1.f;
  const uint8_t zero = 0;
  fm.distance_m.setSize(grid.getXMin(), grid.getXMax(), grid.getYMin(), grid.getYMax(), res,
                        &minus_one);
  fm.reachable.setSize(grid.getXMin(), grid.getXMax(), grid.getYMin(), grid.getYMax(), res, &zero);
  auto d_out = fm.distance_m.begin();
  auto r_out = fm.reachable.begin();
  for (std::size_t i = 0; i < s.dist.size(); ++i, ++d_out, ++r_out)
  {
    if (s.dist[i] < 0) continue;
    *d_out = static_cast<float>(s.dist[i] * res);
    *r_out = s.space[i] == SpaceState::Free ? 1 : 0;
  }

  fm.frontiers = groupFrontiers(s, grid);
  if (s.grow_cells > 0)
    for (Frontier& f : fm.frontiers) f.opening_m = f.size_m;  // grown already
  else
    measureOpenings(s, fm.frontiers, static_cast<int>(std::ceil(cs.radius_m / res - 1e-9)), res);
  const UnknownPockets pockets = openUnknownPockets(s.open_unknown, s.nx, s.ny);
  measureUnknownBehind(s, pockets, fm.frontiers, res);
  // thesis 4.5.3: ascending travel distance; ties: the larger frontier first.
  std::stable_sort(
      fm.frontiers.begin(), fm.frontiers.end(),
      [](const Frontier& a, const Frontier& b)
      { return a.distance_m != b.distance_m ? a.distance_m < b.distance_m : a.size_m > b.size_m; });
  if (unreached.within_m > 0)
  {
    const auto more = unreachedFrom(g, s, grid, fm.frontiers, pockets, unreached);
    fm.frontiers.insert(fm.frontiers.end(), more.begin(), more.end());
  }
  for (std::size_t k = 0; k < fm.frontiers.size(); ++k) fm.frontiers[k].id = static_cast<int>(k);
  return fm;
}

double cutOffFloorM2(const GroundGrid& g, const CollisionSpace& cs, const FrontierMap& fm)
{
  const auto& st = g.state;
  const int nx = static_cast<int>(st.getSizeX()), ny = static_cast<int>(st.getSizeY());
  if (nx == 0 || ny == 0) return 0;
  ASSERT_EQUAL_(fm.reachable.data().size(), st.data().size());
  std::vector<double> sq(st.data().size(), common::kEdtFar);
  bool any = false;
  for (std::size_t i = 0; i < sq.size(); ++i)
    if (fm.reachable.data()[i])
    {
      sq[i] = 0;
      any = true;
    }
  if (any) common::squaredDistanceTransform(sq, nx, ny);
  const double res = st.getResolution();
  const double r_cells = cs.radius_m / res + 1.0;
  std::size_t cut = 0;
  for (std::size_t i = 0; i < sq.size(); ++i)
    if (st.data()[i] == GroundState::Free && sq[i] > r_cells * r_cells) ++cut;
  return static_cast<double>(cut) * res * res;
}

}  // namespace voxplore::exploration
