// Shared by the scalar and the AVX2 ORB sampling kernels (orb_descriptor.cpp, orb_descriptor_avx2.cpp).
#pragma once

#include <cmath>

namespace iraf_vo {

// cv::ORB's rotation of the pattern: the angle converted to radians in float, cos / sin in double, rounded
// to float (both kernels must get the same a and b).
inline void orbRotation(float angle_deg, float* a, float* b) {
  const float angle = angle_deg * static_cast<float>(3.14159265358979323846 / 180.f);
  *a = static_cast<float>(std::cos(static_cast<double>(angle)));
  *b = static_cast<float>(std::sin(static_cast<double>(angle)));
}

}  // namespace iraf_vo
