// Frame-to-map pose tracking (tracking thread): constant-velocity prediction -> projection search of the
// local map (all points of the keyframes kept in the map) in a window of search_radius_px * sigma(octave)
// around the projection, octave within +-1 -> if too few matches: wider window (search_radius_wide_px) ->
// if still too few inliers: relocalization (brute force against the map points + PnP RANSAC) -> pose-only
// refinement (Huber, chi2 5.991 outlier rejection) -> a second, narrow projection search
// (search_radius_refine_px) with the refined pose -> refinement again. Tracked iff inliers >=
// min_tracking_inliers. Without a motion model on a metric map the brute force + PnP comes first. A relocalization
// (min_search_inliers > 0, after darkness) sends a weak projection-search pose to the brute force + PnP instead
// (the narrow search around a pose collects the matches that agree with it, so only the first pass's inliers are
// evidence independent of that pose), and a search pose that passes competes with the brute force + PnP pose:
// the one with more inliers after its narrow pass is kept. Stereo
// (setStereo): the refinements add a right-image residual for each matched keypoint with a left-right match
// (Frame::right_obs). ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/matcher.h"
#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct PoseTrackingResult {
  bool tracked = false;
  int matches = 0;          // projection-search matches before the pose refinement
  int inliers = 0;
  bool used_pnp = false;    // relocalized by brute force + PnP
  int refine_matches = 0;   // matches entering the final pose refinement
  int right_inliers = 0;    // stereo: right-image residuals in use after the final refinement
  double median_chi2 = 0.0; // median sigma-normalized squared reprojection error of the inliers
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();  // of T_c_w (poseInformation)
  bool has_median_depth = false;
  double median_depth = 0;  // of the inlier points in the frame
  double ms_match = 0.0, ms_pose = 0.0;
};

class PoseTracker {
 public:
  /// Projection searches around the refined pose after a rough prediction (trackLocalMap).
  static constexpr int kMaxResearches = 3;

  PoseTracker(const CameraModel& camera, const TrackerParams& params) : cam_(camera), p_(params), matcher_(camera, params) {}

  /// Stereo: the rig (must outlive the tracker) whose right camera sees Frame::right_obs; nullptr: monocular.
  void setStereo(const StereoRig* rig) { rig_ = rig && rig->right ? rig : nullptr; }

  /// Tracks `cur` against the map starting from T_predicted. On success sets cur.T_c_w and cur.point_id and
  /// counts the map points' visibility. prediction_unknown (no motion model, e.g. the frame after a stereo start):
  /// brute force + PnP against the local map first, the projection search around T_predicted only if that fails.
  /// min_search_inliers > 0 (a relocalization): inliers the pose refined from the projection search needs before
  /// the narrow search (fewer: brute force + PnP decides; at least min_tracking_inliers); a search pose that has
  /// them is kept only if it ends with more inliers than the brute force + PnP pose.
  /// rough_prediction (T_predicted from a PnP of few inliers, e.g. a keyframe's after darkness): the projection
  /// search is repeated around the refined pose while that gains inliers (a pose refined from matches found
  /// around a wrong seed can settle between it and the true pose).
  PoseTrackingResult trackLocalMap(Frame& cur, const Eigen::Isometry3d& T_predicted, Map* map,
                                   bool prediction_unknown = false, int min_search_inliers = 0,
                                   bool rough_prediction = false) const;
  /// The inliers trackLocalMap would end with from T_predicted with the same flags (0: not tracked), without
  /// touching `cur` or `map`: ranks the poses a relocalization could start from.
  int inliersFrom(const Frame& cur, const Eigen::Isometry3d& T_predicted, const Map& map, bool prediction_unknown,
                  bool rough_prediction) const;
  /// Stereo: refines the tracked cur.T_c_w again with the right residuals of cur.right_obs (matched after the
  /// tracking, e.g. for a new keyframe); the keypoints whose point fails the chi2 test lose it (cur.point_id).
  /// Returns the right residuals in use, or -1 (cur unchanged) without right observations or with fewer than
  /// min_tracking_inliers inliers.
  int refineWithRight(Frame& cur, const Map& map) const;

 private:
  /// What trackLocalMap found: its result, pose, matches (keypoint <-> local point) and the points in view.
  struct Solution {
    Solution(size_t num_keypoints, size_t num_points) : matches(num_keypoints, num_points), visible(num_points, 0) {}
    PoseTrackingResult res;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    MatchSet matches;
    std::vector<char> visible;
  };
  /// trackLocalMap's searches and refinements on `local`; res.tracked says whether the pose is accepted.
  Solution solve(const Frame& cur, const Eigen::Isometry3d& T_predicted, const std::vector<LocalPoint>& local,
                 bool prediction_unknown, int min_search_inliers, bool rough_prediction) const;
  /// Pose-only refinement from the matches (and their right observations); outlier matches are removed. Returns
  /// the inliers; *right_inliers (optional): the right residuals in use.
  int refinePose(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches, Eigen::Isometry3d* T,
                 int* right_inliers = nullptr) const;
  /// Median chi2 and information matrix of the final inliers.
  void describeInliers(const Frame& f, const std::vector<LocalPoint>& local, const MatchSet& matches,
                       const Eigen::Isometry3d& T, PoseTrackingResult* res) const;
  /// Brute force against all local points + PnP RANSAC; replaces *matches by the PnP inliers. Returns inliers, or
  /// 0 (matches and T untouched) below min_inliers (<= 0: min_tracking_inliers).
  int relocalize(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches, Eigen::Isometry3d* T,
                 int min_inliers = 0) const;
  /// relocalize, then the pose refinement when it has min_tracking_inliers: returns the inliers (0: no PnP pose);
  /// *found (optional): whether the PnP gave a pose; its time into *timing.
  int pnpPose(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches, Eigen::Isometry3d* T,
              PoseTrackingResult* timing, bool* found = nullptr) const;
  /// The second, narrow projection search around *T and the refinement again: *matches, *T, *visible, the
  /// matches entering the refinement, its inliers and right inliers, the time of both into *res.
  void narrowPass(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches, Eigen::Isometry3d* T,
                  std::vector<char>* visible, PoseTrackingResult* res) const;
  /// The projection search around T: narrow, then wide when the narrow one finds fewer than min_search_matches.
  int searchAround(const Frame& f, const Eigen::Isometry3d& T, const std::vector<LocalPoint>& local,
                   MatchSet* matches) const;
  /// The inliers of searchAround(T) and a pose refinement from T (0 below min_search_matches).
  int inliersFromStart(const Frame& f, const std::vector<LocalPoint>& local, Eigen::Isometry3d T) const;

  /// A PnP with this many inliers predicts the first step after a stereo start (ORB-SLAM's relocalization
  /// optimizes from 10 PnP inliers).
  static constexpr int kMinPnPPrediction = 10;

  const CameraModel& cam_;
  const TrackerParams& p_;
  Matcher matcher_;
  const StereoRig* rig_ = nullptr;
};

}  // namespace iraf_vo
