// Reading ORB's sampling pattern from cv::ORB (orb_describer.h: readOrbPattern). ROS-free.
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "iraf_vo/features/cell_grid.h"
#include "orb_describer_kernels.h"

namespace iraf_vo {

cv::Ptr<cv::ORB> makeReferenceOrb() {
  return cv::ORB::create(500, 1.2f, 1, kEdgeThreshold, 0, 2, cv::ORB::FAST_SCORE, kOrbPatchSize, 20);
}

namespace {

// A dot image (one pixel of 255 on 0, or of 0 on 255) blurs into a 7x7 bump. cv::ORB describes it
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
  probe->blurred = blurSubmatrixOpenCv(img, &padded).clone();
  std::vector<cv::KeyPoint> kps;
  for (int dy = -kProbe; dy <= kProbe; ++dy)
    for (int dx = -kProbe; dx <= kProbe; ++dx)
      kps.emplace_back(cv::Point2f(static_cast<float>(kDot - dx), static_cast<float>(kDot - dy)), kOrbPatchSize, 0.f);
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
    readOrbPattern(makeReferenceOrb(), &p);
    return p;
  }();
  return pattern;
}

}  // namespace iraf_vo
