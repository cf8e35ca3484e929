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

namespace {

constexpr int kCircle[16][2] = {{0, 3},  {1, 3},   {2, 2},   {3, 1},   {3, 0},  {3, -1}, {2, -2}, {1, -3},
                                {0, -3}, {-1, -3}, {-2, -2}, {-3, -1}, {-3, 0}, {-3, 1}, {-2, 2}, {-1, 3}};
constexpr int kRingSize = 25;  // 16 + 9: every arc of 9 is a plain window

struct RowKernels {
  int (*corners)(const uint8_t*, const int*, const uint8_t*, int, uint8_t*, int*);
  int (*maxima)(const uint8_t*, const uint8_t*, const uint8_t*, const uint8_t*, int, int*);
};

// The row kernels for this CPU: AVX2 (32 lanes) where available, else the baseline build (16 lanes).
// Same corners and scores either way.
RowKernels pickRowKernels(bool avx2_allowed) {
#if defined(IRAF_VO_FAST9_AVX2)
  if (avx2_allowed && __builtin_cpu_supports("avx2")) return {fast9_avx2::rowCorners, fast9_avx2::rowMaxima};
#endif
  (void)avx2_allowed;
  return {fast9_baseline::rowCorners, fast9_baseline::rowMaxima};
}

RowKernels g_kernels = pickRowKernels(true);

}  // namespace

bool fast9UseAvx2(bool allowed) {
  g_kernels = pickRowKernels(allowed);
  return g_kernels.corners != fast9_baseline::rowCorners;
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
    if (i < rows - 3) nc = kernels.corners(img.ptr<uint8_t>(i), off, th, cols, curr, pos);
    n_corners[i % 3] = nc;
    if (i == 3 || n_corners[(i - 1) % 3] == 0) continue;
    // Non-max suppression of row i - 1 against rows i - 2 .. i (non-corners have score 0).
    const uint8_t* prev = b->score[(i - 1) % 3].data();
    const uint8_t* pprev = b->score[(i - 2) % 3].data();
    int* kept = b->corners[(i - 1) % 3].data();  // its corner list is no longer needed
    int n_kept = 0;
    const int n_prev = n_corners[(i - 1) % 3];
    if (n_prev * 24 < cols) {  // few corners: test each (its list is ascending) rather than every column
      for (int k = 0; k < n_prev; ++k) {
        const int j = kept[k];
        const uint8_t s = prev[j];
        if (!(s > pprev[j] && s > curr[j])) continue;
        const int w = walls ? walls[j] : 0;
        if (((w & kWallLeft) || (s > prev[j - 1] && s > pprev[j - 1] && s > curr[j - 1])) &&
            ((w & kWallRight) || (s > prev[j + 1] && s > pprev[j + 1] && s > curr[j + 1])))
          kept[n_kept++] = j;
      }
    } else {
      n_kept = kernels.maxima(pprev, prev, curr, walls, cols, kept);
    }
    for (int k = 0; k < n_kept; ++k)
      keypoints->emplace_back(static_cast<float>(kept[k]), static_cast<float>(i - 1), 7.f, -1.f,
                              static_cast<float>(prev[kept[k]]));
  }
}

}  // namespace iraf_vo
