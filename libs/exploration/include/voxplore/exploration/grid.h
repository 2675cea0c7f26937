/* voxplore — the 2D exploration grid G and its layers (thesis 4.5). */
#pragma once

#include <mrpt/containers/CDynamicGrid.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace voxplore::exploration
{
/// @brief A 2D grid over world metres with signed coordinates (MRPT's
///        CDynamicGrid: no offset tricks in our code). Cell (cx, cy) covers
///        [x_min + cx*res, x_min + (cx+1)*res) x [...]; with x_min a multiple
///        of res, cells line up with the OctoMap voxel columns of the same res.
///
///        Our own class only for a real move: MRPT 2.5.8's CDynamicGrid
///        declares a virtual destructor and no move operations, so every
///        move of a grid (a layer returned into a struct, make_shared of a
///        stage's result, a vector growing) copied all its cells. Measured on
///        a kept planning step (b10, omniRob, voxplore-plan --repeat under
///        perf): a fifth of the step in memmove and the page faults of the
///        copies. A moved-from grid is empty (0 x 0 cells).
template <typename T>
class Grid : public mrpt::containers::CDynamicGrid<T>
{
  using Base = mrpt::containers::CDynamicGrid<T>;

 public:
  using Base::Base;
  Grid() = default;
  Grid(const Grid&) = default;
  Grid& operator=(const Grid&) = default;
  Grid(Grid&& o) noexcept : Base(0, 0, 0, 0, 1) { take(o); }
  Grid& operator=(Grid&& o) noexcept
  {
    if (this != &o) take(o);
    return *this;
  }
  ~Grid() override = default;

  /// @brief Hands the cells' storage over (capacity kept) and leaves the grid
  ///        0 x 0, as a move does: for storage kept for a later grid.
  std::vector<T> releaseStorage() noexcept
  {
    std::vector<T> out;
    out.swap(this->m_map);
    this->m_size_x = this->m_size_y = 0;
    this->m_x_max = this->m_x_min;
    this->m_y_max = this->m_y_min;
    return out;
  }

  /// @brief setSize with `like`'s extent, every cell `value`, in `storage`'s
  ///        memory when its capacity suffices (no fresh pages to fault in).
  template <typename U>
  void resetLike(const Grid<U>& like, T value, std::vector<T>&& storage)
  {
    this->m_map.swap(storage);
    this->setSize(like.getXMin(), like.getXMax(), like.getYMin(), like.getYMax(),
                  like.getResolution(), &value);
  }

 private:
  void take(Grid& o) noexcept
  {
    this->m_map.swap(o.m_map);
    o.m_map.clear();
    this->m_x_min = o.m_x_min;
    this->m_x_max = o.m_x_max;
    this->m_y_min = o.m_y_min;
    this->m_y_max = o.m_y_max;
    this->m_resolution = o.m_resolution;
    this->m_size_x = o.m_size_x;
    this->m_size_y = o.m_size_y;
    o.m_size_x = o.m_size_y = 0;
    o.m_x_max = o.m_x_min;
    o.m_y_max = o.m_y_min;
  }
};

/// @brief Cell index pair.
struct Cell
{
  int cx = 0, cy = 0;
  bool operator==(const Cell& o) const { return cx == o.cx && cy == o.cy; }
  bool operator!=(const Cell& o) const { return !(*this == o); }
};

/// @brief State of a cell of G after the projection (algorithm 2).
enum class GroundState : uint8_t
{
  Unknown = 0,  ///< not reached by the flood fill, or a column with an unknown voxel
  Free = 1,     ///< every voxel of the column in [z_min, z_max] is free
  Occupied = 2  ///< a voxel of the column is occupied
};

/// @brief Space classes after the collision-space step (thesis 4.5.2).
enum class SpaceState : uint8_t
{
  Unknown = 0,         ///< G unknown
  Occupied = 1,        ///< G occupied
  Collision = 2,       ///< free, within r_coll + sqrt(2) l_res of an occupied cell
  MaybeCollision = 3,  ///< free, within that distance of an unknown cell (not of an occupied one)
  Free = 4             ///< free and clear of both: the robot centre may be here
};

/// @brief Centre of a cell in world metres.
template <typename T>
Eigen::Vector2d cellCenter(const Grid<T>& g, const Cell& c)
{
  return {g.idx2x(c.cx), g.idx2y(c.cy)};
}

/// @brief The cell containing world point p; false when outside the grid.
template <typename T>
bool cellOf(const Grid<T>& g, const Eigen::Vector2d& p, Cell& out)
{
  if (p.x() < g.getXMin() || p.y() < g.getYMin() || p.x() >= g.getXMax() || p.y() >= g.getYMax())
    return false;
  out = {g.x2idx(p.x()), g.y2idx(p.y())};
  return out.cx >= 0 && out.cy >= 0 && out.cx < static_cast<int>(g.getSizeX()) &&
         out.cy < static_cast<int>(g.getSizeY());
}

/// @brief True when (cx, cy) is inside the grid.
template <typename T>
bool inGrid(const Grid<T>& g, int cx, int cy)
{
  return cx >= 0 && cy >= 0 && cx < static_cast<int>(g.getSizeX()) &&
         cy < static_cast<int>(g.getSizeY());
}

}  // namespace voxplore::exploration
