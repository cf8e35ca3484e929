#include "iraf_vo/eval/keypoint_repeatability.h"

#include <algorithm>
#include <cmath>

#include "iraf_vo/features/cell_grid.h"

namespace iraf_vo {

void RepeatabilityStats::add(const RepeatabilityStats& o) {
  keypoints_a += o.keypoints_a;
  keypoints_b += o.keypoints_b;
  reference += o.reference;
  repeated += o.repeated;
  matched += o.matched;
  hamming_sum += o.hamming_sum;
}

cv::Rect2f detectionArea(int width, int height) {
  const float e = static_cast<float>(kEdgeThreshold);
  return cv::Rect2f(e, e, std::max(0.f, width - 2 * e), std::max(0.f, height - 2 * e));
}

namespace {

// B's keypoints bucketed in square cells of the search radius: a query visits the 3 x 3 cells around its own.
class KeypointBuckets {
 public:
  KeypointBuckets(const std::vector<cv::KeyPoint>& kps, float cell) : kps_(kps), cell_(std::max(cell, 1.f)) {
    float max_x = 1.f, max_y = 1.f;
    for (const cv::KeyPoint& k : kps) {
      max_x = std::max(max_x, k.pt.x);
      max_y = std::max(max_y, k.pt.y);
    }
    cols_ = static_cast<int>(max_x / cell_) + 1;
    rows_ = static_cast<int>(max_y / cell_) + 1;
    buckets_.resize(static_cast<size_t>(cols_) * rows_);
    for (size_t i = 0; i < kps.size(); ++i)
      if (kps[i].pt.x >= 0 && kps[i].pt.y >= 0) buckets_[bucketOf(kps[i].pt)].push_back(static_cast<int>(i));
  }

  /// Index of the keypoint nearest to p within radius whose octave is within max_gap of `octave` (max_gap < 0: any;
  /// ties: the lower index), or -1.
  int nearest(const cv::Point2f& p, float radius, int octave, int max_gap) const {
    const int cx = static_cast<int>(std::floor(p.x / cell_)), cy = static_cast<int>(std::floor(p.y / cell_));
    const float r2 = radius * radius;
    int best = -1;
    float best_d2 = 0.f;
    for (int y = std::max(0, cy - 1); y <= std::min(rows_ - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(cols_ - 1, cx + 1); ++x)
        for (int i : buckets_[static_cast<size_t>(y) * cols_ + x]) {
          if (max_gap >= 0 && std::abs(kps_[i].octave - octave) > max_gap) continue;
          const cv::Point2f d = kps_[i].pt - p;
          const float d2 = d.x * d.x + d.y * d.y;
          if (d2 > r2) continue;
          if (best < 0 || d2 < best_d2 || (d2 == best_d2 && i < best)) {
            best = i;
            best_d2 = d2;
          }
        }
    return best;
  }

 private:
  size_t bucketOf(const cv::Point2f& p) const {
    return static_cast<size_t>(static_cast<int>(p.y / cell_)) * cols_ + static_cast<int>(p.x / cell_);
  }
  const std::vector<cv::KeyPoint>& kps_;
  float cell_;
  int cols_ = 1, rows_ = 1;
  std::vector<std::vector<int>> buckets_;
};

}  // namespace

RepeatabilityStats measureRepeatability(const FeatureFrame& a, const std::vector<cv::Point2f>& predicted,
                                        const std::vector<uint8_t>& valid, const FeatureFrame& b,
                                        const cv::Rect2f& area, double radius_px, int max_octave_gap) {
  CV_Assert(predicted.empty() || predicted.size() == a.keypoints.size());
  CV_Assert(valid.empty() || valid.size() == a.keypoints.size());
  RepeatabilityStats st;
  st.keypoints_a = static_cast<int>(a.keypoints.size());
  st.keypoints_b = static_cast<int>(b.keypoints.size());
  const float radius = static_cast<float>(radius_px);
  const KeypointBuckets buckets(b.keypoints, radius);
  const bool describe = a.descriptors.rows == st.keypoints_a && b.descriptors.rows == st.keypoints_b;
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    if (!valid.empty() && !valid[i]) continue;
    const cv::Point2f p = predicted.empty() ? a.keypoints[i].pt : predicted[i];
    if (!area.contains(p)) continue;
    ++st.reference;
    const int j = buckets.nearest(p, radius, a.keypoints[i].octave, max_octave_gap);
    if (j < 0) continue;
    ++st.repeated;
    if (!describe) continue;
    const double h = cv::norm(a.descriptors.row(static_cast<int>(i)), b.descriptors.row(j), cv::NORM_HAMMING);
    st.hamming_sum += h;
    st.matched += h <= kOrbMatchHamming;
  }
  return st;
}

}  // namespace iraf_vo
