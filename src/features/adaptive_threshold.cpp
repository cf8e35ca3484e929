#include "iraf_vo/features/adaptive_threshold.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <cstring>

namespace iraf_vo {

void accumulateHistogram(const cv::Mat& gray, Histogram256* h) {
  CV_Assert(gray.type() == CV_8UC1);
  // Four interleaved sub-histograms (column c counts in t[c % 4]) break the store->load dependency on repeated
  // values; each row is read 8 pixels per load. (Two sub-histograms and byte loads: 1.5x slower on EuRoC cells.)
  alignas(64) uint32_t t[4][256];
  std::memset(t, 0, sizeof(t));
  const int cols = gray.cols;
  for (int r = 0; r < gray.rows; ++r) {
    const uint8_t* p = gray.ptr<uint8_t>(r);
    int c = 0;
    for (; c + 8 <= cols; c += 8) {
      uint64_t w;
      std::memcpy(&w, p + c, 8);  // any byte order: it only decides which sub-histogram counts a pixel
      ++t[0][w & 255];
      ++t[1][(w >> 8) & 255];
      ++t[2][(w >> 16) & 255];
      ++t[3][(w >> 24) & 255];
      ++t[0][(w >> 32) & 255];
      ++t[1][(w >> 40) & 255];
      ++t[2][(w >> 48) & 255];
      ++t[3][w >> 56];
    }
    for (; c < cols; ++c) ++t[c & 3][p[c]];
  }
  uint32_t* a = h->data();
  for (int i = 0; i < 256; ++i) a[i] += t[0][i] + t[1][i] + t[2][i] + t[3][i];
}

double histogramEntropy(const Histogram256& h) {
  double total = 0.0;
  for (uint32_t v : h) total += v;
  if (!(total > 0.0)) return 0.0;
  // eq. (13): F_h = -sum_i P(i) log P(i), log base 2 (bits)
  double f_h = 0.0;
  for (uint32_t v : h) {
    if (v == 0) continue;
    const double p = v / total;
    f_h -= p * std::log2(p);
  }
  return f_h;
}

namespace {

// Adds sqrt(I_x^2 + I_y^2) of one row to a float sum, in a fixed order (vector lanes, then the tail).
float rowMagnitudeSum(const int16_t* gx, const int16_t* gy, int cols) {
  float row_sum = 0.f;
  int c = 0;
#if CV_SIMD
  // sqrt(I_x^2 + I_y^2) with OpenCV's universal intrinsics (int16 -> int32 -> float, vector sqrt).
  cv::v_float32 acc = cv::vx_setzero_f32();
  for (; c + cv::v_int16::nlanes <= cols; c += cv::v_int16::nlanes) {
    cv::v_int32 x0, x1, y0, y1;
    cv::v_expand(cv::vx_load(gx + c), x0, x1);
    cv::v_expand(cv::vx_load(gy + c), y0, y1);
    const cv::v_float32 fx0 = cv::v_cvt_f32(x0), fx1 = cv::v_cvt_f32(x1);
    const cv::v_float32 fy0 = cv::v_cvt_f32(y0), fy1 = cv::v_cvt_f32(y1);
    acc += cv::v_sqrt(cv::v_fma(fx0, fx0, fy0 * fy0)) + cv::v_sqrt(cv::v_fma(fx1, fx1, fy1 * fy1));
  }
  row_sum = cv::v_reduce_sum(acc);
#endif
  for (; c < cols; ++c) row_sum += std::sqrt(static_cast<float>(gx[c] * gx[c] + gy[c] * gy[c]));
  return row_sum;
}

}  // namespace

double meanGradientMagnitudeReference(const cv::Mat& gray) {
  CV_Assert(gray.type() == CV_8UC1);
  if (gray.empty()) return 0.0;
  cv::Mat dx, dy;
  cv::spatialGradient(gray, dx, dy, 3, cv::BORDER_REPLICATE);
  double sum = 0.0;
  for (int r = 0; r < gray.rows; ++r) sum += rowMagnitudeSum(dx.ptr<int16_t>(r), dy.ptr<int16_t>(r), gray.cols);
  return sum / (static_cast<double>(gray.rows) * gray.cols);
}

namespace gradient_baseline {
#include "gradient_row.inl"
}  // namespace gradient_baseline

#if defined(IRAF_VO_AVX2_KERNELS)
namespace gradient_avx2 {
float rowSum(const uint8_t* up, const uint8_t* mid, const uint8_t* dn, int cols, int16_t* s, int16_t* e, int16_t* gx,
             int16_t* gy);
}  // namespace gradient_avx2
#endif

namespace {

using GradientRowFn = float (*)(const uint8_t*, const uint8_t*, const uint8_t*, int, int16_t*, int16_t*, int16_t*,
                                int16_t*);

// The row kernel for this CPU: AVX2 where available, else the baseline build. Same float sums either way.
GradientRowFn pickGradientRow(bool avx2_allowed) {
#if defined(IRAF_VO_AVX2_KERNELS)
  if (avx2_allowed && __builtin_cpu_supports("avx2")) return gradient_avx2::rowSum;
#endif
  (void)avx2_allowed;
  return gradient_baseline::sobelRowMagnitudeSum;
}

GradientRowFn g_gradient_row = pickGradientRow(true);

}  // namespace

bool gradientUseAvx2(bool allowed) {
  g_gradient_row = pickGradientRow(allowed);
  return g_gradient_row != gradient_baseline::sobelRowMagnitudeSum;
}

double meanGradientMagnitude(const cv::Mat& gray, cv::Mat* sobel_rows) {
  CV_Assert(gray.type() == CV_8UC1);
  if (gray.empty()) return 0.0;
  // eq. (14): I_x, I_y by 3x3 Sobel (replicated border); F_g = mean sqrt(I_x^2 + I_y^2). The Sobel rows are
  // computed here one at a time (gradient_row.inl): the same integers as cv::spatialGradient and the same float
  // sums as meanGradientMagnitudeReference, without two image-sized int16 planes.
  const int rows = gray.rows, cols = gray.cols;
  sobel_rows->create(4, cols + 2, CV_16S);  // rows: s, e (with one replicated column each side), I_x, I_y
  int16_t* s = sobel_rows->ptr<int16_t>(0);
  int16_t* e = sobel_rows->ptr<int16_t>(1);
  int16_t* gx = sobel_rows->ptr<int16_t>(2);
  int16_t* gy = sobel_rows->ptr<int16_t>(3);
  const GradientRowFn row_sum = g_gradient_row;
  double sum = 0.0;
  for (int r = 0; r < rows; ++r)
    sum += row_sum(gray.ptr<uint8_t>(std::max(r - 1, 0)), gray.ptr<uint8_t>(r), gray.ptr<uint8_t>(std::min(r + 1, rows - 1)),
                   cols, s, e, gx, gy);
  return sum / (static_cast<double>(rows) * cols);
}

double meanGradientMagnitude(const cv::Mat& gray) {
  cv::Mat sobel_rows;
  return meanGradientMagnitude(gray, &sobel_rows);
}

double meanDeviationFrom(const Histogram256& h, int t_o) {
  uint64_t n = 0, dev = 0;
  for (int b = 0; b < 256; ++b) {
    n += h[b];
    dev += static_cast<uint64_t>(h[b]) * static_cast<uint64_t>(b > t_o ? b - t_o : t_o - b);
  }
  return n > 0 ? static_cast<double>(dev) / static_cast<double>(n) : 0.0;
}

void CellThresholdEstimator::measureCells(const cv::Mat& img, const CellGrid& g, int center_window,
                                          bool cell_mean, Histogram256* level_hist) {
  otsu_.resize(g.cells());
  contrast_.resize(g.cells());
  const int hw = center_window / 2;
  for (int i = 0; i < g.n_rows; ++i) {
    const int y0 = g.y0(i), y1 = std::min(y0 + g.h_cell, g.max_y);
    for (int j = 0; j < g.n_cols; ++j) {
      const int x0 = g.x0(j), x1 = std::min(x0 + g.w_cell, g.max_x);
      const int c = i * g.n_cols + j;
      if (y1 <= y0 || x1 <= x0) {
        otsu_[c] = 0;
        contrast_[c] = 0;
        continue;
      }
      Histogram256 h{};
      accumulateHistogram(img(cv::Rect(x0, y0, x1 - x0, y1 - y0)), &h);
      if (level_hist)
        for (int b = 0; b < 256; ++b) (*level_hist)[b] += h[b];
      otsu_[c] = otsuThreshold(h);  // eqs. (16)-(18): t_o of the subregion
      if (cell_mean) {  // |I_m - t_o| of eq. (19) averaged over every position of I_m in the cell
        contrast_[c] = meanDeviationFrom(h, otsu_[c]);
        continue;
      }
      // I_m of eq. (19). The paper uses the single centre pixel G(size/2, size/2); here the mean of a
      // center_window^2 patch at the centre (center_window = 1 gives the paper's pixel), because one
      // pixel makes F_t^l follow sensor noise.
      const int cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
      const cv::Rect win = cv::Rect(cx - hw, cy - hw, 2 * hw + 1, 2 * hw + 1) & cv::Rect(0, 0, img.cols, img.rows);
      int sum = 0;
      for (int r = win.y; r < win.y + win.height; ++r) {
        const uint8_t* row = img.ptr<uint8_t>(r);
        for (int x = win.x; x < win.x + win.width; ++x) sum += row[x];
      }
      contrast_[c] = std::abs(static_cast<double>(sum) / win.area() - otsu_[c]);
    }
  }
}

double CellThresholdEstimator::estimate(const cv::Mat& img, const CellGrid& g, const FeatureParams& p, bool level0,
                                        FeatureStats* st, std::vector<double>* thresholds) {
  thresholds->assign(g.cells(), static_cast<double>(p.ini_th_fast));
  if (!p.adaptive_threshold) {
    if (level0) st->global_threshold = p.ini_th_fast;
    return p.min_th_fast;
  }
  Histogram256 level_hist{};
  measureCells(img, g, p.center_window, p.cell_mean_contrast, level0 ? &level_hist : nullptr);  // F_h is of level 0 only
  // The global metrics (eqs. 13-15) are computed once, on level 0 (the enhanced image, as in the paper):
  // F_h over the detection area (the union of the level-0 cells), F_g over the whole image. Every level
  // uses this F_t^g as the upper clip; the per-cell F_t^l adapts to each level.
  if (level0) {
    st->entropy = histogramEntropy(level_hist);                                          // eq. (13): F_h
    st->gradient = meanGradientMagnitude(img, &sobel_rows_);                         // eq. (14): F_g
    st->global_threshold = globalThreshold(st->entropy, st->gradient, p.alpha, p.beta);  // eq. (15): F_t^g
  }
  for (int c = 0; c < g.cells(); ++c) {
    const double ft_l = p.delta * contrast_[c];                              // eq. (19): F_t^l
    (*thresholds)[c] = clipThreshold(ft_l, p.ft_min, st->global_threshold);  // eq. (20): F_t
  }
  return p.ft_min;
}

}  // namespace iraf_vo

