#include "iraf_vo/pipeline/anchored_trajectory.h"

namespace iraf_vo {

void KeyframeAnchoredTrajectory::addFrame(double stamp, const TrackResult& r) {
  if (r.state != TrackingState::kTracking) return;
  frames_.push_back({stamp, r.reference_keyframe_id, r.T_kf_c, r.T_w_c});
}

void KeyframeAnchoredTrajectory::updateKeyframes(const std::vector<KeyframePose>& keyframes) {
  for (const KeyframePose& k : keyframes) keyframe_poses_[k.id] = k.T_w_c;
}

Trajectory KeyframeAnchoredTrajectory::build() const {
  Trajectory t;
  for (const FrameEntry& f : frames_) {
    const auto it = f.keyframe >= 0 ? keyframe_poses_.find(f.keyframe) : keyframe_poses_.end();
    t.push_back(f.stamp, it != keyframe_poses_.end() ? Eigen::Isometry3d(it->second * f.T_kf_c) : f.T_w_c_online);
  }
  return t;
}

}  // namespace iraf_vo
