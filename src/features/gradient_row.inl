// One row of F_g (eq. 14): 3x3 Sobel of the row (replicated border) and the float sum of sqrt(I_x^2 + I_y^2),
// written once with OpenCV's universal intrinsics and compiled twice: adaptive_threshold.cpp (baseline) and
// gradient_avx2.cpp (AVX2, 16 pixels per step). The sum is accumulated in 4 float lanes in the baseline's order
// (lane k of the accumulator adds pixels 8i + k and 8i + 4 + k, then one v_reduce_sum, then the scalar tail),
// with separate multiply and add (no FMA), so both builds return the same float. Include after
// <opencv2/core/hal/intrin.hpp>, inside the TU's own namespace (no std:: templates here).

namespace {

// s / e (one replicated column each side): column sums U + 2M + D and differences D - U of the rows
// above / at / below; I_x = s(c+1) - s(c-1), I_y = e(c-1) + 2 e(c) + e(c+1): cv::spatialGradient's integers.
// Returns the float sum of the row's magnitudes; gx, gy hold the row's I_x, I_y.
float sobelRowMagnitudeSum(const uint8_t* up, const uint8_t* mid, const uint8_t* dn, int cols, int16_t* s,
                           int16_t* e, int16_t* gx, int16_t* gy) {
  int c = 0;
#if CV_SIMD256
  for (; c + 32 <= cols; c += 32) {
    cv::v_uint16x16 u0, u1, m0, m1, d0, d1;
    cv::v_expand(cv::v256_load(up + c), u0, u1);
    cv::v_expand(cv::v256_load(mid + c), m0, m1);
    cv::v_expand(cv::v256_load(dn + c), d0, d1);
    cv::v_store(s + c + 1, cv::v_reinterpret_as_s16(u0 + m0 + m0 + d0));
    cv::v_store(s + c + 17, cv::v_reinterpret_as_s16(u1 + m1 + m1 + d1));
    cv::v_store(e + c + 1, cv::v_reinterpret_as_s16(d0) - cv::v_reinterpret_as_s16(u0));
    cv::v_store(e + c + 17, cv::v_reinterpret_as_s16(d1) - cv::v_reinterpret_as_s16(u1));
  }
#endif
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
#if CV_SIMD256
  for (; c + 16 <= cols; c += 16) {
    const cv::v_int16x16 e1 = cv::v256_load(e + c + 1);
    cv::v_store(gx + c, cv::v256_load(s + c + 2) - cv::v256_load(s + c));
    cv::v_store(gy + c, cv::v256_load(e + c) + e1 + e1 + cv::v256_load(e + c + 2));
  }
#endif
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
  float row_sum = 0.f;
  c = 0;
#if CV_SIMD128
  cv::v_float32x4 acc = cv::v_setzero_f32();
#if CV_SIMD256
  // Magnitudes of 16 pixels as two 8-lane vectors m0 (c .. c+7), m1 (c+8 .. c+15), added to the 4-lane
  // accumulator as the baseline does: acc + (m0[0..3] + m0[4..7]), then + (m1[0..3] + m1[4..7]).
  for (; c + 16 <= cols; c += 16) {
    cv::v_int32x8 x0, x1, y0, y1;
    cv::v_expand(cv::v256_load(gx + c), x0, x1);
    cv::v_expand(cv::v256_load(gy + c), y0, y1);
    const cv::v_float32x8 fx0 = cv::v_cvt_f32(x0), fx1 = cv::v_cvt_f32(x1);
    const cv::v_float32x8 fy0 = cv::v_cvt_f32(y0), fy1 = cv::v_cvt_f32(y1);
    const cv::v_float32x8 m0 = cv::v_sqrt(fx0 * fx0 + fy0 * fy0), m1 = cv::v_sqrt(fx1 * fx1 + fy1 * fy1);
    alignas(32) float t[8];
    cv::v_store_aligned(t, cv::v_combine_low(m0, m1) + cv::v_combine_high(m0, m1));
    acc = acc + cv::v_load_aligned(t);
    acc = acc + cv::v_load_aligned(t + 4);
  }
#endif
  for (; c + 8 <= cols; c += 8) {
    cv::v_int32x4 x0, x1, y0, y1;
    cv::v_expand(cv::v_load(gx + c), x0, x1);
    cv::v_expand(cv::v_load(gy + c), y0, y1);
    const cv::v_float32x4 fx0 = cv::v_cvt_f32(x0), fx1 = cv::v_cvt_f32(x1);
    const cv::v_float32x4 fy0 = cv::v_cvt_f32(y0), fy1 = cv::v_cvt_f32(y1);
    acc = acc + (cv::v_sqrt(fx0 * fx0 + fy0 * fy0) + cv::v_sqrt(fx1 * fx1 + fy1 * fy1));
  }
  row_sum = cv::v_reduce_sum(acc);
#endif
  for (; c < cols; ++c) row_sum += sqrtf(static_cast<float>(gx[c] * gx[c] + gy[c] * gy[c]));  // = std::sqrt
  return row_sum;
}

}  // namespace
