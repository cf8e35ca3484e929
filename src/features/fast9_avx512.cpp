// FAST-9 corner test and score of one image row, and its non-max suppression, with AVX-512BW: 64 lanes per block, comparisons into mask
// registers (the run lengths advance by a masked add instead of compare + add + and). Same corners and scores
// as fast9_row.inl (every lane depends only on its own pixel and column threshold; the arithmetic below is
// that file's, lane by lane). CMake builds this file with -mavx512f -mavx512bw on x86-64 only; detectFast9
// calls it where the CPU has AVX-512BW (checked at run time) and the row holds at least one block.
#if defined(IRAF_VO_FAST9_AVX512) && defined(__AVX512BW__)

#include <immintrin.h>

#include <cstdint>

namespace iraf_vo {
namespace fast9_avx512 {

namespace {

constexpr int kW = 64;            // lanes per block
constexpr int kArc = 9;           // FAST-9
constexpr int kRing = 16 + kArc;  // circle offsets 16..24 repeat 0..8

inline __m512i at(const uint8_t* p, int off) { return _mm512_loadu_si512(static_cast<const void*>(p + off)); }

// Scores of the lanes (fast9_row.inl scoreLanes): saturated margins of the lane's polarity, the best arc's
// minimum, minus 1.
inline __m512i scoreLanes(const uint8_t* p, const int* off, __m512i v, __mmask64 bright) {
  __m512i d[kRing];
  for (int k = 0; k < kRing; ++k) {
    const __m512i x = at(p, off[k]);
    d[k] = _mm512_mask_blend_epi8(bright, _mm512_subs_epu8(v, x), _mm512_subs_epu8(x, v));
  }
  __m512i m2[kRing - 1], m4[kRing - 3], best = _mm512_setzero_si512();
  for (int k = 0; k < kRing - 1; ++k) m2[k] = _mm512_min_epu8(d[k], d[k + 1]);
  for (int k = 0; k < kRing - 3; ++k) m4[k] = _mm512_min_epu8(m2[k], m2[k + 2]);
  for (int s = 0; s < 16; ++s) best = _mm512_max_epu8(best, _mm512_min_epu8(_mm512_min_epu8(m4[s], m4[s + 4]), d[s + 8]));
  return _mm512_sub_epi8(best, _mm512_set1_epi8(1));
}

// Columns j0 .. j0 + 63; lanes below column `from` were done by an earlier block.
inline __attribute__((always_inline)) void cornerBlock(const uint8_t* row, const int* off, const uint8_t* th, int j0,
                                                       int from, uint8_t* curr, int* pos, int* nc) {
  const uint8_t* p = row + j0;
  const __m512i v = at(p, 0), t = _mm512_loadu_si512(static_cast<const void*>(th + j0));
  const __m512i hi = _mm512_adds_epu8(v, t), lo = _mm512_subs_epu8(v, t);
  const uint64_t fresh = ~((uint64_t{1} << (from - j0)) - 1u);
  // Quick rejection: every arc of 9 holds two consecutive compass points (0, 4, 8, 12).
  const __m512i x0 = at(p, off[0]), x4 = at(p, off[4]), x8 = at(p, off[8]), x12 = at(p, off[12]);
  const __mmask64 b0 = _mm512_cmpgt_epu8_mask(x0, hi), b4 = _mm512_cmpgt_epu8_mask(x4, hi);
  const __mmask64 b8 = _mm512_cmpgt_epu8_mask(x8, hi), b12 = _mm512_cmpgt_epu8_mask(x12, hi);
  const __mmask64 d0 = _mm512_cmplt_epu8_mask(x0, lo), d4 = _mm512_cmplt_epu8_mask(x4, lo);
  const __mmask64 d8 = _mm512_cmplt_epu8_mask(x8, lo), d12 = _mm512_cmplt_epu8_mask(x12, lo);
  const uint64_t maybe = ((b0 & b4) | (b4 & b8) | (b8 & b12) | (b12 & b0) | (d0 & d4) | (d4 & d8) | (d8 & d12) |
                          (d12 & d0)) & fresh;
  if (maybe == 0) return;
  // Longest run of brighter / darker circle pixels per lane.
  const __m512i one = _mm512_set1_epi8(1);
  __m512i run_b = _mm512_setzero_si512(), run_d = run_b, max_b = run_b, max_d = run_b;
#pragma GCC unroll 25
  for (int k = 0; k < kRing; ++k) {
    const __m512i x = at(p, off[k]);
    run_b = _mm512_maskz_add_epi8(_mm512_cmpgt_epu8_mask(x, hi), run_b, one);
    run_d = _mm512_maskz_add_epi8(_mm512_cmplt_epu8_mask(x, lo), run_d, one);
    max_b = _mm512_max_epu8(max_b, run_b);
    max_d = _mm512_max_epu8(max_d, run_d);
  }
  const __m512i arc_minus_1 = _mm512_set1_epi8(kArc - 1);
  const __mmask64 bright = _mm512_cmpgt_epu8_mask(max_b, arc_minus_1);
  uint64_t mask = (bright | _mm512_cmpgt_epu8_mask(max_d, arc_minus_1)) & fresh;
  if (mask == 0) return;
  alignas(64) uint8_t s[kW];
  _mm512_store_si512(static_cast<void*>(s), scoreLanes(p, off, v, bright));
  while (mask) {
    const int k = __builtin_ctzll(mask);
    mask &= mask - 1;
    pos[(*nc)++] = j0 + k;
    curr[j0 + k] = s[k];
  }
}

// 3x3 non-max suppression of columns j0 .. j0 + 63 of score row b (fast9_row.inl nmsBlock): kept iff the score
// is > every neighbour's, neighbours across a wall ignored; lanes below column `from` were done before.
inline __attribute__((always_inline)) void nmsBlock(const uint8_t* a, const uint8_t* b, const uint8_t* c,
                                                    const uint8_t* walls, int j0, int from, int* out, int* n) {
  const __m512i s = at(b, j0);
  const uint64_t fresh = ~((uint64_t{1} << (from - j0)) - 1u);
  uint64_t keep = _mm512_test_epi8_mask(s, s) & fresh;  // corners (score > 0)
  if (keep == 0) return;
  keep &= _mm512_cmpgt_epu8_mask(s, at(a, j0)) & _mm512_cmpgt_epu8_mask(s, at(c, j0));
  uint64_t left = _mm512_cmpgt_epu8_mask(s, at(a, j0 - 1)) & _mm512_cmpgt_epu8_mask(s, at(b, j0 - 1)) &
                  _mm512_cmpgt_epu8_mask(s, at(c, j0 - 1));
  uint64_t right = _mm512_cmpgt_epu8_mask(s, at(a, j0 + 1)) & _mm512_cmpgt_epu8_mask(s, at(b, j0 + 1)) &
                   _mm512_cmpgt_epu8_mask(s, at(c, j0 + 1));
  if (walls) {
    const __m512i w = at(walls, j0);
    left |= _mm512_test_epi8_mask(w, _mm512_set1_epi8(1));
    right |= _mm512_test_epi8_mask(w, _mm512_set1_epi8(2));
  }
  keep &= left & right;
  while (keep) {
    out[(*n)++] = j0 + __builtin_ctzll(keep);
    keep &= keep - 1;
  }
}

}  // namespace

/// fast9_row.inl's rowMaxima for rows with cols - 6 >= 64 (columns [3, cols - 3)); returns -1 without touching
/// anything for narrower rows.
int rowMaxima(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int cols, int* out) {
  const int end = cols - 3;
  if (end - 3 < kW) return -1;
  int n = 0, j = 3;
  for (; j + kW <= end; j += kW) nmsBlock(a, b, c, walls, j, j, out, &n);
  if (j < end) nmsBlock(a, b, c, walls, end - kW, j, out, &n);
  return n;
}

/// fast9_row.inl's rowCorners for rows with cols - 6 >= 64 (columns [3, cols - 3), the last block overlapping
/// the previous one); returns -1 without touching anything for narrower rows.
int rowCorners(const uint8_t* row, const int* off, const uint8_t* th, int cols, uint8_t* curr, int* pos) {
  const int end = cols - 3;
  if (end - 3 < kW) return -1;
  int nc = 0, j = 3;
  for (; j + kW <= end; j += kW) cornerBlock(row, off, th, j, j, curr, pos, &nc);
  if (j < end) cornerBlock(row, off, th, end - kW, j, curr, pos, &nc);
  return nc;
}

}  // namespace fast9_avx512
}  // namespace iraf_vo

#endif
