// When the tracker inserts a keyframe (ORB-SLAM mono flavour). ROS-free, pure.
//
// new keyframe iff frames since the last keyframe >= min_frames_between_keyframes AND one of
//   (a) inliers < keyframe_min_tracked                                   (losing the map: insert now)
//   (b) inliers < keyframe_tracked_ratio * (points of the reference keyframe seen by >= 2 keyframes)
//       (0.9 as ORB-SLAM mono) AND (mapping idle OR frames since last keyframe >= max_frames_between_keyframes)
//       (mapping_thread = false: "idle" = frames since last keyframe >= sync_mapping_busy_frames)
//   (c) frames since the last keyframe >= max_frames_between_keyframes AND inliers < 0.98 * reference
#pragma once

#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct KeyframeCandidate {
  int frames_since_keyframe = 0;
  int inliers = 0;               // pose inliers of the current frame
  int reference_tracked = 0;     // points of the last keyframe observed by >= 2 keyframes
  bool mapping_idle = true;      // the local mapper has nothing queued (threaded mapping)
};

bool needNewKeyframe(const KeyframeCandidate& c, const TrackerParams& p);

}  // namespace iraf_vo
