#include "iraf_vo/features/orb_descriptor.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "iraf_vo/features/cell_grid.h"
#include "orb_descriptor_kernel.h"

namespace iraf_vo {

namespace {

constexpr int kPatchSize = 31;
// cv::ORB's border around a level: max(edge threshold, rotated half patch ceil(15 sqrt 2) = 22, 4) + 1.
constexpr int kPad = 23;
constexpr int kMaxReach = 18;  // |rotated pattern offset| <= 13 sqrt 2 < 18.5, rounded

cv::Ptr<cv::ORB> makeOrb() {
  return cv::ORB::create(500, 1.2f, 1, kEdgeThreshold, 0, 2, cv::ORB::FAST_SCORE, kPatchSize, 20);
}

// The blur cv::ORB applies before sampling: the level inside a reflect-101 border, blurred in place as a
// sub-matrix (OpenCV rounds a sub-matrix's blur differently from a whole image's, so this is not
// GaussianBlur(level)).
cv::Mat blurSubmatrix(const cv::Mat& level, cv::Mat* padded) {
  cv::copyMakeBorder(level, *padded, kPad, kPad, kPad, kPad, cv::BORDER_REFLECT_101);
  cv::Mat inner = (*padded)(cv::Rect(kPad, kPad, level.cols, level.rows));
  cv::GaussianBlur(inner, inner, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
  return inner;
}

// The 7 float taps OpenCV's GaussianBlur(7x7, sigma 2) filters a sub-matrix with.
const float* blurTaps() {
  static const cv::Mat k = cv::getGaussianKernel(7, 2, CV_32F);
  return k.ptr<float>();
}

// The same blur by orb_blur_avx2 (bytes equal to blurSubmatrix's where it passed the start-up check).
cv::Mat blurSubmatrixSimd(const cv::Mat& level, cv::Mat* padded, std::vector<float>* ring) {
  cv::copyMakeBorder(level, *padded, kPad, kPad, kPad, kPad, cv::BORDER_REFLECT_101);
  orb_blur_avx2::blurInPlace(padded, kPad, level.cols, level.rows, blurTaps(), ring);
  return (*padded)(cv::Rect(kPad, kPad, level.cols, level.rows));
}

// orb_blur_avx2 against OpenCV on random images of a few sizes (odd widths: the scalar tails too).
bool simdBlurMatchesOpenCv() {
  if (!orb_blur_avx2::built() || !__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return false;
  cv::RNG rng(0x0b1a5);
  cv::Mat padded_a, padded_b;
  std::vector<float> ring;
  for (const cv::Size& sz : {cv::Size(64, 48), cv::Size(203, 97), cv::Size(37, 41), cv::Size(752, 480)}) {
    cv::Mat img(sz, CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    if (cv::norm(blurSubmatrix(img, &padded_a), blurSubmatrixSimd(img, &padded_b, &ring), cv::NORM_INF) != 0) return false;
  }
  return true;
}

// ---- Reading the pattern from cv::ORB -------------------------------------------------------------
// A dot image (one pixel of value `dot` on background `bg`) blurs into a 7x7 bump. cv::ORB describes it
// from keypoints at angle 0 placed at every offset d in [-kProbe, kProbe]^2 from the dot. Bit k from the
// keypoint at offset d compares the blurred image at dot + p0[k] - d and dot + p1[k] - d, so with a bright
// dot it is set only for d near p1[k] (where the bump is higher at p1 - d than at p0 - d) and with a dark
// dot only for d near p0[k]. Each pair is then the one (p0, p1) whose predicted bits equal both probes'
// bits at every offset where either bump reaches.
constexpr int kProbe = 18;                 // offsets probed
constexpr int kSide = 2 * kProbe + 1;
constexpr int kMaxCoord = kProbe - 3;      // pattern coordinates that can be told apart: +-15 (ORB's: +-13)
constexpr int kDot = 48;                   // dot position in the 97 x 97 probe image

struct Probe {
  cv::Mat blurred;                 // the probe image as ORB blurs it
  std::vector<uint8_t> bits;       // [k][dy][dx]: bit k of the keypoint at offset (dx, dy)
  bool bit(int k, cv::Point d) const { return bits[(k * kSide + d.y + kProbe) * kSide + d.x + kProbe] != 0; }
  int value(cv::Point offset_from_dot) const { return blurred.at<uint8_t>(kDot + offset_from_dot.y, kDot + offset_from_dot.x); }
};

bool runProbe(const cv::Ptr<cv::ORB>& orb, bool bright, Probe* probe) {
  cv::Mat img(2 * kDot + 1, 2 * kDot + 1, CV_8U, cv::Scalar(bright ? 0 : 255));
  img.at<uint8_t>(kDot, kDot) = bright ? 255 : 0;
  cv::Mat padded;
  probe->blurred = blurSubmatrix(img, &padded).clone();
  std::vector<cv::KeyPoint> kps;
  for (int dy = -kProbe; dy <= kProbe; ++dy)
    for (int dx = -kProbe; dx <= kProbe; ++dx)
      kps.emplace_back(cv::Point2f(static_cast<float>(kDot - dx), static_cast<float>(kDot - dy)), kPatchSize, 0.f);
  const size_t n = kps.size();
  cv::Mat desc;
  orb->compute(img, kps, desc);
  if (kps.size() != n || desc.rows != static_cast<int>(n) || desc.cols != 32) return false;
  probe->bits.assign(256 * n, 0);
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 256; ++k) probe->bits[k * n + i] = (desc.at<uint8_t>(static_cast<int>(i), k / 8) >> (k % 8)) & 1;
  return true;
}

bool within3(cv::Point a, cv::Point b) { return std::abs(a.x - b.x) <= 3 && std::abs(a.y - b.y) <= 3; }

// Positions p whose 7x7 box holds every offset at which bit k is set in `probe` (the bump around p).
std::vector<cv::Point> boxCandidates(const Probe& probe, int k) {
  std::vector<cv::Point> set;
  for (int dy = -kProbe; dy <= kProbe; ++dy)
    for (int dx = -kProbe; dx <= kProbe; ++dx)
      if (probe.bit(k, {dx, dy})) set.emplace_back(dx, dy);
  std::vector<cv::Point> out;
  if (set.empty()) return out;
  // Inside every box = within 3 of the set's bounding box corners.
  const cv::Rect box = cv::boundingRect(set);
  for (int y = std::max(-kMaxCoord, box.br().y - 1 - 3); y <= std::min(kMaxCoord, box.y + 3); ++y)
    for (int x = std::max(-kMaxCoord, box.br().x - 1 - 3); x <= std::min(kMaxCoord, box.x + 3); ++x) out.emplace_back(x, y);
  return out;
}

bool explains(const Probe& bright, const Probe& dark, int k, cv::Point p0, cv::Point p1) {
  for (int dy = -kProbe; dy <= kProbe; ++dy)
    for (int dx = -kProbe; dx <= kProbe; ++dx) {
      const cv::Point d(dx, dy);
      if (!within3(d, p0) && !within3(d, p1)) continue;  // both on the background: bit 0, as the boxes imply
      const bool b = bright.value(p0 - d) < bright.value(p1 - d), t = dark.value(p0 - d) < dark.value(p1 - d);
      if (b != bright.bit(k, d) || t != dark.bit(k, d)) return false;
    }
  return true;
}

}  // namespace

bool readOrbPattern(const cv::Ptr<cv::ORB>& orb, OrbPattern* pattern) {
  pattern->p0.clear();
  pattern->p1.clear();
  Probe bright, dark;
  if (!runProbe(orb, true, &bright) || !runProbe(orb, false, &dark)) return false;
  std::vector<cv::Point> p0s, p1s;
  for (int k = 0; k < 256; ++k) {
    int solutions = 0;
    cv::Point s0, s1;
    for (const cv::Point& p1 : boxCandidates(bright, k))
      for (const cv::Point& p0 : boxCandidates(dark, k))
        if (p0 != p1 && explains(bright, dark, k, p0, p1)) {
          ++solutions;
          s0 = p0;
          s1 = p1;
        }
    if (solutions != 1) return false;
    p0s.push_back(s0);
    p1s.push_back(s1);
  }
  pattern->p0 = p0s;
  pattern->p1 = p1s;
  for (int k = 0; k < 256; ++k) {
    pattern->x0[k] = static_cast<float>(p0s[k].x);
    pattern->y0[k] = static_cast<float>(p0s[k].y);
    pattern->x1[k] = static_cast<float>(p1s[k].x);
    pattern->y1[k] = static_cast<float>(p1s[k].y);
  }
  return true;
}

const OrbPattern& orbPatternFromOpenCv() {
  static const OrbPattern pattern = [] {
    OrbPattern p;
    readOrbPattern(makeOrb(), &p);
    return p;
  }();
  return pattern;
}

namespace {

// cv::ORB's sampling loop, one keypoint: pattern offsets rotated in float, rounded to the nearest pixel.
void describeScalar(const uint8_t* center, int step, float angle_deg, const OrbPattern& pattern, uint8_t* desc) {
  float a, b;
  orbRotation(angle_deg, &a, &b);
  auto sample = [&](float px, float py) {
    const float x = px * a - py * b, y = px * b + py * a;
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

// Our descriptors of random keypoints on a random image against cv::ORB's, with `kernel`.
bool kernelMatchesOpenCv(OrbDescriptor::Kernel kernel, const cv::Ptr<cv::ORB>& orb, const OrbPattern& pattern) {
  if (!kernel || !pattern.valid()) return false;
  cv::RNG rng(0x0b5e55ed);
  cv::Mat img(160, 200, CV_8U);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 400; ++i) {
    const float angle = i < 8 ? 45.f * i : rng.uniform(0.f, 360.f);  // the axes and diagonals, then random
    kps.emplace_back(cv::Point2f(static_cast<float>(rng.uniform(kEdgeThreshold, img.cols - kEdgeThreshold)),
                                 static_cast<float>(rng.uniform(kEdgeThreshold, img.rows - kEdgeThreshold))),
                     kPatchSize, angle);
  }
  std::vector<cv::KeyPoint> ref_kps = kps;
  cv::Mat ref;
  orb->compute(img, ref_kps, ref);
  if (ref_kps.size() != kps.size()) return false;
  cv::Mat padded;
  const cv::Mat blurred = blurSubmatrix(img, &padded);
  uint8_t desc[32];
  for (size_t i = 0; i < kps.size(); ++i) {
    kernel(blurred.ptr<uint8_t>(cvRound(kps[i].pt.y)) + cvRound(kps[i].pt.x), static_cast<int>(blurred.step),
           kps[i].angle, pattern, desc);
    if (std::memcmp(desc, ref.ptr<uint8_t>(static_cast<int>(i)), 32) != 0) return false;
  }
  return true;
}

}  // namespace

OrbDescriptor::OrbDescriptor(bool use_simd) : orb_(makeOrb()) {
  const OrbPattern& pattern = orbPatternFromOpenCv();
  // Checked once per process and kernel (the pattern and OpenCV do not change while it runs).
  static const bool scalar_ok = kernelMatchesOpenCv(describeScalar, makeOrb(), pattern);
  static const Kernel simd = __builtin_cpu_supports("avx2") ? orb_descriptor_avx2::kernel() : nullptr;
  static const bool simd_ok = kernelMatchesOpenCv(simd, makeOrb(), pattern);
  static const bool simd_blur_ok = simdBlurMatchesOpenCv();
  if (use_simd && simd_ok) {
    kernel_ = simd;
    simd_ = true;
  } else if (scalar_ok) {
    kernel_ = describeScalar;
  }
  simd_blur_ = use_simd && simd_blur_ok;
}

cv::Mat OrbDescriptor::blurLikeOrb(const cv::Mat& level) {
  return simd_blur_ ? blurSubmatrixSimd(level, &padded_, &blur_rows_) : blurSubmatrix(level, &padded_);
}

void OrbDescriptor::compute(const cv::Mat& level, const std::vector<cv::KeyPoint>& kps, cv::Mat* descriptors) {
  if (level.empty() || level.type() != CV_8UC1)
    throw std::invalid_argument("OrbDescriptor: expected a non-empty CV_8UC1 level image");
  for (size_t i = 0; i < kps.size(); ++i) {
    const int x = cvRound(kps[i].pt.x), y = cvRound(kps[i].pt.y);
    if (x < kEdgeThreshold || y < kEdgeThreshold || x >= level.cols - kEdgeThreshold ||
        y >= level.rows - kEdgeThreshold)
      throw std::invalid_argument("OrbDescriptor: keypoint " + std::to_string(i) + " at (" + std::to_string(x) + ", " +
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
    if (fallback_kps_.size() != kps.size()) throw std::logic_error("OrbDescriptor: cv::ORB dropped keypoints");
    d.copyTo(*descriptors);
    return;
  }
  static_assert(kMaxReach + 3 < kPad + kEdgeThreshold, "samples and blur stay inside the padded buffer");
  const cv::Mat blurred = blurLikeOrb(level);
  const OrbPattern& pattern = orbPatternFromOpenCv();
  const int step = static_cast<int>(blurred.step);
  for (size_t i = 0; i < kps.size(); ++i)
    kernel_(blurred.ptr<uint8_t>(cvRound(kps[i].pt.y)) + cvRound(kps[i].pt.x), step, kps[i].angle, pattern,
            descriptors->ptr<uint8_t>(static_cast<int>(i)));
}

}  // namespace iraf_vo
