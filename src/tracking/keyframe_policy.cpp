#include "iraf_vo/tracking/keyframe_policy.h"

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

}  // namespace iraf_vo
