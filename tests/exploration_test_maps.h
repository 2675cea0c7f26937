/* voxplore tests — synthetic maps for the exploration stages: OcTrees built
 * voxel by voxel and ground grids built from rectangles. */
#pragma once

#include <octomap/OcTree.h>
#include <voxplore/exploration/stages.h>

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>

namespace voxplore::test
{
/// Sets every voxel whose centre lies in [x0,x1) x [y0,y1) x [z0,z1) to
/// `log_odds` (bounds are multiples of the resolution in the tests).
inline void fillBox(octomap::OcTree& t, double x0, double x1, double y0, double y1, double z0,
                    double z1, float log_odds)
{
  const double r = t.getResolution();
  const int nx = static_cast<int>(std::lround((x1 - x0) / r));
  const int ny = static_cast<int>(std::lround((y1 - y0) / r));
  const int nz = static_cast<int>(std::lround((z1 - z0) / r));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
      {
        const octomap::point3d p(static_cast<float>(x0 + (i + 0.5) * r),
                                 static_cast<float>(y0 + (j + 0.5) * r),
                                 static_cast<float>(z0 + (k + 0.5) * r));
        t.setNodeValue(t.coordToKey(p), log_odds);
      }
}

/// Clearly free / clearly occupied log-odds (the clamping bounds).
inline float freeLog(const octomap::OcTree& t)
{
  return t.getClampingThresMinLog();
}
inline float occLog(const octomap::OcTree& t)
{
  return t.getClampingThresMaxLog();
}

/// A room: free voxels over [x0,x1) x [y0,y1) for z in [0, 0.6), enclosed by
/// a one-voxel occupied wall (corners included).
inline void addRoom(octomap::OcTree& t, double x0, double x1, double y0, double y1)
{
  const double r = t.getResolution();
  fillBox(t, x0, x1, y0, y1, 0.0, 0.6, freeLog(t));
  fillBox(t, x0 - r, x1 + r, y0 - r, y0, 0.0, 0.6, occLog(t));
  fillBox(t, x0 - r, x1 + r, y1, y1 + r, 0.0, 0.6, occLog(t));
  fillBox(t, x0 - r, x0, y0, y1, 0.0, 0.6, occLog(t));
  fillBox(t, x1, x1 + r, y0, y1, 0.0, 0.6, occLog(t));
}

/// Free (or occupied) columns over a rectangle, z in [0, 0.6).
inline void setColumns(octomap::OcTree& t, double x0, double x1, double y0, double y1,
                       bool occupied)
{
  fillBox(t, x0, x1, y0, y1, 0.0, 0.6, occupied ? occLog(t) : freeLog(t));
}

/// A ground grid over [x0,x1) x [y0,y1) filled with `fill`.
inline exploration::GroundGrid makeGround(double x0, double x1, double y0, double y1, double res,
                                          exploration::GroundState fill)
{
  exploration::GroundGrid g;
  g.state.setSize(x0, x1, y0, y1, res, &fill);
  return g;
}

/// Sets the ground cells whose centres lie in [x0,x1) x [y0,y1).
inline void paint(exploration::GroundGrid& g, double x0, double x1, double y0, double y1,
                  exploration::GroundState s)
{
  for (std::size_t cy = 0; cy < g.state.getSizeY(); ++cy)
    for (std::size_t cx = 0; cx < g.state.getSizeX(); ++cx)
    {
      const double x = g.state.idx2x(static_cast<int>(cx)), y = g.state.idx2y(static_cast<int>(cy));
      if (x >= x0 && x < x1 && y >= y0 && y < y1) *g.state.cellByIndex(cx, cy) = s;
    }
}

/// Places the robot at world point (x, y); the cell must exist.
inline void placeRobot(exploration::GroundGrid& g, double x, double y)
{
  if (!exploration::cellOf(g.state, Eigen::Vector2d(x, y), g.robot))
    throw std::runtime_error("placeRobot: off the grid");
}

/// The cell containing (x, y) (the test's points are inside the grid).
template <typename T>
exploration::Cell cellAt(const exploration::Grid<T>& g, double x, double y)
{
  exploration::Cell c;
  if (!exploration::cellOf(g, Eigen::Vector2d(x, y), c))
    throw std::runtime_error("cellAt: off grid");
  return c;
}

template <typename T>
T at(const exploration::Grid<T>& g, double x, double y)
{
  const exploration::Cell c = cellAt(g, x, y);
  return *g.cellByIndex(c.cx, c.cy);
}

}  // namespace voxplore::test
