// One row of the enhancer's eqs. (11)-(12) (enhancer.cpp blendRow) with AVX-512: 16 pixels per float vector.
// The same float operations in the same order, no fused multiply-add (CMake: -ffp-contract=off; GCC: -mno-fma), so
// the same bytes as the 128-bit and scalar code. Built with -mavx512f -mavx512bw on x86-64 only; called where
// the CPU has AVX-512BW (checked at run time).
#if defined(IRAF_VO_AVX512_KERNELS) && !defined(__AVX512BW__)
#error "blend_avx512.cpp needs AVX-512BW code generation (CMakeLists.txt sets its flags per compiler)"
#endif
#if defined(IRAF_VO_AVX512_KERNELS)

// GCC 12 reports its own intrinsics' undefined-vector placeholders as maybe-uninitialized once inlined here.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

#include <cstdint>

namespace iraf_vo {
namespace blend_avx512 {

/// out = sat(wi * I + wb * B + wg * G + 0.5), truncated, for columns [0, n - n % 16); returns that count.
int blendRow(const uint8_t* pi, const uint8_t* pb, const uint8_t* pg, float wi, float wb, float wg, int n,
             uint8_t* po) {
  const __m512 vwi = _mm512_set1_ps(wi), vwb = _mm512_set1_ps(wb), vwg = _mm512_set1_ps(wg);
  const __m512 half = _mm512_set1_ps(0.5f), lo = _mm512_setzero_ps(), hi = _mm512_set1_ps(255.f);
  auto load = [](const uint8_t* p) {
    return _mm512_cvtepi32_ps(_mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
  };
  int c = 0;
  for (; c + 16 <= n; c += 16) {
    const __m512 fi = load(pi + c), fb = load(pb + c), fg = load(pg + c);
    __m512 v = _mm512_add_ps(_mm512_mul_ps(vwi, fi), _mm512_mul_ps(vwb, fb));
    v = _mm512_add_ps(_mm512_add_ps(v, _mm512_mul_ps(vwg, fg)), half);
    v = _mm512_min_ps(hi, _mm512_max_ps(lo, v));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(po + c), _mm512_cvtepi32_epi8(_mm512_cvttps_epi32(v)));
  }
  return c;
}

}  // namespace blend_avx512
}  // namespace iraf_vo

#endif
