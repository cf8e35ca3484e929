#include "iraf_vo/features/orb_describer.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "iraf_vo/features/cell_grid.h"
#include "orb_describer_kernels.h"

namespace iraf_vo {

namespace {

// Furthest sample from a keypoint: |rotated offset| <= 15 sqrt 2 < 21.3 for the +-15 the pattern reader
// accepts (ORB's pattern: +-13), rounded, + 3 bytes of the 4-byte gather.
constexpr int kMaxReach = 21 + 3;
static_assert(kMaxReach + 3 <= kOrbPad + kEdgeThreshold, "samples and blur reads stay inside the padded buffer");

// `level` with its kOrbPad reflect-101 border, written into the top-left corner of *buffer (grown only when a
// level does not fit, so the pyramid's levels reuse level 0's buffer). Returns that padded view.
cv::Mat padLevel(const cv::Mat& level, cv::Mat* buffer) {
  const cv::Size whole(level.cols + 2 * kOrbPad, level.rows + 2 * kOrbPad);
  if (buffer->type() != CV_8UC1 || buffer->cols < whole.width || buffer->rows < whole.height)
    buffer->create(std::max(buffer->rows, whole.height), std::max(buffer->cols, whole.width), CV_8UC1);
  cv::Mat padded = (*buffer)(cv::Rect(cv::Point(0, 0), whole));
  cv::copyMakeBorder(level, padded, kOrbPad, kOrbPad, kOrbPad, kOrbPad, cv::BORDER_REFLECT_101);  // in place: same size
  return padded;
}

cv::Mat innerOf(const cv::Mat& padded) {
  return padded(cv::Rect(kOrbPad, kOrbPad, padded.cols - 2 * kOrbPad, padded.rows - 2 * kOrbPad));
}

// The 7 float taps OpenCV's GaussianBlur(7x7, sigma 2) filters a sub-matrix with.
const float* blurTaps() {
  static const cv::Mat k = cv::getGaussianKernel(7, 2, CV_32F);
  return k.ptr<float>();
}

// The same blur by orb_blur_avx2 (bytes equal to blurSubmatrixOpenCv's where it passed the start-up check).
cv::Mat blurSubmatrixSimd(const cv::Mat& level, cv::Mat* buffer, std::vector<float>* ring) {
  const cv::Mat padded = padLevel(level, buffer);
  ring->resize(static_cast<size_t>(8) * level.cols + 6);
  orb_blur_avx2::blurInPlace(padded.data, padded.step, kOrbPad, level.cols, level.rows, blurTaps(), ring->data());
  return innerOf(padded);
}

bool cpuHasAvx2(bool and_fma) {
#if defined(IRAF_VO_AVX2_KERNELS)
  return __builtin_cpu_supports("avx2") && (!and_fma || __builtin_cpu_supports("fma"));
#else
  (void)and_fma;
  return false;
#endif
}

// orb_blur_avx2 against OpenCV on random images of a few sizes: odd widths and a 7-px-wide one exercise the
// scalar tails (a 7-px row is all tail in both implementations).
bool simdBlurMatchesOpenCv() {
  if (!cpuHasAvx2(true) || !orb_blur_avx2::built()) return false;
  cv::RNG rng(0x0b1a5);
  cv::Mat padded_a, padded_b;
  std::vector<float> ring;
  for (const cv::Size& sz : {cv::Size(64, 48), cv::Size(203, 97), cv::Size(37, 41), cv::Size(7, 2000), cv::Size(752, 480)}) {
    cv::Mat img(sz, CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    if (cv::norm(blurSubmatrixOpenCv(img, &padded_a), blurSubmatrixSimd(img, &padded_b, &ring), cv::NORM_INF) != 0)
      return false;
  }
  return true;
}

// cv::ORB's sampling loop, one keypoint: pattern offsets rotated in float, rounded to the nearest pixel.
void describeScalar(const uint8_t* center, int step, float angle_deg, const OrbPattern& pattern, uint8_t* desc) {
  float a, b;
  orbRotation(angle_deg, &a, &b);
  auto sample = [&](float px, float py) {
    const float x = px * a - py * b, y = px * b + py * a;  // no contraction: CMake builds this file with it off
    return center[cvRound(y) * step + cvRound(x)];
  };
  for (int byte = 0; byte < 32; ++byte) {
    int v = 0;
    for (int bit = 0; bit < 8; ++bit) {
      const int k = 8 * byte + bit;
      v |= (sample(pattern.x0[k], pattern.y0[k]) < sample(pattern.x1[k], pattern.y1[k])) << bit;
    }
    desc[byte] = static_cast<uint8_t>(v);
  }
}

OrbDescriber::Kernel simdKernel() { return cpuHasAvx2(false) ? orb_describer_avx2::kernel() : nullptr; }

}  // namespace

cv::Mat blurSubmatrixOpenCv(const cv::Mat& level, cv::Mat* buffer) {
  cv::Mat inner = innerOf(padLevel(level, buffer));
  cv::GaussianBlur(inner, inner, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
  return inner;
}

namespace {

// The start-up check's input and cv::ORB's answer: random keypoints on a random image, their cv::ORB descriptors
// and the image blurred as cv::ORB blurs it. Computed once per process (every kernel and pattern is compared
// against the same reference).
struct KernelCheck {
  std::vector<cv::KeyPoint> kps;
  cv::Mat reference, padded, blurred;
  bool valid = false;
};

const KernelCheck& kernelCheck() {
  static const KernelCheck check = [] {
    KernelCheck c;
    cv::RNG rng(0x0b5e55ed);
    cv::Mat img(160, 200, CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    for (int i = 0; i < 400; ++i) {
      const float angle = i < 8 ? 45.f * i : rng.uniform(0.f, 360.f);  // the axes and diagonals, then random
      c.kps.emplace_back(cv::Point2f(static_cast<float>(rng.uniform(kEdgeThreshold, img.cols - kEdgeThreshold)),
                                     static_cast<float>(rng.uniform(kEdgeThreshold, img.rows - kEdgeThreshold))),
                         kOrbPatchSize, angle);
    }
    std::vector<cv::KeyPoint> ref_kps = c.kps;
    makeReferenceOrb()->compute(img, ref_kps, c.reference);
    c.valid = ref_kps.size() == c.kps.size();
    c.blurred = blurSubmatrixOpenCv(img, &c.padded);
    return c;
  }();
  return check;
}

}  // namespace

bool orbKernelMatchesOpenCv(bool simd, const OrbPattern& pattern) {
  const OrbDescriber::Kernel kernel = simd ? simdKernel() : describeScalar;
  if (!kernel || !pattern.valid()) return false;
  const KernelCheck& c = kernelCheck();
  if (!c.valid) return false;
  uint8_t desc[32];
  for (size_t i = 0; i < c.kps.size(); ++i) {
    kernel(c.blurred.ptr<uint8_t>(cvRound(c.kps[i].pt.y)) + cvRound(c.kps[i].pt.x), static_cast<int>(c.blurred.step),
           c.kps[i].angle, pattern, desc);
    if (std::memcmp(desc, c.reference.ptr<uint8_t>(static_cast<int>(i)), 32) != 0) return false;
  }
  return true;
}

OrbDescriber::OrbDescriber(bool use_simd) : orb_(makeReferenceOrb()) {
  const OrbPattern& pattern = orbPatternFromOpenCv();
  // Checked once per process and kernel (the pattern and OpenCV do not change while it runs).
  static const bool scalar_ok = orbKernelMatchesOpenCv(false, pattern);
  static const bool simd_ok = orbKernelMatchesOpenCv(true, pattern);
  static const bool simd_blur_ok = simdBlurMatchesOpenCv();
  if (use_simd && simd_ok) {
    kernel_ = simdKernel();
    simd_ = true;
  } else if (scalar_ok) {
    kernel_ = describeScalar;
  }
  simd_blur_ = use_simd && simd_blur_ok;
}

cv::Mat OrbDescriber::blurLikeOrb(const cv::Mat& level) {
  return simd_blur_ ? blurSubmatrixSimd(level, &padded_, &blur_rows_) : blurSubmatrixOpenCv(level, &padded_);
}

void OrbDescriber::compute(const cv::Mat& level, const std::vector<cv::KeyPoint>& kps, cv::Mat* descriptors) {
  if (level.empty() || level.type() != CV_8UC1)
    throw std::invalid_argument("OrbDescriber: expected a non-empty CV_8UC1 level image");
  for (size_t i = 0; i < kps.size(); ++i) {
    const int x = cvRound(kps[i].pt.x), y = cvRound(kps[i].pt.y);
    if (x < kEdgeThreshold || y < kEdgeThreshold || x >= level.cols - kEdgeThreshold ||
        y >= level.rows - kEdgeThreshold)
      throw std::invalid_argument("OrbDescriber: keypoint " + std::to_string(i) + " at (" + std::to_string(x) + ", " +
                                  std::to_string(y) + ") is closer than " + std::to_string(kEdgeThreshold) +
                                  " px to the border of the " + std::to_string(level.cols) + "x" +
                                  std::to_string(level.rows) + " level");
  }
  descriptors->create(static_cast<int>(kps.size()), 32, CV_8U);
  if (kps.empty()) return;
  if (!kernel_) {  // cv::ORB itself (one level = octave 0 of a one-level pyramid)
    fallback_kps_ = kps;
    for (cv::KeyPoint& k : fallback_kps_) k.octave = 0;
    cv::Mat d;
    orb_->compute(level, fallback_kps_, d);
    if (fallback_kps_.size() != kps.size()) throw std::logic_error("OrbDescriber: cv::ORB dropped keypoints");
    d.copyTo(*descriptors);
    return;
  }
  const cv::Mat blurred = blurLikeOrb(level);
  const OrbPattern& pattern = orbPatternFromOpenCv();
  const int step = static_cast<int>(blurred.step);
  for (size_t i = 0; i < kps.size(); ++i)
    kernel_(blurred.ptr<uint8_t>(cvRound(kps[i].pt.y)) + cvRound(kps[i].pt.x), step, kps[i].angle, pattern,
            descriptors->ptr<uint8_t>(static_cast<int>(i)));
}

}  // namespace iraf_vo
