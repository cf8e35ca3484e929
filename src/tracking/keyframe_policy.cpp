#include "iraf_vo/tracking/keyframe_policy.h"

#include <algorithm>
#include <cmath>

namespace iraf_vo {

bool needNewKeyframe(const KeyframeCandidate& c, const TrackerParams& p) {
  if (c.frames_since_keyframe < p.min_frames_between_keyframes) return false;
  // A thin near map running out (forward motion, the few near points leaving the view): no mapping wait, or the
  // next keyframe comes after the pose has been taken from far points alone, whose depth does not fix the step.
  const bool losing_close = c.reference_close >= kMinClosePoints && c.close_tracked < p.keyframe_close_ratio * c.reference_close;
  const bool mapping_idle = c.frames_since_keyframe >= p.mapping_busy_frames || losing_close;
  const bool losing_map = c.inliers < p.keyframe_min_tracked;
  const bool timeout = c.frames_since_keyframe >= p.max_frames_between_keyframes;
  const bool few_tracked = c.inliers < p.keyframe_tracked_ratio * c.reference_tracked && (timeout || mapping_idle);
  const bool timeout_and_changed = timeout && c.inliers < 0.98 * c.reference_tracked;
  const bool stereo_needs_close = c.stereo_close_tracked >= 0 && c.stereo_close_tracked < kStereoCloseTracked &&
                                  c.stereo_close_untracked_share > kStereoCloseUntrackedShare;
  const bool forward_losing = c.forward && c.inliers < c.reference_tracked;
  return losing_map || forward_losing || few_tracked || timeout_and_changed || stereo_needs_close;
}

bool movesAlongOpticalAxis(const Eigen::Vector3d& t, double max_deg) {
  const double n = t.norm();
  return max_deg > 0.0 && n > 0.0 && std::abs(t.z()) >= std::cos(max_deg * M_PI / 180.0) * n;
}

void ForwardMotionWindow::add(bool forward, int frames) {
  frames = std::max(1, frames);
  recent_.push_back(forward);
  forward_count_ += forward ? 1 : 0;
  while (static_cast<int>(recent_.size()) > frames) {
    forward_count_ -= recent_.front() ? 1 : 0;
    recent_.pop_front();
  }
  const int n = static_cast<int>(recent_.size());
  if (!engaged_) {
    engaged_ = n >= std::min(frames, kForwardMinFrames) && forward_count_ >= kForwardShare * n;
  } else {
    engaged_ = forward_count_ >= kForwardKeepShare * n;
  }
}

bool ForwardMotionWindow::sustained() const {
  return engaged_;
}

void ForwardMotionWindow::clear() {
  recent_.clear();
  forward_count_ = 0;
  engaged_ = false;
}

}  // namespace iraf_vo
