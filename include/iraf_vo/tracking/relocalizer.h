// Relocalization in the map the tracker kept (tracking thread; ROS-free), as ORB-SLAM's Tracking::Relocalization
// does with its keyframe database: each keyframe of the map is a candidate; the frame's descriptors are matched
// by brute force against the points that keyframe observes (few distractors, so the ratio test keeps the true
// matches that a match against the whole map loses), and PnP RANSAC on those matches gives a candidate pose.
// The map is small (max_map_keyframes), so the keyframes are tried one by one, newest first, instead of a
// bag-of-words query.
// The caller then tracks the local map from the best candidates' poses (projection search + pose refinement with
// the usual inlier and health checks), so a pose is only accepted with min_tracking_inliers map inliers.
#pragma once

#include <iraf_vo/camera/camera_model.h>
#include <iraf_vo/tracking/frame.h>
#include <iraf_vo/tracking/map.h>
#include <iraf_vo/tracking/matcher.h>
#include <iraf_vo/tracking/tracker_params.h>

#include <Eigen/Geometry>
#include <vector>

namespace iraf_vo {

struct RelocalizationCandidate {
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  int pnp_inliers = 0;
  int keyframe_rank = 0;  // 0 = the newest keyframe
  bool moved_on = false;  // not a keyframe's PnP: the last pose moved on at the velocity before the dark (tracker)
};

class Relocalizer {
 public:
  Relocalizer(const CameraModel& camera, const TrackerParams& params) : cam_(camera), p_(params), matcher_(camera, params) {}

  /// Candidate poses of `cur` in `map`, most PnP inliers first, at most max_candidates; empty when no keyframe
  /// gives kMinMatches descriptor matches and kMinPnPInliers PnP inliers. Keyframes newest first, until one gives
  /// kEnoughPnPInliers.
  std::vector<RelocalizationCandidate> candidates(const Frame& cur, const Map& map, size_t max_candidates) const;

  static constexpr int kMinMatches = 15;     // ORB-SLAM: 15 BoW matches per candidate keyframe
  static constexpr int kMinPnPInliers = 10;  // ORB-SLAM: 10 PnP inliers before its projection search
  static constexpr int kEnoughPnPInliers = 50;  // a keyframe with this many ends the search (ORB-SLAM accepts a
                                                // relocalization at 50 inliers)
  static constexpr int kMinAcceptedInliers = 50;  // map inliers of the pose after the projection search that accept
                                                  // a relocalization after darkness (ORB-SLAM: 50); fewer, on a
                                                  // view seen from far away, can be a wrong pose (a plane's mirror
                                                  // solution, repeated texture) that new keyframes then entrench

 private:
  const CameraModel& cam_;
  const TrackerParams& p_;
  Matcher matcher_;
};

}  // namespace iraf_vo
