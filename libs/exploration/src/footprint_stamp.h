/* voxplore — the stamp of the robot's rectangle over yaw bins: which bins an
 * obstacle cell at each offset blocks, and stamping it round obstacle cells
 * (issue 13). Internal to libs/exploration (footprint_space.cpp, footprint_reach.cpp). */
#pragma once

#include <voxplore/exploration/footprint.h>

#include <cstdint>
#include <vector>

namespace voxplore::exploration::detail
{
/// One entry of the stamp: the bins an obstacle cell at offset (dx, dy)
/// cells from the robot's cell blocks.
struct StampEntry
{
  int dx, dy;
  YawMask bins;
};

/// The bins for which an obstacle square (side res x square_share) centred
/// at offset (dx, dy) * res from the robot centre touches the rectangle (half
/// sides a, b) grown by margin, at some yaw of the bin. For the bin's yaws
/// the square is bounded, along each of the rectangle's axes, by its support
/// h (|cos| + |sin|) at the bin's worst yaw, so the test is the centre point
/// against the rectangle grown by margin + that support: exact on the faces,
/// conservative only round the corners. The blocked yaws of a point at
/// (rho, alpha) are theta = alpha -+ phi with acos(a'/rho) <= phi <= asin(b'/rho).
/// With bin_span < 1 only the yaws within bin_span times half the bin's
/// width of its centre count (0: the centre yaw alone). With lateral_m the
/// rectangle's centre is moved that far along the +Y axis of each bin's
/// centre yaw (sideways to the way the robot drives in that bin).
std::vector<StampEntry> makeStamp(double a, double b, double margin, double res, int bins,
                                  double square_share, double bin_span = 1.0,
                                  double lateral_m = 0.0);

/// The cells of `src` with an 8-neighbour outside `src` (or on the grid
/// border): a rectangle whose centre lies outside src and that overlaps a
/// src square overlaps such a border square.
std::vector<int> borderCells(const std::vector<uint8_t>& src, int nx, int ny);

/// A stamp (or two, at two margins) as rows of robot cells: row `dy` covers
/// obstacle offsets dx in [dx_max - len + 1, dx_max]; element k is the
/// offset dx_max - k, so that, round an obstacle cell at x, element k blocks
/// the robot cell x - dx_max + k (increasing: one vectorisable OR per row).
struct StampRows
{
  struct Row
  {
    int dy = 0, dx_max = 0;
    std::vector<YawMask> a, b;  ///< the first and second stamp's bins (b empty: one stamp)
  };
  std::vector<Row> rows;
};

/// Rows of `first`, and of `second` when given (then each row holds both).
/// With `pack` (both stamps of at most 32 bins) the second stamp's bins go
/// into the upper 32 bits of `a` and `b` stays empty: one array to OR into,
/// half the memory traffic of two.
StampRows toRows(const std::vector<StampEntry>& first, const std::vector<StampEntry>* second,
                 bool pack = false);

/// ORs the stamp's rows into `a` (and their second masks into `b`, when the
/// rows hold two and b is not null) round every cell of `borders`; a and b
/// are row-major nx x ny layers.
void stampAt(YawMask* a, YawMask* b, const std::vector<int>& borders,
             int nx, int ny, const StampRows& stamp);

/// The bins of `bins` that the stamp blocks at robot cell (cx, cy): those of
/// its entries whose obstacle cell (cx, cy) + (dx, dy) is set in `obstacle`
/// (what stampAt gives that one cell, tested there alone).
YawMask stampBlocks(const std::vector<StampEntry>& stamp, const std::vector<uint8_t>& obstacle,
                    int nx, int ny, int cx, int cy, YawMask bins);

/// Does the rectangle (half sides a, b) centred at robot cell (cx, cy) at
/// exactly `yaw` overlap a square of `obstacle` (separating axes, each cell
/// a full square of side res)?
bool rectangleOverlaps(const std::vector<uint8_t>& obstacle, int nx, int ny, double res, int cx,
                       int cy, double yaw, double a, double b);

}  // namespace voxplore::exploration::detail
