// The FAST-9 row kernel (fast9_row.inl) compiled for AVX2: 32 lanes per block. CMake builds this file with
// -mavx2 on x86-64 only; detectFast9 calls it where the CPU has AVX2 (checked at run time). OpenCV's
// universal intrinsics are used in their AVX2 form (namespace cv::hal_AVX2, as OpenCV's own dispatched code).
#if defined(IRAF_VO_FAST9_AVX2) && defined(__AVX2__)

#define CV_FP16 1
#define CV_FMA3 1
#include "avx2_intrinsics.h"

#include <cstdint>

#if !CV_SIMD256
#error "fast9_avx2.cpp: OpenCV's 256-bit intrinsics are not enabled"
#endif

namespace iraf_vo {
namespace fast9_avx2 {
#include "fast9_row.inl"
}  // namespace fast9_avx2
}  // namespace iraf_vo

#endif
