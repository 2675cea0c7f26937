/* voxplore — the AVX2 beam walker of the fast scan rating: four beams step
 * together, their DDA (computeRayKeys' axis rule and arithmetic, in double)
 * and window addresses in vector registers. Each lane's cell then goes
 * through a small table, without branches: what it adds to the counts and
 * the gain, the bit to set once counted, and whether the lane must leave
 * the loop. The loop makes no call and branches only to leave, so the loads
 * of many steps are in flight at once; a data-dependent branch per voxel
 * ("new?") measured ~1.5x slower. Beam ends, stops, unfilled blocks and
 * overflow classes are served outside the loop by VoxelWindow::visit, then
 * the lane takes the next beam. Compiled for AVX2 by function attribute and
 * chosen at run time; elsewhere walkBeamsScalar does the same work. */
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

/// What a cell adds when a lane steps on it, by its bits 9..0 (counted |
/// stop | class), or kBad for a cell of an unfilled block or a lane at its end.
struct CellTable
{
  static constexpr uint32_t kBad = 1024;
  uint64_t inc[kBad + 1];   ///< counted voxels (low 32 bits) and unknown ones (high 32 bits)
  double gain[kBad + 1];    ///< entropy
  uint16_t mark[kBad + 1];  ///< bits to set in the cell: kVisited when counted now
  uint8_t leave[kBad + 1];  ///< 1: the lane leaves the loop to be served
  uint32_t classes = 0;     ///< classes whose entries are set (more appear as blocks fill)

  explicit CellTable(const VoxelWindow& w)
  {
    for (uint32_t code = 0; code <= kBad; code++) set(code, w);
    classes = w.classCount();
  }

  void set(uint32_t code, const VoxelWindow& w)
  {
    const uint32_t cls = code & kClassMask;
    const bool counted = code & kVisited, stop = code & kStop;
    // Overflow classes take their entropy from the tree: served, like unfilled cells.
    const bool count_now = code < kBad && !counted && cls != kOverflow && cls <= w.classCount();
    inc[code] = count_now ? 1 | (uint64_t(cls == 0) << 32) : 0;
    gain[code] = count_now ? w.entropy()[cls] : 0.0;
    mark[code] = count_now ? static_cast<uint16_t>(kVisited) : 0;
    leave[code] = code == kBad || stop || (!counted && !count_now) ? 1 : 0;
  }

  /// Sets the entries of the classes interned since the last call.
  void update(const VoxelWindow& w)
  {
    for (uint32_t cls = classes + 1; cls <= w.classCount(); cls++)
      for (uint32_t bits : {0u, kStop, kVisited, kVisited | kStop}) set(cls | bits, w);
    classes = w.classCount();
  }
};

/// Serves lane l, which left the loop: at its end, or on a stop, an unfilled
/// block or an overflow class; false when its beam is done and no beam is
/// left for it.
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

/// kLog: append each voxel counted in the loop to the window's log (rateScans).
template <bool kLog>
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

  CellTable table(w);
  uint64_t counts = 0;
  double gain[4] = {0, 0, 0, 0};  // one chain of adds per lane
  uint16_t* const cells = w.cells();
  const uint32_t epoch = w.epochBase() >> kEpochShift;
  [[maybe_unused]] uint32_t* const log = w.countedLog();
  [[maybe_unused]] std::size_t logged = w.countedCount();
  bool live[4] = {true, true, true, true};
  while (live[0] && live[1] && live[2] && live[3])
  {
    __m256d tx = _mm256_load_pd(q.tx), ty = _mm256_load_pd(q.ty), tz = _mm256_load_pd(q.tz);
    const __m256d dx = _mm256_load_pd(q.dx), dy = _mm256_load_pd(q.dy), dz = _mm256_load_pd(q.dz),
                  len = _mm256_load_pd(q.len);
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
      const __m256i step =
          _mm256_or_si256(_mm256_or_si256(_mm256_and_si256(_mm256_castpd_si256(mx), ax),
                                          _mm256_and_si256(_mm256_castpd_si256(my), ay)),
                          _mm256_andnot_si256(_mm256_castpd_si256(not_z), az));
      addr = _mm256_add_epi64(addr, step);
      // Rounding may step past the end voxel: computeRayKeys stops when min t > length.
      const __m256d over = _mm256_cmp_pd(len, _mm256_min_pd(_mm256_min_pd(tx, ty), tz), _CMP_LT_OQ);
      at_end = static_cast<unsigned>(_mm256_movemask_pd(
          _mm256_or_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(addr, end)), over)));
      alignas(32) int64_t at[4];
      _mm256_store_si256(reinterpret_cast<__m256i*>(at), addr);
      // Per lane, branch-free: the cell's table entry says what it adds and
      // whether the lane must leave (a lane stepping on a voxel another lane
      // just counted sees it counted).
      leave = 0;
      for (int l = 0; l < 4; l++)
      {
        uint16_t& cell = cells[at[l]];
        const uint32_t c = cell;
        const bool bad = ((c >> kEpochShift) != epoch) | ((at_end >> l) & 1u);
        const uint32_t code = bad ? CellTable::kBad : (c & (CellTable::kBad - 1));
        const uint16_t mark = table.mark[code];
        cell = static_cast<uint16_t>(c | mark);
        if constexpr (kLog)
        {
          // Written always, kept when counted: no branch.
          log[logged] = static_cast<uint32_t>(at[l]);
          logged += mark >> 9;
          static_assert(kVisited == 1u << 9, "the mark is kVisited or 0");
        }
        counts += table.inc[code];
        gain[l] += table.gain[code];
        leave |= static_cast<unsigned>(table.leave[code]) << l;
      }
      if (leave) break;
    }
    _mm256_store_pd(q.tx, tx);
    _mm256_store_pd(q.ty, ty);
    _mm256_store_pd(q.tz, tz);
    _mm256_store_si256(reinterpret_cast<__m256i*>(q.addr), addr);
    if constexpr (kLog) w.setCountedCount(logged);
    for (int l = 0; l < 4; l++)
      if ((leave >> l) & 1) live[l] = serveLane((at_end >> l) & 1, q, l, feed, w, tally);
    if constexpr (kLog) logged = w.countedCount();
    if (w.classCount() != table.classes) table.update(w);
  }
  // No beam left for some lane: the others finish theirs one at a time.
  for (int l = 0; l < 4; l++)
  {
    if (!live[l]) continue;
    BeamDda st = laneState(q, l);
    finishBeam(st, w, tally);
  }
  tally.voxels += counts & 0xFFFFFFFFu;
  tally.unknown += counts >> 32;
  tally.gain += (gain[0] + gain[1]) + (gain[2] + gain[3]);
}
}  // namespace
#endif

bool walkBeamsAvx2(BeamFeed& feed, VoxelWindow& w, Tally& tally)
{
#ifdef VOXPLORE_AVX2_WALK
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (!has_avx2) return false;
  if (w.countedLog())
    walkAvx2<true>(feed, w, tally);
  else
    walkAvx2<false>(feed, w, tally);
  return true;
#else
  (void)feed;
  (void)w;
  (void)tally;
  return false;
#endif
}

}  // namespace voxplore::exploration::detail
