// Included first by the files CMake compiles with -mavx2 (fast9_avx2.cpp, gradient_avx2.cpp): OpenCV's universal
// intrinsics in their AVX2 form (namespace cv::hal_AVX2), as OpenCV's own dispatched code declares them. A file
// built with -mf16c / -mfma too defines CV_FP16 / CV_FMA3 before including this.
#pragma once

#define CV_CPU_DISPATCH_MODE AVX2
#include <immintrin.h>
#define CV_SSE3 1
#define CV_SSSE3 1
#define CV_SSE4_1 1
#define CV_SSE4_2 1
#define CV_POPCNT 1
#define CV_AVX 1
#define CV_AVX2 1
#include <opencv2/core/hal/intrin.hpp>
