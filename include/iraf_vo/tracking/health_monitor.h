// Tracking health monitor: decides whether a pose the tracker computed can be trusted, so that a wrong pose
// is never published as TRACKING. ROS-free; tracking thread only.
//
// A tracked frame is rejected (reported LOST, recovery as for any lost frame) when one of these fires:
//   inlier ratio    inliers / matches of the final pose refinement < health_min_inlier_ratio
//   reprojection    median chi2 (sigma-normalized squared error) of the inliers > health_max_median_chi2
//   duplicate       the frame's keypoints and descriptors equal the last frame's while the camera was moving
//   motion model    the pose differs from the constant-velocity prediction (made from the last frame's pose
//                   after any BA correction) by more than health_max_accel_ratio * (median per-frame speed of
//                   the last frames) + health_min_accel_depth * (median scene depth), or the rotation differs
//                   from the predicted one by more than health_max_rot_accel_deg + health_max_accel_ratio *
//                   (median per-frame rotation), or the camera reverses its direction against the motion model
//                   while both move faster than half of that floor
//                   (swapped frames, a frame from another place, a jump of the camera)
//   map scale       the last local BA changed the window's extent by more than a factor health_max_ba_scale_change
//                   (tracking and local BA disagree on the scale). Monocular maps only: it guards the unobservable
//                   monocular scale; a stereo map tracked with its right image observes the scale, and its BA
//                   may move the extent as the metric points demand (HealthInput::metric_scale). A map made, or
//                   a frame tracked, without the right image keeps the check.
// The motion history restarts after every loss or (re-)initialization: until the motion model exists again
// and three frames of motion history exist, a frame is only checked for inliers and reprojection.
#pragma once

#include "iraf_vo/tracking/tracker_params.h"

#include <Eigen/Geometry>

#include <deque>
#include <string>

namespace iraf_vo {

struct HealthInput {
  int inliers = 0;
  int refine_matches = 0;      // matches entering the final pose refinement
  double median_chi2 = 0.0;    // of the inliers
  bool duplicate_of_last = false;
  double ba_scale_change = 1.0;  // window extent after / before the newest local BA (1 = none since last frame)
  bool metric_scale = false;     // stereo map and this frame has its right image: the scale is observed
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();        // the tracked pose
  bool have_motion_model = false;
  Eigen::Isometry3d T_w_last = Eigen::Isometry3d::Identity();     // last frame (after BA corrections)
  Eigen::Isometry3d T_w_predicted = Eigen::Isometry3d::Identity();  // constant-velocity prediction
  double median_depth = 1.0;
};

class TrackingHealthMonitor {
 public:
  explicit TrackingHealthMonitor(const TrackerParams& params) : p_(params) {}
  /// "" when the pose can be trusted, else why not (one line).
  std::string check(const HealthInput& in) const;
  /// Records the motion of an accepted frame (from the last frame to it).
  void accept(const Eigen::Isometry3d& T_w_last, const Eigen::Isometry3d& T_w_c);
  /// Forgets the motion history (after a loss, a relocalization or a new map).
  void restart() { speeds_.clear(), rotations_deg_.clear(); }
  /// True when the camera moved noticeably in the last frames (duplicate-frame test).
  bool moving(double median_depth) const;

 private:
  const TrackerParams& p_;
  std::deque<double> speeds_, rotations_deg_;  // per-frame motion of the last accepted frames (at most 5)
};

}  // namespace iraf_vo
