/* voxplore — separable squared EDT: the columns by two sweeps (Meijster et
 * al. 2000), the rows by lower envelopes (Felzenszwalb & Huttenlocher 2012). */
#include <voxplore/common/distance_transform.h>

#include <algorithm>
#include <limits>

namespace voxplore::common
{
namespace
{
/// Scratch buffers of the 1D transform, sized for the longest line.
struct Scratch
{
  std::vector<double> f, d, z;
  std::vector<int> v;
  explicit Scratch(int n) : f(n), d(n), z(n + 1), v(n) {}
};

/// 1D lower envelope of the parabolas (q - p)^2 + f(p): d(q) = min_p ... .
void transform1d(int n, Scratch& s)
{
  const double* f = s.f.data();
  int* v = s.v.data();
  double* z = s.z.data();
  const auto inter = [&](int q, int p)
  { return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p); };
  int k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q)
  {
    double x = inter(q, v[k]);
    while (x <= z[k])
    {
      --k;
      x = inter(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = x;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q)
  {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    s.d[q] = dq * dq + f[v[k]];
  }
}
}  // namespace

void squaredDistanceTransform(std::vector<double>& sq, int width, int height)
{
  // Columns: with sources of value 0 and kEdtFar elsewhere, the 1D
  // transform of a column is the squared distance along it to its nearest
  // source (Meijster et al. 2000, phase 1): two sweeps over whole rows,
  // contiguous in memory, instead of the lower envelope of every column
  // gathered at a stride of a row (the same values: integers, exact in a
  // double, and kEdtFar where a column holds no source).
  const std::size_t w = static_cast<std::size_t>(width);
  for (int y = 1; y < height; ++y)
  {
    const double* above = sq.data() + (y - 1) * w;
    double* row = sq.data() + y * w;
    for (std::size_t x = 0; x < w; ++x)
      row[x] = row[x] == 0.0 ? 0.0 : std::min(above[x] + 1.0, kEdtFar);
  }
  for (int y = height - 2; y >= 0; --y)
  {
    const double* below = sq.data() + (y + 1) * w;
    double* row = sq.data() + y * w;
    for (std::size_t x = 0; x < w; ++x) row[x] = std::min(row[x], below[x] + 1.0);
  }
  Scratch s(width);
  for (int y = 0; y < height; ++y)  // rows, over the columns' squared distances
  {
    double* row = sq.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) s.f[x] = row[x] >= kEdtFar / 2 ? kEdtFar : row[x] * row[x];
    transform1d(width, s);
    for (int x = 0; x < width; ++x) row[x] = s.d[x];
  }
}

}  // namespace voxplore::common
