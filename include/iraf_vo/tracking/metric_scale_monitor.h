// Whether a stereo map's metric scale is observed. ROS-free; tracking thread only.
//
// The right image measures depth only where the disparity is large enough: nearer than the close depth
// (focal x baseline / stereo_min_disparity_px, StereoMatcher::closeDepth; 9.6 m for a 0.10 m fisheye pair of
// 191 px, 25 m for EuRoC's pinholes). A pose resting on farther points alone carries the scale of their
// depths, which one stereo frame cannot measure (their disparity errors are as large as their disparities) and
// the map propagates from older keyframes: the scale then drifts as a monocular one does. The monitor
// averages, over the last stereo_scale_window_frames tracked frames, the pose inliers whose map point lies
// nearer than the close depth; below stereo_scale_min_close_inliers the scale is "weakly observed" (reported
// with the pose, the tracker keeps tracking). Measured: every simulated road with a scale error above 2 %
// averaged 1-7 such inliers per frame over some 10 frames, every passing one and EuRoC at least 17.
#pragma once

#include "iraf_vo/tracking/tracker_params.h"

#include <deque>

namespace iraf_vo {

class MetricScaleMonitor {
 public:
  explicit MetricScaleMonitor(const TrackerParams& params) : p_(params) {}

  /// A new metric map (or the monitor switched off): no history, not weak.
  void restart();
  /// A tracked frame's close inliers. Returns true when this frame changed weak().
  bool add(int close_inliers);
  /// The window is full and its mean is below stereo_scale_min_close_inliers.
  bool weak() const { return weak_; }
  /// Mean close inliers per frame over the window (-1 before the first frame).
  double mean() const;

 private:
  const TrackerParams& p_;
  std::deque<int> window_;
  long sum_ = 0;
  bool weak_ = false;
};

}  // namespace iraf_vo
