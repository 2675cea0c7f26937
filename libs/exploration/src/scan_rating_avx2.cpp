/* voxplore — the AVX2 beam walker of the fast scan rating: four beams step
 * together in vector registers. Per step of the four: the branch-free DDA
 * (computeRayKeys' axis rule and arithmetic, in double), the address step,
 * the end test, one gather of the four cells and a compare of their state
 * bits. A lane whose voxel was already counted goes on without a branch;
 * new voxels are counted in place (re-reading the cell, so two lanes on one
 * voxel count it once); everything else (beam end, stop, unfilled block,
 * overflow class) leaves the vector loop and is served by VoxelWindow::visit,
 * after which the lane takes the next beam. Compiled for AVX2 by function
 * attribute and chosen at run time; other CPUs use walkBeamsScalar. */
#include "scan_rating_walk.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define VOXPLORE_AVX2_WALK 1
#endif

namespace voxplore::exploration::detail
{
#ifdef VOXPLORE_AVX2_WALK
namespace
{
/// The four lanes' DDA state, in memory between runs of the vector loop.
struct alignas(32) Lanes
{
  double tx[4], ty[4], tz[4], dx[4], dy[4], dz[4], len[4];
  int64_t addr[4], end[4], ax[4], ay[4], az[4];
};

void loadLane(Lanes& q, int l, const BeamDda& s)
{
  q.tx[l] = s.t_max[0];
  q.ty[l] = s.t_max[1];
  q.tz[l] = s.t_max[2];
  q.dx[l] = s.t_delta[0];
  q.dy[l] = s.t_delta[1];
  q.dz[l] = s.t_delta[2];
  q.len[l] = s.length;
  q.addr[l] = static_cast<int64_t>(s.addr);
  q.end[l] = static_cast<int64_t>(s.end);
  q.ax[l] = s.advance[0];
  q.ay[l] = s.advance[1];
  q.az[l] = s.advance[2];
}

BeamDda laneState(const Lanes& q, int l)
{
  BeamDda s;
  s.t_max[0] = q.tx[l];
  s.t_max[1] = q.ty[l];
  s.t_max[2] = q.tz[l];
  s.t_delta[0] = q.dx[l];
  s.t_delta[1] = q.dy[l];
  s.t_delta[2] = q.dz[l];
  s.length = q.len[l];
  s.addr = static_cast<std::size_t>(q.addr[l]);
  s.end = static_cast<std::size_t>(q.end[l]);
  s.advance[0] = q.ax[l];
  s.advance[1] = q.ay[l];
  s.advance[2] = q.az[l];
  return s;
}

/// vpermd indices that move the 64-bit lanes set in a 4-bit mask to the front.
alignas(32) const int32_t kCompress[16][8] = {
    {0, 0, 0, 0, 0, 0, 0, 0},
    {0, 1, 0, 0, 0, 0, 0, 0},
    {2, 3, 0, 0, 0, 0, 0, 0},
    {0, 1, 2, 3, 0, 0, 0, 0},
    {4, 5, 0, 0, 0, 0, 0, 0},
    {0, 1, 4, 5, 0, 0, 0, 0},
    {2, 3, 4, 5, 0, 0, 0, 0},
    {0, 1, 2, 3, 4, 5, 0, 0},
    {6, 7, 0, 0, 0, 0, 0, 0},
    {0, 1, 6, 7, 0, 0, 0, 0},
    {2, 3, 6, 7, 0, 0, 0, 0},
    {0, 1, 2, 3, 6, 7, 0, 0},
    {4, 5, 6, 7, 0, 0, 0, 0},
    {0, 1, 4, 5, 6, 7, 0, 0},
    {2, 3, 4, 5, 6, 7, 0, 0},
    {0, 1, 2, 3, 4, 5, 6, 7},
};
const unsigned kPopCount[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

/// Addresses of new voxels, counted in batches without branches.
struct Pending
{
  static constexpr unsigned kFlushAt = 60;
  alignas(32) int64_t addr[kFlushAt + 8];
  unsigned n = 0;
  uint64_t inc[512];  ///< per code: 1 voxel (+ 1 << 32 if unknown); 0 past 255 (already counted)
  double entropy[512];

  explicit Pending(const double* class_entropy)
  {
    for (unsigned i = 0; i < 512; i++)
    {
      inc[i] = i < 256 ? 1 : 0;
      entropy[i] = i < 256 ? class_entropy[i] : 0.0;
    }
    inc[0] |= uint64_t(1) << 32;
  }

  /// Counts (voxels low 32 bits, unknown high 32 bits) and gain of the
  /// appended voxels not counted yet, and marks them counted.
  void flush(uint16_t* cells, uint64_t& counts, double& gain)
  {
    for (unsigned i = 0; i < n; i++)
    {
      uint16_t& cell = cells[addr[i]];
      const uint32_t c = cell;
      const uint32_t code = (c & kClassMask) | (c & kVisited) >> 1;  // +256 once counted
      cell = static_cast<uint16_t>(c | kVisited);
      counts += inc[code];
      gain += entropy[code];
    }
    n = 0;
  }
};

/// Serves lane l, which left the vector loop; false when its beam is done
/// and no beam is left for it.
bool serveLane(bool at_end, Lanes& q, int l, BeamFeed& feed, VoxelWindow& w, Tally& tally)
{
  if (at_end)
    w.visit(static_cast<std::size_t>(q.end[l]), tally);
  else if (!w.visit(static_cast<std::size_t>(q.addr[l]), tally))
    return true;  // block filled or overflow voxel counted: the beam goes on
  BeamDda s;
  if (!feed.pop(w, tally, s)) return false;
  loadLane(q, l, s);
  return true;
}

__attribute__((target("avx2"))) void walkAvx2(BeamFeed& feed, VoxelWindow& w, Tally& tally)
{
  BeamDda s[4];
  int started = 0;
  while (started < 4 && feed.pop(w, tally, s[started])) started++;
  if (started < 4)
  {
    for (int i = 0; i < started; i++) finishBeam(s[i], w, tally);
    return;
  }
  Lanes q;
  for (int l = 0; l < 4; l++) loadLane(q, l, s[l]);

  Pending pending(w.entropy());
  uint64_t counts = 0;
  double gain = 0;
  uint16_t* const cells = w.cells();
  const int* const cells32 = reinterpret_cast<const int*>(cells);
  const double* const entropy = w.entropy();
  const uint32_t epoch = w.epochBase() >> kEpochShift;
  // Cell bits 15..8 = epoch | counted | stop.
  const __m128i seen_bits = _mm_set1_epi32(static_cast<int>((epoch << 2) | 2));
  const __m128i new_bits = _mm_set1_epi32(static_cast<int>(epoch << 2));
  const __m128i byte = _mm_set1_epi32(0xFF);
  bool live[4] = {true, true, true, true};
  while (live[0] && live[1] && live[2] && live[3])
  {
    __m256d tx = _mm256_load_pd(q.tx), ty = _mm256_load_pd(q.ty), tz = _mm256_load_pd(q.tz);
    const __m256d dx = _mm256_load_pd(q.dx), dy = _mm256_load_pd(q.dy),
                  dz = _mm256_load_pd(q.dz), len = _mm256_load_pd(q.len);
    __m256i addr = _mm256_load_si256(reinterpret_cast<const __m256i*>(q.addr));
    const __m256i end = _mm256_load_si256(reinterpret_cast<const __m256i*>(q.end));
    const __m256i ax = _mm256_load_si256(reinterpret_cast<const __m256i*>(q.ax));
    const __m256i ay = _mm256_load_si256(reinterpret_cast<const __m256i*>(q.ay));
    const __m256i az = _mm256_load_si256(reinterpret_cast<const __m256i*>(q.az));
    unsigned leave, at_end;
    for (;;)
    {
      // computeRayKeys: x if tx < ty and tx < tz; else y if ty < tz; else z.
      const __m256d x_lt_y = _mm256_cmp_pd(tx, ty, _CMP_LT_OQ);
      const __m256d x_lt_z = _mm256_cmp_pd(tx, tz, _CMP_LT_OQ);
      const __m256d y_lt_z = _mm256_cmp_pd(ty, tz, _CMP_LT_OQ);
      const __m256d mx = _mm256_and_pd(x_lt_y, x_lt_z), my = _mm256_andnot_pd(x_lt_y, y_lt_z);
      const __m256d not_z = _mm256_or_pd(mx, my);
      tx = _mm256_add_pd(tx, _mm256_and_pd(mx, dx));
      ty = _mm256_add_pd(ty, _mm256_and_pd(my, dy));
      tz = _mm256_add_pd(tz, _mm256_andnot_pd(not_z, dz));
      // Rounding may step past the end voxel: computeRayKeys stops when min t > length.
      const __m256d over =
          _mm256_cmp_pd(len, _mm256_min_pd(_mm256_min_pd(tx, ty), tz), _CMP_LT_OQ);
      const __m256i step = _mm256_or_si256(
          _mm256_or_si256(_mm256_and_si256(_mm256_castpd_si256(mx), ax),
                          _mm256_and_si256(_mm256_castpd_si256(my), ay)),
          _mm256_andnot_si256(_mm256_castpd_si256(not_z), az));
      addr = _mm256_add_epi64(addr, step);
      at_end = static_cast<unsigned>(_mm256_movemask_pd(
          _mm256_or_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(addr, end)), over)));
      const __m128i c = _mm256_i64gather_epi32(cells32, addr, 2);  // low 16 bits: the cell
      const __m128i state = _mm_and_si128(_mm_srli_epi32(c, 8), byte);
      const __m128i not_overflow =
          _mm_xor_si128(_mm_cmpeq_epi32(_mm_and_si128(c, byte), byte), _mm_set1_epi32(-1));
      const auto seen = static_cast<unsigned>(
          _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(state, seen_bits))));
      const auto fresh = static_cast<unsigned>(_mm_movemask_ps(
          _mm_castsi128_ps(_mm_and_si128(_mm_cmpeq_epi32(state, new_bits), not_overflow))));
      // New voxels: their addresses are appended (compressed, no branch) and
      // counted in batches; a voxel appended twice is counted once.
      const unsigned count = fresh & ~at_end;
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(pending.addr + pending.n),
                          _mm256_permutevar8x32_epi32(
                              addr, _mm256_load_si256(reinterpret_cast<const __m256i*>(kCompress[count]))));
      pending.n += kPopCount[count];
      if (pending.n > Pending::kFlushAt) pending.flush(cells, counts, gain);
      leave = at_end | (0xFu & ~(seen | fresh));
      if (leave) break;
    }
    _mm256_store_pd(q.tx, tx);
    _mm256_store_pd(q.ty, ty);
    _mm256_store_pd(q.tz, tz);
    _mm256_store_si256(reinterpret_cast<__m256i*>(q.addr), addr);
    for (int l = 0; l < 4; l++)
      if ((leave >> l) & 1) live[l] = serveLane((at_end >> l) & 1, q, l, feed, w, tally);
  }
  pending.flush(cells, counts, gain);
  // No beam left for some lane: the others finish theirs one at a time.
  for (int l = 0; l < 4; l++)
  {
    if (!live[l]) continue;
    BeamDda st = laneState(q, l);
    finishBeam(st, w, tally);
  }
  tally.voxels += counts & 0xFFFFFFFFu;
  tally.unknown += counts >> 32;
  tally.gain += gain;
}
}  // namespace
#endif

bool walkBeamsAvx2(BeamFeed& feed, VoxelWindow& w, Tally& tally)
{
#ifdef VOXPLORE_AVX2_WALK
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (!has_avx2) return false;
  walkAvx2(feed, w, tally);
  return true;
#else
  (void)feed;
  (void)w;
  (void)tally;
  return false;
#endif
}

}  // namespace voxplore::exploration::detail
