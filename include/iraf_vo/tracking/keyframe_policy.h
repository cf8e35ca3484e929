// When the tracker inserts a keyframe (ORB-SLAM mono flavour). ROS-free, pure.
//
// new keyframe iff frames since the last keyframe >= min_frames_between_keyframes AND one of
//   (a) inliers < keyframe_min_tracked                                   (losing the map: insert now)
//   (b) inliers < keyframe_tracked_ratio * (points of the reference keyframe seen by >= 2 keyframes)
//       (0.9 as ORB-SLAM mono) AND (mapping idle OR frames since last keyframe >= max_frames_between_keyframes)
//       ("idle" = frames since last keyframe >= mapping_busy_frames, in both mapping modes: with the threaded
//       mapper's real state the keyframes depended on the machine's load; under CPU load it is never idle,
//       keyframes then came only when the map was already being lost and the monocular scale collapsed)
//       Monocular: mapping also counts as idle while the frame tracks fewer than keyframe_close_ratio of the
//       reference keyframe's close points (nearer than keyframe_close_steps frame steps; at least kMinClosePoints
//       of them): on a road the few near points leave the view within frames, and a pose from the far points
//       alone loses the scale (the keyframe after it triangulates its near points at that scale).
//   (c) frames since the last keyframe >= max_frames_between_keyframes AND inliers < 0.98 * reference
#pragma once

#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct KeyframeCandidate {
  int frames_since_keyframe = 0;
  int inliers = 0;               // pose inliers of the current frame
  int reference_tracked = 0;     // points of the last keyframe observed by >= 2 keyframes
  int reference_close = 0;       // of those, nearer than keyframe_close_steps frame steps to it
  int close_tracked = 0;         // inliers nearer than that to the current frame
};

constexpr int kMinClosePoints = 10;  // fewer close points in the reference keyframe: the close rule stays off

bool needNewKeyframe(const KeyframeCandidate& c, const TrackerParams& p);

}  // namespace iraf_vo
