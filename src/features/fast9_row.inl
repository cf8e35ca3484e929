// FAST-9 corner test and score of one image row, written once with OpenCV's universal intrinsics and compiled
// twice: fast9.cpp (baseline, 16 lanes) and fast9_avx2.cpp (AVX2, 32 lanes then 16). Every lane's result
// depends only on its own pixel and column threshold, so both builds give the same corners and scores.
// Include after <opencv2/core/hal/intrin.hpp>, inside the TU's own namespace. No std:: templates here (an
// AVX2-compiled copy of a shared inline function could be picked by the linker for the baseline code).

namespace {

// The 16 circle pixels (dx, dy) in order around the circle; entries 16..24 repeat 0..8 so every arc of 9
// contiguous pixels is a plain window.
constexpr int kArc = 9;
constexpr int kRing = 16 + kArc;  // 25

inline int imin(int a, int b) { return a < b ? a : b; }
inline int imax(int a, int b) { return a > b ? a : b; }

// Score of one pixel: max over the 16 arcs of (min over the arc of the brighter-than / darker-than margin) - 1,
// for both polarities = the largest t for which the FAST test (strict >) still holds.
int scalarScore(const uint8_t* p, const int* off) {
  const int v = p[0];
  int best = 0;
  for (int s = 0; s < 16; ++s) {
    int bright = 255, dark = 255;
    for (int k = s; k < s + kArc; ++k) {
      const int x = p[off[k]];
      bright = imin(bright, x - v);
      dark = imin(dark, v - x);
    }
    best = imax(best, imax(bright, dark));
  }
  return best - 1;
}

bool scalarIsCorner(const uint8_t* p, const int* off, int t) {
  const int v = p[0];
  int run_b = 0, run_d = 0;
  for (int k = 0; k < kRing; ++k) {
    const int x = p[off[k]];
    run_b = x > v + t ? run_b + 1 : 0;
    run_d = x < v - t ? run_d + 1 : 0;
    if (run_b >= kArc || run_d >= kArc) return true;
  }
  return false;
}

#if CV_SIMD128
template <class V>
struct Lanes;
template <>
struct Lanes<cv::v_uint8x16> {
  static cv::v_uint8x16 load(const uint8_t* p) { return cv::v_load(p); }
  static cv::v_uint8x16 all(uint8_t x) { return cv::v_setall_u8(x); }
};
#if CV_SIMD256
template <>
struct Lanes<cv::v_uint8x32> {
  static cv::v_uint8x32 load(const uint8_t* p) { return cv::v256_load(p); }
  static cv::v_uint8x32 all(uint8_t x) { return cv::v256_setall_u8(x); }
};
#endif

// Scores of the lanes at once. A corner has one polarity (9 brighter and 9 darker pixels do not fit on 16),
// and every arc of the other polarity holds a pixel of this one, where its saturated margin is 0: so one pass
// over the lane's own polarity's margins (bright_lanes selects) gives the score. Lanes that are not corners
// get a meaningless value that the caller ignores.
template <class V>
V scoreLanes(const uint8_t* p, const int* off, const V& v, const V& bright_lanes) {
  V d[kRing];
  for (int k = 0; k < kRing; ++k) {
    const V x = Lanes<V>::load(p + off[k]);
    d[k] = cv::v_select(bright_lanes, x - v, v - x);  // saturating margins
  }
  // Window minima of 2, 4, 8, then 9 elements; the best arc.
  V m2[kRing - 1], m4[kRing - 3], best = Lanes<V>::all(0);
  for (int k = 0; k < kRing - 1; ++k) m2[k] = cv::v_min(d[k], d[k + 1]);
  for (int k = 0; k < kRing - 3; ++k) m4[k] = cv::v_min(m2[k], m2[k + 2]);
  for (int s = 0; s < 16; ++s) best = cv::v_max(best, cv::v_min(cv::v_min(m4[s], m4[s + 4]), d[s + 8]));
  return best - Lanes<V>::all(1);
}

// The lanes of columns j0 .. j0 + nlanes - 1 of `row`; lanes below column `from` were done by an earlier block.
// Corner columns are appended to pos[*nc ...], their scores written to curr[column].
template <class V>
inline __attribute__((always_inline)) void cornerBlock(const uint8_t* row, const int* off, const uint8_t* th, int j0, int from, uint8_t* curr, int* pos,
                 int* nc) {
  const uint8_t* p = row + j0;
  const V v = Lanes<V>::load(p), t = Lanes<V>::load(th + j0);
  const V hi = v + t, lo = v - t;  // saturating, as the strict integer test needs
  // Quick rejection: every arc of 9 holds two consecutive compass points (0, 4, 8, 12).
  const V x0 = Lanes<V>::load(p + off[0]), x4 = Lanes<V>::load(p + off[4]);
  const V x8 = Lanes<V>::load(p + off[8]), x12 = Lanes<V>::load(p + off[12]);
  const V b0 = x0 > hi, b4 = x4 > hi, b8 = x8 > hi, b12 = x12 > hi;
  const V d0 = x0 < lo, d4 = x4 < lo, d8 = x8 < lo, d12 = x12 < lo;
  const V maybe = (b0 & b4) | (b4 & b8) | (b8 & b12) | (b12 & b0) | (d0 & d4) | (d4 & d8) | (d8 & d12) | (d12 & d0);
  if (!cv::v_check_any(maybe)) return;
  // Longest run of brighter / darker circle pixels per lane.
  const V one = Lanes<V>::all(1), arc_minus_1 = Lanes<V>::all(kArc - 1);
  V run_b = Lanes<V>::all(0), run_d = run_b, max_b = run_b, max_d = run_b;
#pragma GCC unroll 25
  for (int k = 0; k < kRing; ++k) {
    const V x = Lanes<V>::load(p + off[k]);
    run_b = (run_b + one) & (x > hi);
    run_d = (run_d + one) & (x < lo);
    max_b = cv::v_max(max_b, run_b);
    max_d = cv::v_max(max_d, run_d);
  }
  const V bright = max_b > arc_minus_1;
  uint32_t mask = static_cast<uint32_t>(cv::v_signmask(bright | (max_d > arc_minus_1))) & ~((1u << (from - j0)) - 1u);
  if (mask == 0) return;
  uint8_t s[V::nlanes];
  cv::v_store(s, scoreLanes(p, off, v, bright));
  while (mask) {
    const int k = __builtin_ctz(mask);
    mask &= mask - 1;
    pos[(*nc)++] = j0 + k;
    curr[j0 + k] = s[k];
  }
}

// Blocks of V over columns [*j, end); the last partial block overlaps the previous one.
template <class V>
void cornerBlocks(const uint8_t* row, const int* off, const uint8_t* th, int* j, int end, uint8_t* curr, int* pos,
                  int* nc) {
  constexpr int W = V::nlanes;
  if (end - 3 < W) return;  // narrower than one block (the row starts at column 3)
  for (; *j + W <= end; *j += W) cornerBlock<V>(row, off, th, *j, *j, curr, pos, nc);
  if (*j < end) {
    cornerBlock<V>(row, off, th, end - W, *j, curr, pos, nc);
    *j = end;
  }
}

// 3x3 non-max suppression of the lanes of columns j0 .. j0 + nlanes - 1 of score row b (a above, c below;
// non-corners score 0): kept iff the score is > every neighbour's, neighbours across a wall ignored.
template <class V>
inline __attribute__((always_inline)) void nmsBlock(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int j0, int from, int* out,
              int* n) {
  const V s = Lanes<V>::load(b + j0);
  if (!cv::v_check_any(s > Lanes<V>::all(0))) return;  // no corner in these columns
  V left = (s > Lanes<V>::load(a + j0 - 1)) & (s > Lanes<V>::load(b + j0 - 1)) & (s > Lanes<V>::load(c + j0 - 1));
  V right = (s > Lanes<V>::load(a + j0 + 1)) & (s > Lanes<V>::load(b + j0 + 1)) & (s > Lanes<V>::load(c + j0 + 1));
  if (walls) {
    const V w = Lanes<V>::load(walls + j0), one = Lanes<V>::all(1), two = Lanes<V>::all(2);
    left = left | ((w & one) == one);
    right = right | ((w & two) == two);
  }
  const V keep = (s > Lanes<V>::load(a + j0)) & (s > Lanes<V>::load(c + j0)) & left & right;
  uint32_t mask = static_cast<uint32_t>(cv::v_signmask(keep)) & ~((1u << (from - j0)) - 1u);
  while (mask) {
    out[(*n)++] = j0 + __builtin_ctz(mask);
    mask &= mask - 1;
  }
}

template <class V>
void nmsBlocks(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int* j, int end, int* out,
               int* n) {
  constexpr int W = V::nlanes;
  if (end - 3 < W) return;
  for (; *j + W <= end; *j += W) nmsBlock<V>(a, b, c, walls, *j, *j, out, n);
  if (*j < end) {
    nmsBlock<V>(a, b, c, walls, end - W, *j, out, n);
    *j = end;
  }
}
#endif

}  // namespace

/// Non-max suppression of score row b (a: the row above, c: below; 0 = no corner) over columns [3, cols - 3):
/// the columns whose score is > that of each 8-neighbour (walls as in detectFast9; may be null), ascending,
/// into out; returns the count.
int rowMaxima(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int cols, int* out) {
  int n = 0, j = 3;
  const int end = cols - 3;
#if CV_SIMD256
  nmsBlocks<cv::v_uint8x32>(a, b, c, walls, &j, end, out, &n);
#endif
#if CV_SIMD128
  nmsBlocks<cv::v_uint8x16>(a, b, c, walls, &j, end, out, &n);
#endif
  for (; j < end; ++j) {
    const uint8_t s = b[j];
    if (!(s > a[j] && s > c[j])) continue;
    const int w = walls ? walls[j] : 0;
    if (((w & 1) || (s > a[j - 1] && s > b[j - 1] && s > c[j - 1])) &&
        ((w & 2) || (s > a[j + 1] && s > b[j + 1] && s > c[j + 1])))
      out[n++] = j;
  }
  return n;
}

/// FAST-9 corners of columns [3, cols - 3) of `row` (off: the 25 circle offsets, th: per-column thresholds):
/// appends their columns to pos (ascending) and writes their scores to curr; returns the count.
int rowCorners(const uint8_t* row, const int* off, const uint8_t* th, int cols, uint8_t* curr, int* pos) {
  int nc = 0, j = 3;
  const int end = cols - 3;
#if CV_SIMD256
  cornerBlocks<cv::v_uint8x32>(row, off, th, &j, end, curr, pos, &nc);
#endif
#if CV_SIMD128
  cornerBlocks<cv::v_uint8x16>(row, off, th, &j, end, curr, pos, &nc);
#endif
  for (; j < end; ++j) {
    if (!scalarIsCorner(row + j, off, th[j])) continue;
    pos[nc++] = j;
    curr[j] = static_cast<uint8_t>(scalarScore(row + j, off));
  }
  return nc;
}
