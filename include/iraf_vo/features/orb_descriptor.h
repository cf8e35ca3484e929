// Rotated-BRIEF (ORB) descriptors of keypoints on one pyramid level, byte for byte those of
// cv::ORB::compute (patch 31, WTA_K 2, 32 bytes), without cv::ORB's per-call pyramid copy and with the
// sampling loop in AVX2 where the CPU has it. ROS-free.
//
// OpenCV does not expose ORB's learned sampling pattern, so it is read from cv::ORB once per process:
// cv::ORB describes a dot image from keypoints at every offset around the dot, and each of the 256 point
// pairs is the one position pair that explains all of those bits (see orb_descriptor.cpp). The whole
// computation is then checked against cv::ORB on a random image at random angles; if a single byte differs
// (another OpenCV, another compiler's float contraction) every call goes through cv::ORB instead.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

namespace iraf_vo {

/// ORB's sampling pattern: pair k compares the blurred image at p0[k] and p1[k] (offsets from the
/// keypoint at angle 0); bit k of the descriptor (byte k / 8, bit k % 8) is I(p0) < I(p1).
struct OrbPattern {
  std::vector<cv::Point> p0, p1;  // 256 each; empty when reading it from cv::ORB failed
  alignas(32) float x0[256], y0[256], x1[256], y1[256];  // the same as floats, for the SIMD loop
  bool valid() const { return p0.size() == 256 && p1.size() == 256; }
};

/// The pattern read from cv::ORB (once per process, thread-safe).
const OrbPattern& orbPatternFromOpenCv();

/// Reads the pattern from `orb` (patch size 31, WTA_K 2) by describing probe images; false when the
/// probe's bits do not single out one position pair for every bit.
bool readOrbPattern(const cv::Ptr<cv::ORB>& orb, OrbPattern* pattern);

class OrbDescriptor {
 public:
  /// Sampling kernel: the descriptor of the keypoint at `center` (a pixel of the blurred level, `step`
  /// bytes per row) at angle `angle_deg`, into desc[0..31].
  using Kernel = void (*)(const uint8_t* center, int step, float angle_deg, const OrbPattern& pattern, uint8_t* desc);

  /// use_simd = false keeps the scalar kernel even where the CPU has AVX2 (tests compare the two).
  explicit OrbDescriptor(bool use_simd = true);

  /// Descriptors (rows of 32 bytes, CV_8U) of `kps` on `level` (CV_8UC1): positions in level pixels,
  /// angle in degrees, every keypoint >= 19 px (ORB's edge threshold) from the border; throws
  /// std::invalid_argument naming the keypoint otherwise.
  void compute(const cv::Mat& level, const std::vector<cv::KeyPoint>& kps, cv::Mat* descriptors);

  /// True when the pattern could not be read or our descriptors differed from cv::ORB's at the start:
  /// compute() then calls cv::ORB::compute.
  bool usesOpenCvFallback() const { return kernel_ == nullptr; }
  /// True when compute() samples with the AVX2 kernel.
  bool usesSimd() const { return simd_; }

  /// True when the blur runs in our AVX2 + FMA loop (it equalled OpenCV's at start-up), false when
  /// through cv::GaussianBlur.
  bool usesSimdBlur() const { return simd_blur_; }

  /// ORB's blur, exactly: `level` copied into a reflect-101 border and blurred in place (7x7, sigma 2)
  /// as a sub-matrix, as cv::ORB does (OpenCV blurs a sub-matrix by another rounding than a whole image).
  /// Returns the blurred level (a view into an internal buffer, valid until the next call).
  cv::Mat blurLikeOrb(const cv::Mat& level);

 private:
  cv::Ptr<cv::ORB> orb_;  // the reference, and the fallback
  Kernel kernel_ = nullptr;
  bool simd_ = false, simd_blur_ = false;
  cv::Mat padded_;
  std::vector<float> blur_rows_;
  std::vector<cv::KeyPoint> fallback_kps_;
};

namespace orb_descriptor_avx2 {
/// The AVX2 sampling kernel (orb_descriptor_avx2.cpp); nullptr when not built.
OrbDescriptor::Kernel kernel();
}  // namespace orb_descriptor_avx2

namespace orb_blur_avx2 {
/// True when orb_blur_avx2.cpp was built with AVX2 + FMA.
bool built();
/// Blurs the cols x rows block at (pad, pad) of `padded` in place with the 7-tap kernel k (row pass, then
/// column pass; `ring` is scratch). Needs >= 3 px of border and AVX2 + FMA.
void blurInPlace(cv::Mat* padded, int pad, int cols, int rows, const float* k, std::vector<float>* ring);
}  // namespace orb_blur_avx2

}  // namespace iraf_vo
