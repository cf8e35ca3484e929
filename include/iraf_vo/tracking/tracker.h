// Monocular tracking and mapping core (ROS-free): two-view initialization, frame-to-map tracking,
// keyframes, triangulation, sliding-window Ceres bundle adjustment on a local-mapping thread, and
// tracking-loss recovery.
//
// Per frame (Tracker::track):
//   1. Undistort every keypoint once: bearing = CameraModel::unproject(uv); keypoints go into a pixel grid.
//   2. Not initialized: two-view initialization against a reference frame (initializeTwoView: H vs E with
//      ORB-SLAM scores, cheirality / reprojection / parallax checks). The reference is replaced when it is
//      older than init_max_frames or has fewer than init_min_matches matches. Map scale: median depth 1
//      (after a loss: the last known median depth, see "Loss recovery").
//   3. Tracking: constant-velocity prediction -> projection search of the local map (all points of the
//      keyframes kept in the map) in a window of search_radius_px * scale_factor^octave around the
//      projection, Hamming <= match_threshold_high, ratio test, octave within +-1 of the point's octave ->
//      if too few matches: wider window (search_radius_wide_px) -> if still too few: brute-force matching
//      against the last keyframe (+ rotation-consistency histogram) and cv::solvePnPRansac (AP3P) ->
//      pose-only Ceres refinement (Huber, chi2 5.991 outlier rejection) -> a second, narrow projection
//      search (search_radius_refine_px) with the refined pose -> refinement again.
//   4. Tracked iff inliers >= min_tracking_inliers.
//
// Keyframe policy (decided in the tracking thread, ORB-SLAM mono flavour):
//   new keyframe iff frames since the last keyframe >= min_frames_between_keyframes AND one of
//     (a) inliers < keyframe_min_tracked                                   (losing the map: insert now)
//     (b) inliers < keyframe_tracked_ratio * (points of the reference keyframe seen by >= 2 keyframes)
//         (0.9 as ORB-SLAM mono) AND (mapping thread idle OR frames since last keyframe >= max_frames_between_keyframes)
//         (mapping_thread = false: "idle" = frames since last keyframe >= sync_mapping_busy_frames)
//     (c) frames since the last keyframe >= max_frames_between_keyframes AND inliers < 0.98 * reference
//   The keyframe gets the frame's inlier matches as observations.
//
// Local mapping (own thread unless mapping_thread = false; tracking never waits for it except on reset; when
//   the map is starving (keyframe with inliers < starving_inliers) the tracking thread triangulates that keyframe
//   itself so that new points do not wait behind a BA):
//   for each new keyframe: cull recent points (found/visible < min_found_ratio, or <= 2 observations two
//   keyframes after creation), triangulate new points between the keyframe and its num_triangulation_neighbors
//   best covisible keyframes (unmatched keypoints, Hamming <= match_threshold_low, epipolar check on bearings,
//   cheirality, reprojection chi2, min_triangulation_parallax_deg), then sliding-window BA when no other
//   keyframe is waiting or ba_every_keyframes keyframes were processed since the last BA.
// Sliding-window BA (bundleAdjust): the newest ba_window_size keyframes and the points they observe are free;
//   every other keyframe still in the map that observes those points is held fixed (gauge). If fewer than
//   two keyframes end up fixed (start of a map), or the fixed centres span less than ba_min_fixed_span of the
//   window's extent (scale only weakly held: it drifted towards 0 in fast-motion runs), the oldest window
//   keyframes are fixed until both hold: monocular gauge = 6 dof pose + 1 dof scale. Huber loss on sigma-normalized pixel residuals, bounded by
//   ba_max_num_iterations / ba_max_solver_time_in_seconds, aborted when a new keyframe arrives; results are
//   merged under the map mutex; observations failing chi2 afterwards are removed.
// Bounded memory: the map keeps at most max_map_keyframes keyframes (>= ba_window_size); the oldest
//   keyframe is dropped with its observations, and points without observations are deleted.
//
// Loss recovery: a frame with < min_tracking_inliers inliers is lost (kLost; lost_frames++, and lost_events++
//   on the transition). The next frames try relocalization (brute force against the map's keyframes + PnP).
//   After lost_frames_before_reset consecutive lost frames the map is cleared and initialization restarts
//   (no restart of the program). The new map is re-anchored: its reference frame gets the last good pose
//   T_w_c and its median depth is set to the last tracked frame's median depth, so the published trajectory
//   stays continuous. Scale caveat: monocular scale is unobservable, so the new map's scale only matches the
//   old one as well as the two median depths agree (scenes differ); the relative motion during the lost
//   frames is not recovered (the reference frame is assumed to sit at the last good pose). A Sim(3) ATE over a
//   trajectory with resets therefore includes these scale/offset jumps.
#pragma once

#include <iraf_vo/camera/camera_model.h>
#include <iraf_vo/features/feature_frame.h>
#include <iraf_vo/tracking/geometry.h>
#include <iraf_vo/tracking/tracker_params.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

namespace iraf_vo {

enum class TrackingState { kNotInitialized = 0, kInitializing = 1, kTracking = 2, kLost = 3 };
const char* toString(TrackingState s);

struct TrackTiming {
  double ms_prepare = 0.0;  // undistortion + grid
  double ms_init = 0.0;     // two-view initialization
  double ms_match = 0.0;    // projection search / brute force / PnP
  double ms_pose = 0.0;     // Ceres pose refinement
  double ms_keyframe = 0.0; // keyframe insertion (+ synchronous mapping when mapping_thread = false)
  double ms_total = 0.0;
};

struct TrackResult {
  TrackingState state = TrackingState::kNotInitialized;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();  // camera-to-world (valid when state == kTracking)
  int inliers = 0;
  int matches = 0;          // before pose refinement
  bool is_keyframe = false;
  bool initialized_now = false;  // this frame completed a (re-)initialization
  bool used_pnp = false;
  std::vector<char> keypoint_inlier;  // per input keypoint: 1 = matched to a map point and a pose inlier
  TrackTiming timing;
};

struct TrackerStats {
  long frames = 0;
  long tracked = 0;
  long lost_frames = 0;
  long lost_events = 0;
  long resets = 0;
  long initializations = 0;
  long keyframes = 0;
  long ba_runs = 0;
  double ba_ms_total = 0.0;
  double ba_final_rmse_px = 0.0;   // last BA
};

struct KeyframePose {
  long id = 0;
  double stamp = 0.0;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
};

class Tracker {
 public:
  /// Throws std::invalid_argument for a null camera or invalid params.
  Tracker(CameraModelPtr camera, const TrackerParams& params);
  ~Tracker();
  Tracker(const Tracker&) = delete;
  Tracker& operator=(const Tracker&) = delete;

  /// Processes one frame. Keypoints in level-0 distorted pixels; descriptors N x 32 CV_8U.
  /// A frame with mismatched keypoints/descriptors is reported as lost (never throws on bad frame data).
  TrackResult track(const FeatureFrame& frame);

  /// Positions (world) of the current map's points (the sliding window plus its fixed anchors).
  std::vector<Eigen::Vector3d> mapPoints() const;
  /// Poses of the keyframes currently in the map, oldest first.
  std::vector<KeyframePose> keyframePoses() const;
  TrackerStats stats() const;
  TrackingState state() const;
  const TrackerParams& params() const;
  /// Waits until the local-mapping thread has processed every queued keyframe (offline runs, tests).
  void waitForMapping();
  /// Clears the map and restarts initialization (keeps stats).
  void reset();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace iraf_vo
