// cv::ORB's blur (GaussianBlur 7x7, sigma 2, on a sub-matrix of a reflect-101-padded level) in AVX2 + FMA,
// in place. OpenCV blurs a sub-matrix through its float separable filter; where it dispatches to AVX2 that
// filter forms each row sum as a chain of fused multiply-adds over the 7 taps from 0, and each column sum as
// k0 * S0 fused-added with k_i * (S_i + S_-i), i = 1..3, rounded to nearest-even and saturated. This file
// forms the same chains, so the bytes are equal where OpenCV's own dispatch is the AVX2 one; OrbDescriber
// compares the two at start-up and keeps OpenCV's blur if one byte differs. CMake builds this file with
// -mavx2 -mfma on x86-64 only.
#include "orb_describer_kernels.h"

#if defined(IRAF_VO_AVX2_KERNELS) && defined(__AVX2__) && defined(__FMA__)

#include <immintrin.h>

#include <cmath>
#include <cstdint>

namespace iraf_vo {
namespace orb_blur_avx2 {
namespace {

// Row sums of one padded row: out[x] = fma chain over taps j of src[x + j - 3] * k[j], x in [0, cols).
// The row's pixels are converted to float once (f[i] = src[i - 3]), then each tap is one load and one fma.
void rowPass(const uint8_t* src, int cols, const float* k, float* f, float* out) {
  const uint8_t* s = src - 3;
  const int n = cols + 6;
  int i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(f + i, _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(s + i)))));
  for (; i < n; ++i) f[i] = static_cast<float>(s[i]);
  __m256 kv[7];
  for (int j = 0; j < 7; ++j) kv[j] = _mm256_set1_ps(k[j]);
  int x = 0;
  for (; x + 8 <= cols; x += 8) {
    __m256 acc = _mm256_setzero_ps();
    for (int j = 0; j < 7; ++j) acc = _mm256_fmadd_ps(_mm256_loadu_ps(f + x + j), kv[j], acc);
    _mm256_storeu_ps(out + x, acc);
  }
  for (; x < cols; ++x) {
    float acc = 0.f;
    for (int j = 0; j < 7; ++j) acc = std::fma(f[x + j], k[j], acc);
    out[x] = acc;
  }
}

// One output row from the row sums of rows y-3..y+3 (r[0..6]).
void columnPass(const float* const* r, int cols, const float* k, uint8_t* dst) {
  const __m256 k0 = _mm256_set1_ps(k[3]), k1 = _mm256_set1_ps(k[4]), k2 = _mm256_set1_ps(k[5]), k3 = _mm256_set1_ps(k[6]);
  int x = 0;
  for (; x + 8 <= cols; x += 8) {
    __m256 acc = _mm256_mul_ps(k0, _mm256_loadu_ps(r[3] + x));
    acc = _mm256_fmadd_ps(k1, _mm256_add_ps(_mm256_loadu_ps(r[4] + x), _mm256_loadu_ps(r[2] + x)), acc);
    acc = _mm256_fmadd_ps(k2, _mm256_add_ps(_mm256_loadu_ps(r[5] + x), _mm256_loadu_ps(r[1] + x)), acc);
    acc = _mm256_fmadd_ps(k3, _mm256_add_ps(_mm256_loadu_ps(r[6] + x), _mm256_loadu_ps(r[0] + x)), acc);
    const __m256i i32 = _mm256_cvtps_epi32(acc);  // nearest-even, as cvRound
    const __m128i i16 = _mm_packs_epi32(_mm256_castsi256_si128(i32), _mm256_extracti128_si256(i32, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(dst + x), _mm_packus_epi16(i16, i16));
  }
  for (; x < cols; ++x) {
    float acc = k[3] * r[3][x];
    for (int i = 1; i <= 3; ++i) acc = std::fma(k[3 + i], r[3 + i][x] + r[3 - i][x], acc);
    const int v = static_cast<int>(std::nearbyint(acc));
    dst[x] = static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
  }
}

}  // namespace

bool built() { return true; }

void blurInPlace(uint8_t* padded, size_t step, int pad, int cols, int rows, const float* k, float* ring) {
  // Ring of 7 row-sum rows: row-sum row t (padded row pad - 3 + t) lives in slot t % 7; then the float copy of
  // one padded row. Output row y is written into the padded row it replaces once no later row sum needs it.
  auto slot = [&](int t) { return ring + static_cast<size_t>(t % 7) * cols; };
  float* f = ring + static_cast<size_t>(7) * cols;
  auto srcRow = [&](int t) { return padded + static_cast<size_t>(pad - 3 + t) * step + pad; };
  for (int t = 0; t < 6; ++t) rowPass(srcRow(t), cols, k, f, slot(t));
  for (int y = 0; y < rows; ++y) {
    rowPass(srcRow(y + 6), cols, k, f, slot(y + 6));  // row y + 3 of the level
    const float* r[7];
    for (int i = 0; i < 7; ++i) r[i] = slot(y + i);
    columnPass(r, cols, k, padded + static_cast<size_t>(pad + y) * step + pad);
  }
}

}  // namespace orb_blur_avx2
}  // namespace iraf_vo

#else

#include <cstdlib>

namespace iraf_vo {
namespace orb_blur_avx2 {
bool built() { return false; }
void blurInPlace(uint8_t*, size_t, int, int, int, const float*, float*) { std::abort(); }  // never called: built() is false
}  // namespace orb_blur_avx2
}  // namespace iraf_vo

#endif
