// Map initialization of the tracker: monocular (two-view, MapInitializer) or stereo (one frame's left-right
// matches), and the stereo frame's right image (stereo_frame.h).
#include "tracker_impl.h"

#include "iraf_vo/common/median.h"
#include "iraf_vo/tracking/pose_covariance.h"

#include <algorithm>

namespace iraf_vo {

// Stereo: whether this frame has a right image; a missing one is counted once per frame.
void Tracker::Impl::beginStereo(bool has_right, RightFeatures right, const cv::Mat& left_image, TrackResult* res) {
  const bool new_run = stereo->begin(has_right, std::move(right), left_image);
  res->stereo = has_right;
  res->right_missing = !has_right;
  if (has_right) return;
  updateStats([new_run](TrackerStats& s) {
    s.right_missing_frames++;
    if (new_run) s.right_missing_events++;
  });
}

// Stereo: the left-right matches of this frame, matched at the first call (the initialization, a new keyframe).
const std::vector<StereoMatch>& Tracker::Impl::stereoMatches(Frame& cur, TrackResult* res) {
  const bool first = !stereo->matched();
  double ms = 0.0;
  const std::vector<StereoMatch>& m = stereo->matches(&cur, &ms);
  res->timing.ms_match += ms;
  res->stereo_matches = static_cast<int>(m.size());
  if (first && stereo->hasRight())
    updateStats([n = m.size()](TrackerStats& s) {
      s.stereo_matched_frames++;
      s.stereo_matches_last = static_cast<long>(n);
      s.stereo_matches_total += static_cast<long>(n);
    });
  return m;
}

// Stereo: a metric map from this frame alone (one keyframe, the points of its left-right matches), at the last
// good pose after a loss.
bool Tracker::Impl::initializeStereo(Frame& cur, TrackResult* res) {
  cur.T_c_w = have_last_good ? last_good_T_w_c.inverse() : Eigen::Isometry3d::Identity();
  std::fill(cur.point_id.begin(), cur.point_id.end(), -1);
  const std::vector<StereoMatch>& matches = stereoMatches(cur, res);
  const std::vector<StereoMapPoint> points_w = stereoMapPoints(matches, cur, false);
  auto kf = Keyframe::fromFrame(cur, cur.T_c_w);  // after the matching: with the right observations
  int points = 0;
  if (!map.createStereoMap(kf, points_w, p.stereo_init_min_points, &points)) {
    res->init_status = "stereo: too few left-right matches (" + std::to_string(points) + " < " +
                       std::to_string(p.stereo_init_min_points) + ")";
    return false;
  }
  initializer.clearReference();
  metric_map = true;
  scale_monitor.restart();
  kf_close_untracked_share = closeShareWithoutPoint(matches, cur, stereo->closeDepth());  // cur.point_id: all -1 here
  cur.point_id = kf->point_id;
  last_kf_id = kf->id;
  res->inliers = points;
  res->is_keyframe = true;
  res->inlier_ratio = 1.0;
  res->covariance = worldPoseCovariance(initialPoseInformation(cur), cur.T_c_w);
  have_velocity = false;
  return true;
}

// Monocular: whether the map's keyframes span init_min_map_baseline of the median depth of its points in the current
// frame. Below, each local BA of the young map re-weighs a baseline that is small against the depth and moves the
// map's scale (the poses tracked meanwhile keep the old one); the frames are then tracked and mapped, not reported.
// Only for maps started on a noisy image (young_map_noisy): a clean start keeps its first poses, which a road start
// within a few frames needs (docs/decisions.md).
bool Tracker::Impl::mapBaselineSettled(const Frame& cur) const {
  if (!(p.init_min_map_baseline > 0.0) || metric_map || !young_map_noisy) return true;
  const std::vector<KeyframePose> keyframes = map.keyframePoses();
  if (keyframes.empty()) return true;
  double span = 0.0;
  for (const KeyframePose& k : keyframes)
    span = std::max(span, (k.T_w_c.translation() - keyframes.front().T_w_c.translation()).norm());
  std::vector<double> depth;
  for (const Eigen::Vector3d& p_w : map.pointPositions()) {
    const double z = (cur.T_c_w * p_w).z();
    if (z > 0.0) depth.push_back(z);
  }
  if (depth.empty()) return false;
  return span >= p.init_min_map_baseline * median(depth);
}

bool Tracker::Impl::initializeMap(Frame& cur, TrackResult* res) {
  if (stereo && res->stereo) return initializeStereo(cur, res);
  MapAnchor anchor;
  if (have_last_good) {  // after a loss: continue at the last good pose with the last median depth
    anchor.T_w_ref = last_good_T_w_c;
    anchor.median_depth = last_median_depth;
  }
  KeyframePtr kf0, kf1;
  int points = 0;
  if (!initializer.initialize(cur, anchor, &map, &kf0, &kf1, &points)) {
    res->init_status = initializer.lastFailure();
    return false;
  }
  metric_map = false;
  last_kf_id = kf1->id;
  res->inliers = points;
  res->is_keyframe = true;
  res->inlier_ratio = 1.0;
  res->covariance = worldPoseCovariance(initialPoseInformation(cur), cur.T_c_w);
  // Per-frame velocity from the average motion over the initialization baseline.
  const int nframes = std::max<long>(1, kf1->frame_index - kf0->frame_index);
  const Eigen::Isometry3d T_rel = kf1->T_c_w * kf0->T_c_w.inverse();
  Eigen::Quaterniond q(T_rel.rotation());
  velocity.setIdentity();
  velocity.linear() = Eigen::Quaterniond::Identity().slerp(1.0 / nframes, q).toRotationMatrix();
  velocity.translation() = T_rel.translation() / nframes;
  have_velocity = true;
  return true;
}

}  // namespace iraf_vo
