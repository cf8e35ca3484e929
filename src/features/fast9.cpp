#include "iraf_vo/features/fast9.h"

#include <opencv2/core/hal/intrin.hpp>

#include <cstring>

namespace iraf_vo {

namespace fast9_baseline {
#include "fast9_row.inl"
}  // namespace fast9_baseline

#if defined(IRAF_VO_FAST9_AVX2)
namespace fast9_avx2 {
int rowCorners(const uint8_t* row, const int* off, const uint8_t* th, int cols, uint8_t* curr, int* pos);
int rowMaxima(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int cols, int* out);
}  // namespace fast9_avx2
#endif
#if defined(IRAF_VO_FAST9_AVX512)
namespace fast9_avx512 {
int rowCorners(const uint8_t* row, const int* off, const uint8_t* th, int cols, uint8_t* curr, int* pos);
int rowMaxima(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int cols, int* out);
}  // namespace fast9_avx512
#endif

namespace {

constexpr int kCircle[16][2] = {{0, 3},  {1, 3},   {2, 2},   {3, 1},   {3, 0},  {3, -1}, {2, -2}, {1, -3},
                                {0, -3}, {-1, -3}, {-2, -2}, {-3, -1}, {-3, 0}, {-3, 1}, {-2, 2}, {-1, 3}};
constexpr int kRingSize = 25;  // 16 + 9: every arc of 9 is a plain window
constexpr int kRows = 4;       // score rows kept (Fast9Buffers)

struct RowKernels {
  int (*corners)(const uint8_t*, const int*, const uint8_t*, int, uint8_t*, int*);
  int (*maxima)(const uint8_t*, const uint8_t*, const uint8_t*, const uint8_t*, int, int*);
};

#if defined(IRAF_VO_FAST9_AVX2) && defined(IRAF_VO_FAST9_AVX512)
// AVX-512BW corners and maxima (64 lanes) on rows of >= 64 detection columns, AVX2 on narrower ones (cell retries).
int rowCornersAvx512(const uint8_t* row, const int* off, const uint8_t* th, int cols, uint8_t* curr, int* pos) {
  const int n = fast9_avx512::rowCorners(row, off, th, cols, curr, pos);
  return n >= 0 ? n : fast9_avx2::rowCorners(row, off, th, cols, curr, pos);
}
int rowMaximaAvx512(const uint8_t* a, const uint8_t* b, const uint8_t* c, const uint8_t* walls, int cols, int* out) {
  const int n = fast9_avx512::rowMaxima(a, b, c, walls, cols, out);
  return n >= 0 ? n : fast9_avx2::rowMaxima(a, b, c, walls, cols, out);
}
#endif

// The row kernels for this CPU: AVX-512BW corners (64 lanes) where allowed and available, else AVX2 (32 lanes)
// where available, else the baseline build (16 lanes). Same corners and scores either way.
RowKernels pickRowKernels(bool avx2_allowed, bool avx512_allowed) {
#if defined(IRAF_VO_FAST9_AVX2)
#if defined(IRAF_VO_FAST9_AVX512)
  if (avx2_allowed && avx512_allowed && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512bw"))
    return {rowCornersAvx512, rowMaximaAvx512};
#endif
  if (avx2_allowed && __builtin_cpu_supports("avx2")) return {fast9_avx2::rowCorners, fast9_avx2::rowMaxima};
#endif
  (void)avx2_allowed;
  (void)avx512_allowed;
  return {fast9_baseline::rowCorners, fast9_baseline::rowMaxima};
}

bool g_avx512_allowed = true;
RowKernels g_kernels = pickRowKernels(true, true);

}  // namespace

bool fast9UseAvx2(bool allowed) {
  g_kernels = pickRowKernels(allowed, g_avx512_allowed);
  return g_kernels.corners != fast9_baseline::rowCorners;
}

bool fast9UseAvx512(bool allowed) {
  g_avx512_allowed = allowed;
  g_kernels = pickRowKernels(true, allowed);
#if defined(IRAF_VO_FAST9_AVX2) && defined(IRAF_VO_FAST9_AVX512)
  return g_kernels.corners == rowCornersAvx512;
#else
  return false;
#endif
}

void detectFast9(const cv::Mat& img, const uint8_t* th, std::vector<cv::KeyPoint>* keypoints, Fast9Buffers* b,
                 const uint8_t* walls) {
  CV_Assert(img.type() == CV_8UC1);
  keypoints->clear();
  const int rows = img.rows, cols = img.cols;
  if (rows < 7 || cols < 7) return;
  const RowKernels kernels = g_kernels;
  int off[kRingSize];
  const int step = static_cast<int>(img.step1());
  for (int k = 0; k < 16; ++k) off[k] = kCircle[k][0] + kCircle[k][1] * step;
  for (int k = 16; k < kRingSize; ++k) off[k] = off[k - 16];
  // Score rows in a ring of 4: row i is scanned, then row i - 2 is suppressed against rows i - 3 .. i - 1, so
  // non-max suppression never reads the row whose corner scores were just stored byte by byte (those loads
  // would wait for the stores). Rows 2 and rows - 3 are all zero (no corners), as cv::FAST's borders.
  int n_corners[kRows] = {0, 0, 0, 0};
  for (int r = 0; r < kRows; ++r) {
    b->score[r].assign(cols, 0);
    b->corners[r].resize(cols);
  }
  for (int i = 3; i <= rows - 2; ++i) {
    uint8_t* curr = b->score[i % kRows].data();
    int* pos = b->corners[i % kRows].data();
    std::memset(curr, 0, cols);
    int nc = 0;
    if (i < rows - 3) nc = kernels.corners(img.ptr<uint8_t>(i), off, th, cols, curr, pos);
    n_corners[i % kRows] = nc;
    const int j = i - 2;  // the row to suppress
    if (j < 3 || n_corners[j % kRows] == 0) continue;
    // Non-max suppression of row j against rows j - 1 .. j + 1 (non-corners have score 0).
    const uint8_t* prev = b->score[j % kRows].data();
    const uint8_t* pprev = b->score[(j - 1) % kRows].data();
    const uint8_t* next = b->score[(j + 1) % kRows].data();
    int* kept = b->corners[j % kRows].data();  // its corner list is no longer needed
    int n_kept = 0;
    const int n_prev = n_corners[j % kRows];
    if (n_prev * 24 < cols) {  // few corners: test each (its list is ascending) rather than every column
      for (int k = 0; k < n_prev; ++k) {
        const int x = kept[k];
        const uint8_t s = prev[x];
        if (!(s > pprev[x] && s > next[x])) continue;
        const int w = walls ? walls[x] : 0;
        if (((w & kWallLeft) || (s > prev[x - 1] && s > pprev[x - 1] && s > next[x - 1])) &&
            ((w & kWallRight) || (s > prev[x + 1] && s > pprev[x + 1] && s > next[x + 1])))
          kept[n_kept++] = x;
      }
    } else {
      n_kept = kernels.maxima(pprev, prev, next, walls, cols, kept);
    }
    for (int k = 0; k < n_kept; ++k)
      keypoints->emplace_back(static_cast<float>(kept[k]), static_cast<float>(j), 7.f, -1.f,
                              static_cast<float>(prev[kept[k]]));
  }
}

}  // namespace iraf_vo
