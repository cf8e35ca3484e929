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
//   (e) monocular, sustained forward motion (the motion model's translation within keyframe_forward_deg of the
//       optical axis in at least kForwardShare of the last keyframe_forward_frames tracked frames, as a vehicle
//       drives; ForwardMotionWindow, with hysteresis): inliers < reference, no mapping wait. Moving along the
//       optical axis the points ahead gain parallax only as they come near, and the near points that fix the step
//       pass out of view within a few frames; a keyframe on every frame that loses one of the reference's points
//       triangulates them while they are in view (on a road whose near surface has few corners a keyframe otherwise
//       waits while the far points stay tracked, and the step is taken from them alone). A hand-held or flying
//       camera moves forward for a few frames at a time (EuRoC MH_01: at most 14 in a row, simulated rooms 4): the
//       rule stays off there, where a keyframe on every lost point moved results both ways (docs/decisions.md).
//   (d) stereo (ORB-SLAM's stereo close-point condition): fewer than kStereoCloseTracked inliers nearer than the
//       stereo close depth (stereo_min_disparity_px) AND the last keyframe left close left-right matches without a
//       map point for more than kStereoCloseUntrackedShare of its keypoints (the scene offers close points the map
//       does not track).
//       No mapping wait: on a road the near points leave the view within 2-3 frames, and the step between two
//       keyframes is then fixed by the farther points, whose stereo depth is short near the disparity floor.
//       Left-right matching runs on keyframes only, so the last keyframe's untracked close matches stand in for
//       ORB-SLAM's per-frame count.
#pragma once

#include <deque>

#include <Eigen/Core>

#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct KeyframeCandidate {
  int frames_since_keyframe = 0;
  int inliers = 0;               // pose inliers of the current frame
  int reference_tracked = 0;     // points of the last keyframe observed by >= 2 keyframes
  int reference_close = 0;       // of those, nearer than keyframe_close_steps frame steps to it
  int close_tracked = 0;         // inliers nearer than that to the current frame
  bool forward = false;          // monocular: sustained forward motion (ForwardMotionWindow::sustained)
  int stereo_close_tracked = -1;   // stereo: inliers nearer than the stereo close depth (-1: monocular)
  double stereo_close_untracked_share = 0.0;  // stereo: the last keyframe's close left-right matches without a map
                                             // point, per keypoint of that keyframe
};

constexpr int kMinClosePoints = 10;  // fewer close points in the reference keyframe: the close rule stays off
// ORB-SLAM's stereo rule uses 100 / 70. 150: simulated highway pinhole 0.200 % of the path / scale 1.0065 at 100,
// 0.090 % / 1.0005 at 150; EuRoC MH_01 never reaches it (same keyframes).
constexpr int kStereoCloseTracked = 150;
// ORB-SLAM counts 70 close matches without a map point, on frames of ~1000 keypoints (EuRoC: 1000-1100 here). As a
// share the rule keeps its meaning on smaller images: the simulated 512 x 512 fisheye has ~760 keypoints per frame,
// its keyframes on the highway left 57-69 such matches, and under a count of 70 the next keyframe came 2-3 frames
// later, after the pose had been taken from far points alone (steps 0.67-0.74 of the true one).
constexpr double kStereoCloseUntrackedShare = 0.07;

bool needNewKeyframe(const KeyframeCandidate& c, const TrackerParams& p);

/// Rule (e)'s direction test: a camera step t (in the camera frame) within max_deg of the optical axis, either way
/// (false for max_deg <= 0 or no step).
bool movesAlongOpticalAxis(const Eigen::Vector3d& t, double max_deg);

constexpr double kForwardShare = 0.9;  // of the window's frames moving forward: sustained forward motion
constexpr int kForwardMinFrames = 5;   // a younger window (the map's first tracked frames) needs this many
constexpr double kForwardKeepShare = 0.5;  // once sustained, until fewer of the window's frames move forward

/// Rule (e)'s memory: whether the camera moved forward in the recent tracked frames (one entry per tracked frame).
class ForwardMotionWindow {
 public:
  /// One tracked frame; `frames` (keyframe_forward_frames) is the window's length.
  void add(bool forward, int frames);
  /// Engaged once at least kForwardShare of the window's frames moved forward (a young window: from
  /// kForwardMinFrames frames on); kept while at least kForwardKeepShare of them do.
  bool sustained() const;
  void clear();

 private:
  std::deque<bool> recent_;
  int forward_count_ = 0;
  bool engaged_ = false;
};

}  // namespace iraf_vo
