// Rotated-BRIEF (ORB) descriptors of keypoints on one pyramid level, byte for byte those of
// cv::ORB::compute (patch 31, WTA_K 2, 32 bytes), without cv::ORB's per-call pyramid copy, with the sampling
// loop in AVX2 and ORB's blur in AVX2 + FMA where the CPU has them. ROS-free.
//
// OpenCV does not expose ORB's learned sampling pattern, so it is read from cv::ORB once per process
// (orb_pattern.cpp). Every kernel is then checked against cv::ORB / cv::GaussianBlur on random images; a
// kernel that differs in one byte (another OpenCV, another compiler's float contraction) is not used, down
// to calling cv::ORB itself.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

namespace iraf_vo {

/// ORB's patch size (the keypoint size of level 0 and the descriptor's sampling window).
constexpr int kOrbPatchSize = 31;

/// ORB's sampling pattern: pair k compares the blurred image at p0[k] and p1[k] (offsets from the
/// keypoint at angle 0); bit k of the descriptor (byte k / 8, bit k % 8) is I(p0) < I(p1).
struct OrbPattern {
  std::vector<cv::Point> p0, p1;  // 256 each; empty when reading it from cv::ORB failed
  float x0[256], y0[256], x1[256], y1[256];  // the same as floats, for the sampling kernels
  bool valid() const { return p0.size() == 256 && p1.size() == 256; }
};

/// The cv::ORB our descriptors equal: patch 31, WTA_K 2, edge threshold 19, one level.
cv::Ptr<cv::ORB> makeReferenceOrb();

/// Reads the pattern from `orb` (patch size 31, WTA_K 2) by describing probe images; false when the
/// probe's bits do not single out one position pair for every bit.
bool readOrbPattern(const cv::Ptr<cv::ORB>& orb, OrbPattern* pattern);

/// The pattern read from makeReferenceOrb() (once per process, thread-safe).
const OrbPattern& orbPatternFromOpenCv();

/// True when the sampling kernel (scalar, or the AVX2 one with simd = true, where built and supported) with
/// `pattern` gives cv::ORB's bytes on the start-up check's random image and keypoints.
bool orbKernelMatchesOpenCv(bool simd, const OrbPattern& pattern);

/// One instance per thread: compute() and blurLikeOrb() reuse internal buffers (not reentrant).
class OrbDescriber {
 public:
  /// use_simd = false keeps the scalar kernel and OpenCV's blur even where the CPU has AVX2 (tests compare).
  explicit OrbDescriber(bool use_simd = true);

  /// Descriptors (rows of 32 bytes, CV_8U) of `kps` on `level` (CV_8UC1): positions in level pixels,
  /// angle in degrees, every keypoint >= 19 px (ORB's edge threshold) from the border; throws
  /// std::invalid_argument naming the keypoint otherwise.
  void compute(const cv::Mat& level, const std::vector<cv::KeyPoint>& kps, cv::Mat* descriptors);

  /// True when the pattern could not be read or no kernel equalled cv::ORB at the start: compute() then
  /// calls cv::ORB::compute.
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

  /// Sampling kernel: the descriptor of the keypoint at `center` (a pixel of the blurred level, `step`
  /// bytes per row) at angle `angle_deg`, into desc[0..31].
  using Kernel = void (*)(const uint8_t* center, int step, float angle_deg, const OrbPattern& pattern, uint8_t* desc);

 private:
  cv::Ptr<cv::ORB> orb_;  // the fallback
  Kernel kernel_ = nullptr;
  bool simd_ = false, simd_blur_ = false;
  cv::Mat padded_;  // padded level, sized for the largest level seen (level 0): no allocation per level
  std::vector<float> blur_rows_;
  std::vector<cv::KeyPoint> fallback_kps_;
};

}  // namespace iraf_vo
