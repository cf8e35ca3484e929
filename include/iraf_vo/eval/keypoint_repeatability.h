// Front-end consistency between two images of the same scene: keypoint repeatability (a keypoint of image A is
// re-detected in image B within a radius of where the scene point went) and the descriptor distance of those true
// matches. Where the point went comes from outside (identity for two exposures of one image, optical flow on a
// clean reference, a homography, a simulator's depth and pose). ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "iraf_vo/features/feature_frame.h"

namespace iraf_vo {

/// Hamming distance at or below which ORB-SLAM's projection search accepts a match (ORBmatcher::TH_LOW).
constexpr int kOrbMatchHamming = 50;

struct RepeatabilityStats {
  int keypoints_a = 0, keypoints_b = 0;
  int reference = 0;        // keypoints of A with a valid prediction inside B's detection area
  int repeated = 0;         // ... with a keypoint of B within the radius of the prediction
  int matched = 0;          // repeated, and the descriptor distance of the pair <= kOrbMatchHamming
  double hamming_sum = 0.0; // descriptor distances of the repeated pairs (the nearest B keypoint), summed

  double repeatability() const { return reference > 0 ? static_cast<double>(repeated) / reference : 0.0; }
  double matchedShare() const { return reference > 0 ? static_cast<double>(matched) / reference : 0.0; }
  double meanHamming() const { return repeated > 0 ? hamming_sum / repeated : 0.0; }
  /// Adds another pair's counts (pooled statistics over a sequence).
  void add(const RepeatabilityStats& o);
};

/// For every keypoint i of `a` with valid[i] != 0 whose prediction predicted[i] (B's level-0 pixels) lies inside
/// `area`: is a keypoint of `b` within radius_px of it whose pyramid level differs by at most max_octave_gap (< 0:
/// any level; ORB-SLAM's projection search allows 1), and how far apart are the descriptors of the nearest one.
/// predicted / valid have a.keypoints.size() entries (empty = identity: every keypoint stays put / all valid).
RepeatabilityStats measureRepeatability(const FeatureFrame& a, const std::vector<cv::Point2f>& predicted,
                                        const std::vector<uint8_t>& valid, const FeatureFrame& b,
                                        const cv::Rect2f& area, double radius_px, int max_octave_gap = 1);

/// Where the feature stage can place level-0 keypoints in a width x height image (kEdgeThreshold from each border).
cv::Rect2f detectionArea(int width, int height);

}  // namespace iraf_vo
