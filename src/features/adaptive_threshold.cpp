#include "iraf_vo/features/adaptive_threshold.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

namespace iraf_vo {

void accumulateHistogram(const cv::Mat& gray, Histogram256* h) {
  CV_Assert(gray.type() == CV_8UC1);
  // Two interleaved sub-histograms (*h itself and b) break the store->load dependency on repeated values.
  uint32_t* a = h->data();
  uint32_t b[256] = {0};
  for (int r = 0; r < gray.rows; ++r) {
    const uint8_t* p = gray.ptr<uint8_t>(r);
    int c = 0;
    for (; c + 1 < gray.cols; c += 2) {
      ++a[p[c]];
      ++b[p[c + 1]];
    }
    if (c < gray.cols) ++a[p[c]];
  }
  for (int i = 0; i < 256; ++i) a[i] += b[i];
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

double meanGradientMagnitude(const cv::Mat& gray, cv::Mat* sobel_rows) {
  CV_Assert(gray.type() == CV_8UC1);
  if (gray.empty()) return 0.0;
  // eq. (14): I_x, I_y by 3x3 Sobel (replicated border); F_g = mean sqrt(I_x^2 + I_y^2). The Sobel rows are
  // computed here one at a time (separable: column sums s = U + 2M + D and differences e = D - U of the rows
  // above / at / below, then I_x = s(c+1) - s(c-1), I_y = e(c-1) + 2 e(c) + e(c+1)): the same integers as
  // cv::spatialGradient and the same float sums as meanGradientMagnitudeReference, without two image-sized
  // int16 planes.
  const int rows = gray.rows, cols = gray.cols;
  sobel_rows->create(4, cols + 2, CV_16S);  // rows: s, e (with one replicated column each side), I_x, I_y
  int16_t* s = sobel_rows->ptr<int16_t>(0);
  int16_t* e = sobel_rows->ptr<int16_t>(1);
  int16_t* gx = sobel_rows->ptr<int16_t>(2);
  int16_t* gy = sobel_rows->ptr<int16_t>(3);
  double sum = 0.0;
  for (int r = 0; r < rows; ++r) {
    const uint8_t* up = gray.ptr<uint8_t>(std::max(r - 1, 0));
    const uint8_t* mid = gray.ptr<uint8_t>(r);
    const uint8_t* dn = gray.ptr<uint8_t>(std::min(r + 1, rows - 1));
    int c = 0;
#if CV_SIMD128
    for (; c + 16 <= cols; c += 16) {
      cv::v_uint16x8 u0, u1, m0, m1, d0, d1;
      cv::v_expand(cv::v_load(up + c), u0, u1);
      cv::v_expand(cv::v_load(mid + c), m0, m1);
      cv::v_expand(cv::v_load(dn + c), d0, d1);
      cv::v_store(s + c + 1, cv::v_reinterpret_as_s16(u0 + m0 + m0 + d0));
      cv::v_store(s + c + 9, cv::v_reinterpret_as_s16(u1 + m1 + m1 + d1));
      cv::v_store(e + c + 1, cv::v_reinterpret_as_s16(d0) - cv::v_reinterpret_as_s16(u0));
      cv::v_store(e + c + 9, cv::v_reinterpret_as_s16(d1) - cv::v_reinterpret_as_s16(u1));
    }
#endif
    for (; c < cols; ++c) {
      s[c + 1] = static_cast<int16_t>(up[c] + 2 * mid[c] + dn[c]);
      e[c + 1] = static_cast<int16_t>(dn[c] - up[c]);
    }
    s[0] = s[1];
    e[0] = e[1];
    s[cols + 1] = s[cols];
    e[cols + 1] = e[cols];
    c = 0;
#if CV_SIMD128
    for (; c + 8 <= cols; c += 8) {
      const cv::v_int16x8 e1 = cv::v_load(e + c + 1);
      cv::v_store(gx + c, cv::v_load(s + c + 2) - cv::v_load(s + c));
      cv::v_store(gy + c, cv::v_load(e + c) + e1 + e1 + cv::v_load(e + c + 2));
    }
#endif
    for (; c < cols; ++c) {
      gx[c] = static_cast<int16_t>(s[c + 2] - s[c]);
      gy[c] = static_cast<int16_t>(e[c] + 2 * e[c + 1] + e[c + 2]);
    }
    sum += rowMagnitudeSum(gx, gy, cols);
  }
  return sum / (static_cast<double>(rows) * cols);
}

double meanGradientMagnitude(const cv::Mat& gray) {
  cv::Mat sobel_rows;
  return meanGradientMagnitude(gray, &sobel_rows);
}

int otsuThresholdReference(const Histogram256& h) {
  // N = number of pixels, S = sum of intensities (mu_T = S / N); lo / hi = first / last non-empty bin.
  // Branch-free sums: cells have ~1000 pixels spread over unpredictable bins.
  int lo = 0, hi = 255;
  while (lo < 256 && h[lo] == 0) ++lo;
  if (lo == 256) return 0;  // empty
  while (h[hi] == 0) --hi;
  int64_t n = 0, sum_t = 0;  // over [lo, hi] = over all bins
  for (int i = lo; i <= hi; ++i) {
    n += h[i];
    sum_t += static_cast<int64_t>(i) * h[i];
  }
  if (lo == hi) return lo;  // single-valued: no split exists
  // eq. (16) with P_t = w0 / N and mu_t = s0 / N (w0 = pixels <= t, s0 = their intensity sum):
  //   sigma_c^2(t) = (mu_T P_t - mu_t)^2 / (P_t (1 - P_t)) = (S w0 - N s0)^2 / (N^2 w0 (N - w0)).
  // N^2 is constant, so argmax compares num2 / den with num2 = (S w0 - N s0)^2, den = w0 (N - w0)
  // by cross-multiplication (no division). Bins outside [lo, hi] leave one class empty and are skipped.
  int64_t w0 = 0, s0 = 0;
  double best_num2 = -1.0, best_den = 1.0;
  int t_o = lo, t_last = lo;
  for (int t = lo; t < hi; ++t) {
    w0 += h[t];
    s0 += static_cast<int64_t>(t) * h[t];
    const double num = static_cast<double>(sum_t * w0 - n * s0);
    const double num2 = num * num, den = static_cast<double>(w0 * (n - w0));
    const double lhs = num2 * best_den, rhs = best_num2 * den;
    if (lhs > rhs * (1.0 + 1e-12)) {  // eq. (17): t_o = argmax_t sigma_c^2(t)
      best_num2 = num2;
      best_den = den;
      t_o = t_last = t;
    } else if (t_last == t - 1 && lhs >= rhs * (1.0 - 1e-12)) {
      t_last = t;  // flat maximum (empty bins between the classes): take its middle
    }
  }
  return (t_o + t_last) / 2;
}

namespace {

// One step of otsuThresholdReference's scan at t (num2, den of eq. 16 cross-multiplied): the same comparisons
// on the same doubles, so a scan over any range starting in the same state ends in the same state.
struct OtsuScan {
  double best_num2 = -1.0, best_den = 1.0;
  int t_o = 0, t_last = 0;
  void step(int t, double num2, double den) {
    const double lhs = num2 * best_den, rhs = best_num2 * den;
    if (lhs > rhs * (1.0 + 1e-12)) {  // eq. (17): t_o = argmax_t sigma_c^2(t)
      best_num2 = num2;
      best_den = den;
      t_o = t_last = t;
    } else if (t_last == t - 1 && lhs >= rhs * (1.0 - 1e-12)) {
      t_last = t;  // flat maximum (empty bins between the classes): take its middle
    }
  }
};

}  // namespace

int otsuThreshold(const Histogram256& h) {
  // lo / hi = first / last non-empty bin (4 bins at a time, then within the vector).
  int lo = 0, hi = 252;
#if CV_SIMD128
  const cv::v_uint32x4 zero = cv::v_setzero_u32();
  while (lo < 256 && !cv::v_check_any(cv::v_load(h.data() + lo) != zero)) lo += 4;
  if (lo == 256) return 0;  // empty
  while (!cv::v_check_any(cv::v_load(h.data() + hi) != zero)) hi -= 4;
#endif
  while (lo < 256 && h[lo] == 0) ++lo;
  if (lo == 256) return 0;  // empty
  hi += 3;
  while (h[hi] == 0) --hi;
  if (lo == hi) return lo;  // single-valued: no split exists
  // Class sums: w0(t) = pixels <= t, s0(t) = their intensity sum, for t = lo .. hi (int32 below n = 4e6).
  alignas(16) int32_t w0[260], s0[260];
  uint64_t w = 0;
  uint32_t s = 0;  // no wrap-around while n <= 4e6 (s <= 255 n)
  for (int t = lo; t <= hi; ++t) {
    w += h[t];
    s += static_cast<uint32_t>(t) * h[t];
    w0[t - lo] = static_cast<int32_t>(w);
    s0[t - lo] = static_cast<int32_t>(s);
  }
  // As doubles, sum_t * w0 and n * s0 are exact (< 255 n^2 < 2^53), so num, num2 and den below are the
  // doubles the reference computes from its int64 values; above n = 4e6, the reference itself.
  if (w > 4000000) return otsuThresholdReference(h);
  const double n = static_cast<double>(w), sum_t = static_cast<double>(s);
  // eq. (16) cross-multiplied, as in otsuThresholdReference: sigma_c^2(t) ~ num2 / den with
  // num2 = (S w0 - N s0)^2, den = w0 (N - w0); v = num2 / den only locates the maximum.
  const int m = hi - lo;  // t = lo .. hi - 1
  alignas(16) double num2[260], den[260], v[260];
  int k = 0;
  double v_max = 0.0;
#if CV_SIMD128_64F
  const cv::v_float64x2 v_sum_t = cv::v_setall_f64(sum_t), v_n = cv::v_setall_f64(n);
  cv::v_float64x2 best0 = cv::v_setzero_f64(), best1 = best0;
  auto eval2 = [&](int i, const cv::v_float64x2& a, const cv::v_float64x2& b, cv::v_float64x2* best) {
    const cv::v_float64x2 num = v_sum_t * a - v_n * b;
    const cv::v_float64x2 q2 = num * num, d = a * (v_n - a), r = q2 / d;
    cv::v_store_aligned(num2 + i, q2);
    cv::v_store_aligned(den + i, d);
    cv::v_store_aligned(v + i, r);
    *best = cv::v_max(*best, r);
  };
  for (; k + 4 <= m; k += 4) {
    const cv::v_int32x4 a = cv::v_load_aligned(w0 + k), b = cv::v_load_aligned(s0 + k);
    eval2(k, cv::v_cvt_f64(a), cv::v_cvt_f64(b), &best0);
    eval2(k + 2, cv::v_cvt_f64_high(a), cv::v_cvt_f64_high(b), &best1);
  }
  alignas(16) double lanes[2];
  cv::v_store_aligned(lanes, cv::v_max(best0, best1));
  v_max = std::max(lanes[0], lanes[1]);
#endif
  for (; k < m; ++k) {
    const double num = sum_t * w0[k] - n * s0[k];
    num2[k] = num * num;
    den[k] = static_cast<double>(w0[k]) * (n - w0[k]);
    v[k] = num2[k] / den[k];
    v_max = std::max(v_max, v[k]);
  }
  // Only t with sigma_c^2 near the maximum can change the reference scan's state: run the scan on
  // [q, r] = the first / last t with v >= theta_band = theta (1 - 1e-9), theta = v_max (1 - 1e-6).
  // Before q every v is < theta_band; if v(q) >= theta, v(q) exceeds them by more than the reference's 1e-12
  // tolerance, so the reference takes q as its new best whatever its state (else: scan from lo). After r every
  // v is < theta_band < best (1 - 1e-6): no update, no flat extension.
  const double theta = v_max * (1.0 - 1e-6), theta_band = theta * (1.0 - 1e-9);
  int q = 0, r = m - 1;
  while (v[q] < theta_band) ++q;
  while (v[r] < theta_band) --r;
  if (v[q] < theta) q = 0;
  OtsuScan scan;
  for (int i = q; i <= r; ++i) scan.step(lo + i, num2[i], den[i]);
  return (scan.t_o + scan.t_last) / 2;
}

void CellThresholdEstimator::measureCells(const cv::Mat& img, const CellGrid& g, int center_window,
                                          Histogram256* level_hist) {
  otsu_.resize(g.cells());
  center_.resize(g.cells());
  const int hw = center_window / 2;
  for (int i = 0; i < g.n_rows; ++i) {
    const int y0 = g.y0(i), y1 = std::min(y0 + g.h_cell, g.max_y);
    for (int j = 0; j < g.n_cols; ++j) {
      const int x0 = g.x0(j), x1 = std::min(x0 + g.w_cell, g.max_x);
      const int c = i * g.n_cols + j;
      if (y1 <= y0 || x1 <= x0) {
        otsu_[c] = 0;
        center_[c] = 0;
        continue;
      }
      Histogram256 h{};
      accumulateHistogram(img(cv::Rect(x0, y0, x1 - x0, y1 - y0)), &h);
      if (level_hist)
        for (int b = 0; b < 256; ++b) (*level_hist)[b] += h[b];
      otsu_[c] = otsuThreshold(h);  // eqs. (16)-(18): t_o of the subregion
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
      center_[c] = static_cast<double>(sum) / win.area();
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
  measureCells(img, g, p.center_window, level0 ? &level_hist : nullptr);  // F_h is of level 0 only
  // The global metrics (eqs. 13-15) are computed once, on level 0 (the enhanced image, as in the paper):
  // F_h over the detection area (the union of the level-0 cells), F_g over the whole image. Every level
  // uses this F_t^g as the upper clip; the per-cell F_t^l adapts to each level.
  if (level0) {
    st->entropy = histogramEntropy(level_hist);                                          // eq. (13): F_h
    st->gradient = meanGradientMagnitude(img, &sobel_rows_);                         // eq. (14): F_g
    st->global_threshold = globalThreshold(st->entropy, st->gradient, p.alpha, p.beta);  // eq. (15): F_t^g
  }
  for (int c = 0; c < g.cells(); ++c) {
    const double ft_l = localThreshold(center_[c], otsu_[c], p.delta);       // eq. (19): F_t^l
    (*thresholds)[c] = clipThreshold(ft_l, p.ft_min, st->global_threshold);  // eq. (20): F_t
  }
  return p.ft_min;
}

}  // namespace iraf_vo

