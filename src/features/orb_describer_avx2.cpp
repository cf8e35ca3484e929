// The ORB sampling loop in AVX2: 8 pattern pairs per step, offsets rotated in float exactly as the scalar
// loop (no FMA, no contraction: x = px a - py b must round like cv::ORB's), rounded to nearest-even like
// cvRound, and the 8 pixels of each side fetched by one gather. CMake builds this file with -mavx2 on
// x86-64 only; OrbDescriber uses it where the CPU has AVX2 and it matched cv::ORB at start-up.
#include "orb_describer_kernels.h"

#if defined(IRAF_VO_AVX2_KERNELS) && defined(__AVX2__)

#if defined(__FMA__)
#error "orb_describer_avx2.cpp must be built without FMA (the rotated offsets must round like cv::ORB's)"
#endif

#include <immintrin.h>

#include <cstdint>
#include <cstring>

namespace iraf_vo {
namespace orb_describer_avx2 {
namespace {

// Byte offsets (iy * step + ix) of 8 rotated pattern points.
inline __m256i rotatedOffsets(const float* px, const float* py, __m256 a, __m256 b, __m256i step) {
  const __m256 x = _mm256_loadu_ps(px), y = _mm256_loadu_ps(py);
  const __m256i ix = _mm256_cvtps_epi32(_mm256_sub_ps(_mm256_mul_ps(x, a), _mm256_mul_ps(y, b)));
  const __m256i iy = _mm256_cvtps_epi32(_mm256_add_ps(_mm256_mul_ps(x, b), _mm256_mul_ps(y, a)));
  return _mm256_add_epi32(_mm256_mullo_epi32(iy, step), ix);
}

void describe(const uint8_t* center, int step, float angle_deg, const OrbPattern& p, uint8_t* desc) {
  float a, b;
  orbRotation(angle_deg, &a, &b);
  const __m256 va = _mm256_set1_ps(a), vb = _mm256_set1_ps(b);
  const __m256i vstep = _mm256_set1_epi32(step), low_byte = _mm256_set1_epi32(0xff);
  const int* base = reinterpret_cast<const int*>(center);  // gathers read 4 bytes; the low one is the pixel
  for (int k = 0; k < 256; k += 32) {
    uint32_t bits = 0;
    for (int q = 0; q < 4; ++q) {
      const int o = k + 8 * q;
      const __m256i v0 = _mm256_and_si256(_mm256_i32gather_epi32(base, rotatedOffsets(p.x0 + o, p.y0 + o, va, vb, vstep), 1), low_byte);
      const __m256i v1 = _mm256_and_si256(_mm256_i32gather_epi32(base, rotatedOffsets(p.x1 + o, p.y1 + o, va, vb, vstep), 1), low_byte);
      const int lt = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(v1, v0)));  // bit j: I(p0) < I(p1)
      bits |= static_cast<uint32_t>(lt) << (8 * q);
    }
    std::memcpy(desc + k / 8, &bits, 4);  // pairs k..k+31 -> bytes k/8..k/8+3, bit j of byte = pair 8 byte + j
  }
}

}  // namespace

OrbDescriber::Kernel kernel() { return describe; }

}  // namespace orb_describer_avx2
}  // namespace iraf_vo

#else

namespace iraf_vo {
namespace orb_describer_avx2 {
OrbDescriber::Kernel kernel() { return nullptr; }
}  // namespace orb_describer_avx2
}  // namespace iraf_vo

#endif
