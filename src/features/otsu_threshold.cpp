// Otsu threshold of a cell histogram (paper eqs. 16-18): the reference scan and a faster evaluation that returns
// the same t_o bit for bit. ROS-free.
#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>

#include "iraf_vo/features/adaptive_threshold.h"

namespace iraf_vo {

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
  OtsuScan scan;
  scan.t_o = scan.t_last = lo;
  for (int t = lo; t < hi; ++t) {
    w0 += h[t];
    s0 += static_cast<int64_t>(t) * h[t];
    const double num = static_cast<double>(sum_t * w0 - n * s0);
    scan.step(t, num * num, static_cast<double>(w0 * (n - w0)));
  }
  return (scan.t_o + scan.t_last) / 2;
}

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

}  // namespace iraf_vo
