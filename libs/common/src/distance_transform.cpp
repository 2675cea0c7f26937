/* voxplore — separable squared EDT (Felzenszwalb & Huttenlocher 2012). */
#include <voxplore/common/distance_transform.h>

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
  Scratch s(width > height ? width : height);
  for (int x = 0; x < width; ++x)  // columns
  {
    for (int y = 0; y < height; ++y) s.f[y] = sq[x + y * width];
    transform1d(height, s);
    for (int y = 0; y < height; ++y) sq[x + y * width] = s.d[y];
  }
  for (int y = 0; y < height; ++y)  // rows
  {
    double* row = sq.data() + static_cast<std::size_t>(y) * width;
    for (int x = 0; x < width; ++x) s.f[x] = row[x];
    transform1d(width, s);
    for (int x = 0; x < width; ++x) row[x] = s.d[x];
  }
}

}  // namespace voxplore::common
