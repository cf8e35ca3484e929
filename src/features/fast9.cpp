#include "iraf_vo/features/fast9.h"

#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cstring>

namespace iraf_vo {

namespace {

// The 16 circle pixels (dx, dy) in order around the circle; entries 16..24 repeat 0..8 so every arc of 9
// contiguous pixels is a plain window.
constexpr int kCircle[16][2] = {{0, 3},  {1, 3},   {2, 2},   {3, 1},   {3, 0},  {3, -1}, {2, -2}, {1, -3},
                                {0, -3}, {-1, -3}, {-2, -2}, {-3, -1}, {-3, 0}, {-3, 1}, {-2, 2}, {-1, 3}};
constexpr int kArc = 9;
constexpr int kRing = 16 + kArc;  // 25

// Score of one pixel: max over the 16 arcs of (min over the arc of the brighter-than / darker-than margin) - 1,
// for both polarities = the largest t for which the FAST test (strict >) still holds.
int scalarScore(const uint8_t* p, const int* off) {
  const int v = p[0];
  int best = 0;
  for (int s = 0; s < 16; ++s) {
    int bright = 255, dark = 255;
    for (int k = s; k < s + kArc; ++k) {
      const int x = p[off[k]];
      bright = std::min(bright, x - v);
      dark = std::min(dark, v - x);
    }
    best = std::max(best, std::max(bright, dark));
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
// Scores of 16 adjacent pixels at once. A corner has one polarity (9 brighter and 9 darker pixels do not fit on
// 16), and every arc of the other polarity holds a pixel of this one, where its saturated margin is 0: so one
// pass over the lane's own polarity's margins (bright_lanes selects) gives the score. Lanes that are not
// corners get a meaningless value that the caller ignores.
cv::v_uint8x16 scoreLanes(const uint8_t* p, const int* off, const cv::v_uint8x16& v, const cv::v_uint8x16& bright_lanes) {
  cv::v_uint8x16 d[kRing];
  for (int k = 0; k < kRing; ++k) {
    const cv::v_uint8x16 x = cv::v_load(p + off[k]);
    d[k] = cv::v_select(bright_lanes, x - v, v - x);  // saturating margins
  }
  // Window minima of 2, 4, 8, then 9 elements; the best arc.
  cv::v_uint8x16 m2[kRing - 1], m4[kRing - 3], best = cv::v_setzero_u8();
  for (int k = 0; k < kRing - 1; ++k) m2[k] = cv::v_min(d[k], d[k + 1]);
  for (int k = 0; k < kRing - 3; ++k) m4[k] = cv::v_min(m2[k], m2[k + 2]);
  for (int s = 0; s < 16; ++s) best = cv::v_max(best, cv::v_min(cv::v_min(m4[s], m4[s + 4]), d[s + 8]));
  return best - cv::v_setall_u8(1);
}
#endif

}  // namespace

void detectFast9(const cv::Mat& img, const uint8_t* th, std::vector<cv::KeyPoint>* keypoints, Fast9Buffers* b,
                 const uint8_t* walls) {
  CV_Assert(img.type() == CV_8UC1);
  keypoints->clear();
  const int rows = img.rows, cols = img.cols;
  if (rows < 7 || cols < 7) return;
  int off[kRing];
  const int step = static_cast<int>(img.step1());
  for (int k = 0; k < 16; ++k) off[k] = kCircle[k][0] + kCircle[k][1] * step;
  for (int k = 16; k < kRing; ++k) off[k] = off[k - 16];
  int n_corners[3] = {0, 0, 0};
  for (int r = 0; r < 3; ++r) {
    b->score[r].assign(cols, 0);
    b->corners[r].resize(cols);
  }
  for (int i = 3; i < rows - 2; ++i) {
    uint8_t* curr = b->score[i % 3].data();
    int* pos = b->corners[i % 3].data();
    std::memset(curr, 0, cols);
    int nc = 0;
    if (i < rows - 3) {
      const uint8_t* row = img.ptr<uint8_t>(i);
      int j = 3;
#if CV_SIMD128
      const cv::v_uint8x16 one = cv::v_setall_u8(1), arc_minus_1 = cv::v_setall_u8(kArc - 1);
      // 16 pixels from column j0; lanes below column `from` were done by the previous block.
      auto block = [&](int j0, int from) {
        const uint8_t* p = row + j0;
        const cv::v_uint8x16 v = cv::v_load(p), t = cv::v_load(th + j0);
        const cv::v_uint8x16 hi = v + t, lo = v - t;  // saturating, as the strict integer test needs
        // Quick rejection: every arc of 9 holds two consecutive compass points (0, 4, 8, 12).
        const cv::v_uint8x16 x0 = cv::v_load(p + off[0]), x4 = cv::v_load(p + off[4]);
        const cv::v_uint8x16 x8 = cv::v_load(p + off[8]), x12 = cv::v_load(p + off[12]);
        const cv::v_uint8x16 b0 = x0 > hi, b4 = x4 > hi, b8 = x8 > hi, b12 = x12 > hi;
        const cv::v_uint8x16 d0 = x0 < lo, d4 = x4 < lo, d8 = x8 < lo, d12 = x12 < lo;
        const cv::v_uint8x16 maybe = (b0 & b4) | (b4 & b8) | (b8 & b12) | (b12 & b0) | (d0 & d4) | (d4 & d8) |
                                     (d8 & d12) | (d12 & d0);
        if (!cv::v_check_any(maybe)) return;
        // Longest run of brighter / darker circle pixels per lane.
        cv::v_uint8x16 run_b = cv::v_setzero_u8(), run_d = run_b, max_b = run_b, max_d = run_b;
        for (int k = 0; k < kRing; ++k) {
          const cv::v_uint8x16 x = cv::v_load(p + off[k]);
          run_b = (run_b + one) & (x > hi);
          run_d = (run_d + one) & (x < lo);
          max_b = cv::v_max(max_b, run_b);
          max_d = cv::v_max(max_d, run_d);
        }
        const cv::v_uint8x16 bright = max_b > arc_minus_1;
        int mask = cv::v_signmask(bright | (max_d > arc_minus_1)) & ~((1 << (from - j0)) - 1);
        if (mask == 0) return;
        uint8_t s[16];
        cv::v_store(s, scoreLanes(p, off, v, bright));
        while (mask) {
          const int k = __builtin_ctz(mask);
          mask &= mask - 1;
          pos[nc++] = j0 + k;
          curr[j0 + k] = s[k];
        }
      };
      for (; j + 16 <= cols - 3; j += 16) block(j, j);
      if (j < cols - 3 && cols - 3 - 16 >= 3) {  // the tail: one block ending at the last column
        block(cols - 3 - 16, j);
        j = cols - 3;
      }
#endif
      for (; j < cols - 3; ++j) {
        if (!scalarIsCorner(row + j, off, th[j])) continue;
        pos[nc++] = j;
        curr[j] = static_cast<uint8_t>(scalarScore(row + j, off));
      }
    }
    n_corners[i % 3] = nc;
    if (i == 3) continue;
    // Non-max suppression of row i - 1 against rows i - 2 .. i (non-corners have score 0).
    const uint8_t* prev = b->score[(i - 1) % 3].data();
    const uint8_t* pprev = b->score[(i - 2) % 3].data();
    const int* ppos = b->corners[(i - 1) % 3].data();
    for (int k = 0; k < n_corners[(i - 1) % 3]; ++k) {
      const int j = ppos[k];
      const uint8_t s = prev[j];
      if (!(s > pprev[j] && s > curr[j])) continue;
      const int w = walls ? walls[j] : 0;
      if (((w & kWallLeft) || (s > prev[j - 1] && s > pprev[j - 1] && s > curr[j - 1])) &&
          ((w & kWallRight) || (s > prev[j + 1] && s > pprev[j + 1] && s > curr[j + 1])))
        keypoints->emplace_back(static_cast<float>(j), static_cast<float>(i - 1), 7.f, -1.f, static_cast<float>(s));
    }
  }
}

}  // namespace iraf_vo
