// The right image of the frame being tracked (stereo tracker, tracking thread). The left-right matching runs only
// on the frames that use it: the stereo initialization and a new keyframe (its stereo points and right
// observations for the local BA); the other frames are posed on the left image against the metric map. The right
// features may be computed on demand too (Tracker::track with a RightFeatures function), so that a tracked frame
// that becomes no keyframe costs neither the right front-end nor the matcher. ROS-free.
#pragma once

#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/stereo_matcher.h"
#include "iraf_vo/tracking/tracker_params.h"

#include <functional>
#include <vector>

namespace iraf_vo {

/// The right image's features, computed when called (at most once per frame).
using RightFeatures = std::function<FeatureFrame()>;

class StereoFrame {
 public:
  /// rig and params must outlive it.
  StereoFrame(const StereoRig& rig, const TrackerParams& params) : matcher_(rig, params) {}

  /// A new frame. has_right false: no right image (features is not called). Returns true when this frame starts
  /// a run of frames without a right image.
  /// left_image: the left features' image (FeatureFrame::image; empty: no sub-pixel refinement).
  bool begin(bool has_right, RightFeatures features, const cv::Mat& left_image = cv::Mat());
  bool hasRight() const { return has_right_; }
  /// This frame's checked left-right matches, matched at the first call (fills cur->right_obs); empty without a
  /// right image or with unusable right features. *ms: the time spent matching now (0 when already done).
  const std::vector<StereoMatch>& matches(Frame* cur, double* ms);
  /// Whether matches() ran on this frame.
  bool matched() const { return matched_; }
  /// Matches farther than this are far ones (StereoMatcher::closeDepth).
  double closeDepth() const { return matcher_.closeDepth(); }

 private:
  StereoMatcher matcher_;
  RightFeatures features_;
  cv::Mat left_image_;
  bool has_right_ = false;
  bool last_missing_ = false;
  bool matched_ = false;
  std::vector<StereoMatch> matches_;
};

}  // namespace iraf_vo
