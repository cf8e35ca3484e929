#include "iraf_vo/tracking/keyframe_policy.h"

namespace iraf_vo {

bool needNewKeyframe(const KeyframeCandidate& c, const TrackerParams& p) {
  if (c.frames_since_keyframe < p.min_frames_between_keyframes) return false;
  const bool mapping_idle = c.frames_since_keyframe >= p.mapping_busy_frames;
  const bool losing_map = c.inliers < p.keyframe_min_tracked;
  const bool timeout = c.frames_since_keyframe >= p.max_frames_between_keyframes;
  const bool few_tracked = c.inliers < p.keyframe_tracked_ratio * c.reference_tracked && (timeout || mapping_idle);
  const bool timeout_and_changed = timeout && c.inliers < 0.98 * c.reference_tracked;
  return losing_map || few_tracked || timeout_and_changed;
}

}  // namespace iraf_vo
