// The F_g row kernel (gradient_row.inl) compiled for AVX2: 16 pixels per step. CMake builds this file with -mavx2
// (no FMA, no contraction: the float sum must equal the baseline's) on x86-64 only; meanGradientMagnitude calls it
// where the CPU has AVX2 (checked at run time). Same pattern as fast9_avx2.cpp.
#if defined(IRAF_VO_AVX2_KERNELS) && defined(__AVX2__)

#include <math.h>
#include "avx2_intrinsics.h"

#include <cstdint>

#if !CV_SIMD256
#error "gradient_avx2.cpp: OpenCV's 256-bit intrinsics are not enabled"
#endif
#if defined(__FMA__)
#error "gradient_avx2.cpp must be built without FMA (the sum must round like the baseline build's)"
#endif

namespace iraf_vo {
namespace gradient_avx2 {
#include "gradient_row.inl"

float rowSum(const uint8_t* up, const uint8_t* mid, const uint8_t* dn, int cols, int16_t* s, int16_t* e, int16_t* gx,
             int16_t* gy) {
  return sobelRowMagnitudeSum(up, mid, dn, cols, s, e, gx, gy);
}
}  // namespace gradient_avx2
}  // namespace iraf_vo

#endif
