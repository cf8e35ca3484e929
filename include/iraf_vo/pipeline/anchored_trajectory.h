// The trajectory as it stands after mapping (what ORB-SLAM's and DSO's result files hold): every tracked frame's
// pose relative to its reference keyframe (as tracking measured it), re-attached to that keyframe's latest pose,
// so the local-BA corrections made after the frame was published reach it. The online trajectory (poses as
// published at each frame) stays the primary output; this one is written by iraf_vo_run --out-final. ROS-free.
#pragma once

#include <unordered_map>
#include <vector>

#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/tracking/tracker.h"

namespace iraf_vo {

class KeyframeAnchoredTrajectory {
 public:
  /// A tracked frame: its stamp, reference keyframe and pose in that keyframe (TrackResult fields).
  void addFrame(double stamp, const TrackResult& r);
  /// The keyframes' current poses (Tracker::keyframePoses()); a keyframe keeps the last pose it was seen with
  /// after it leaves the map. Keyframe ids are unique over the tracker's life (also across map resets).
  void updateKeyframes(const std::vector<KeyframePose>& keyframes);
  /// Frames whose keyframe pose is known, T_w_c = T_w_kf * T_kf_c; others keep their online pose.
  Trajectory build() const;

 private:
  struct FrameEntry {
    double stamp;
    long keyframe;
    Eigen::Isometry3d T_kf_c, T_w_c_online;
  };
  std::vector<FrameEntry> frames_;
  std::unordered_map<long, Eigen::Isometry3d> keyframe_poses_;
};

}  // namespace iraf_vo
