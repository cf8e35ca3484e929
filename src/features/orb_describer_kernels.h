// The kernels behind OrbDescriber (orb_describer.cpp): shared rotation, and the AVX2 files' entry points.
#pragma once

#include <opencv2/core.hpp>

#include <cmath>
#include <cstdint>

#include "iraf_vo/features/orb_describer.h"

namespace iraf_vo {

// cv::ORB's border around a level: max(edge threshold 19, rotated half patch ceil(15 sqrt 2) = 22, 4) + 1.
constexpr int kOrbPad = 23;

/// The blur cv::ORB applies before sampling: `level` inside a kOrbPad reflect-101 border (written into the
/// reused *buffer), blurred in place as a sub-matrix by cv::GaussianBlur (7x7, sigma 2). Returns the blurred
/// level (a view of *buffer).
cv::Mat blurSubmatrixOpenCv(const cv::Mat& level, cv::Mat* buffer);

// cv::ORB's rotation of the pattern: the angle converted to radians in float, cos / sin of that float (OpenCV
// 4.6 calls sincosf; the double functions rounded to float differ by one ulp at ~2.6 % of angles). Every
// kernel must get the same a and b.
inline void orbRotation(float angle_deg, float* a, float* b) {
  const float angle = angle_deg * static_cast<float>(3.14159265358979323846 / 180.f);
  *a = std::cos(angle);
  *b = std::sin(angle);
}

namespace orb_describer_avx2 {
/// The AVX2 sampling kernel (orb_describer_avx2.cpp); nullptr when not built.
OrbDescriber::Kernel kernel();
}  // namespace orb_describer_avx2

namespace orb_blur_avx2 {
/// True when orb_blur_avx2.cpp was built with AVX2 + FMA.
bool built();
/// Blurs the cols x rows block at (pad, pad) of the CV_8U `padded` in place with the 7-tap kernel k (row
/// pass, then column pass). `ring`: scratch of >= 8 cols + 6 floats. Needs >= 3 px of border, AVX2 + FMA.
void blurInPlace(uint8_t* padded, size_t step, int pad, int cols, int rows, const float* k, float* ring);
}  // namespace orb_blur_avx2

}  // namespace iraf_vo
