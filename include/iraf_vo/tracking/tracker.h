// Monocular tracking and mapping core (ROS-free): the public facade. Tracker::track runs the state machine
// (src/tracking/tracker.cpp) over role classes that own their data:
//   Frame (frame.h)               keypoints undistorted once into bearings + a pixel grid
//   Map (map.h)                   keyframes, map points, observations, covisibility; the map mutex
//   Matcher (matcher.h)           projection search, brute force, epipolar search; MatchSet
//   MapInitializer (map_initializer.h)  two-view initialization (H vs E), first two keyframes
//   PoseTracker (pose_tracker.h)  motion-model prediction -> projection search -> PnP fallback -> refinement
//   needNewKeyframe (keyframe_policy.h)  the keyframe decision
//   LocalMapper (local_mapper.h)  the mapping protocol: triangulation, fusion, point culling, local BA, its thread
//   LocalBAProblem (local_ba.h)   the sliding window and its monocular gauge
//   TrackingHealthMonitor (health_monitor.h)  rejects untrustworthy poses (reported lost, never tracking)
//
// Per frame: undistort -> not initialized: two-view initialization against a reference frame; map scale =
// median depth 1 (after a loss: the last known median depth) -> tracking: PoseTracker::trackLocalMap; tracked
// iff inliers >= min_tracking_inliers and the health monitor trusts the pose -> keyframe decision -> LocalMapper:
// the keyframe is mapped (culling, triangulation, fusion) inside the tracking step, its BA runs synchronously or
// on the mapping thread (mapping_thread) and is written back at once or at the next keyframe (local_mapper.h);
// the tracker calls the mapper the same way in both modes, and both give the same trajectory every run. The
// keyframe decision counts mapping as busy for mapping_busy_frames frames after a keyframe in both modes, so
// keyframes do not depend on the machine's load; one tracking step holds the map-update lock
// (Map::lockUpdates), so a BA result is written back between frames.
//
// Darkness (signal_check.h): a frame whose image carries no usable signal is lost with a "too dark" reason and
//   is not tracked; the map and the last pose are kept and, once the light returns, the lost-frame path below
//   relocalizes in that map (+ the keyframe-wise Relocalizer and the last pose moved on at the velocity before the
//   dark, ranked by the map inliers tracking from each ends with: tracker_relocalization.cpp); for
//   dark_relocalization_frames frames after the dark ones a loss resets the map only after that many lost frames,
//   and the keyframe rule's reference is the keyframe sharing the most points with the frame.
// Loss recovery: a frame with < min_tracking_inliers inliers is lost (kLost; lost_frames++, and lost_events++
//   on the transition). The next frames try relocalization (brute force against the map's points + PnP).
//   After lost_frames_before_reset consecutive lost frames the map is cleared and initialization restarts
//   (no restart of the program). The new map is re-anchored: its reference frame gets the last good pose
//   T_w_c and its median depth is set to the last tracked frame's median depth, so the published trajectory
//   stays continuous. Scale caveat: monocular scale is unobservable, so the new map's scale only matches the
//   old one as well as the two median depths agree (scenes differ); the relative motion during the lost
//   frames is not recovered (the reference frame is assumed to sit at the last good pose). A Sim(3) ATE over a
//   trajectory with resets therefore includes these scale/offset jumps.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/stereo_frame.h"
#include "iraf_vo/tracking/tracker_params.h"

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
  /// The keyframe this pose is measured against and the pose in it (T_w_c = T_w_kf * T_kf_c at tracking time;
  /// valid when state == kTracking): re-attached to the keyframe's later, BA-refined pose this gives the
  /// trajectory after mapping (KeyframeAnchoredTrajectory).
  long reference_keyframe_id = -1;
  Eigen::Isometry3d T_kf_c = Eigen::Isometry3d::Identity();
  std::vector<char> keypoint_inlier;  // per input keypoint: 1 = matched to a map point and a pose inlier
  /// Covariance of T_w_c in the world frame, [x y z rx ry rz] (map units, radians): the pose refinement's
  /// (sigma = scale_factor^octave px per keypoint) calibrated by the frame's variance factor and its deviation
  /// from the motion model (calibratedPoseCovariance; valid when state == kTracking).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
  double inlier_ratio = 0.0;  // inliers / matches of the final pose refinement
  double median_chi2 = 0.0;   // of the inliers
  std::string rejected;       // why the health monitor rejected a computed pose ("" if it did not)
  std::string too_dark;       // why the image carries no usable signal (state kLost, no pose; "" if it does)
  int relocalized_after_frames = 0;  // > 0: tracked again in the same map after dark frames, at the n-th frame
                                     // with signal
  std::string init_status;    // while initializing: why this frame did not initialize the map
  bool stereo = false;         // stereo tracker: the right image of this frame was used
  bool right_missing = false;  // stereo tracker: this frame had no right image (tracked with the left camera)
  int stereo_matches = 0;      // stereo tracker: left-right matches of this frame (0 when not matched)
  int right_inliers = 0;       // stereo tracker: right-image residuals in this frame's final pose refinement
  /// Stereo tracker, tracked frame: pose inliers nearer than the close depth (depths the pair measures; -1
  /// otherwise). On a metric map also their mean over the last stereo_scale_window_frames (-1 otherwise) and
  /// whether that mean is below stereo_scale_min_close_inliers (metric scale weakly observed: MetricScaleMonitor);
  /// metric_scale_changed: this frame changed metric_scale_weak.
  int close_inliers = -1;
  double close_inliers_mean = -1.0;
  bool metric_scale_weak = false;
  bool metric_scale_changed = false;
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
  long rejected = 0;               // tracked poses rejected by the health monitor (counted as lost frames)
  long dark_frames = 0;            // frames without usable signal, too dark or washed out (counted as lost
                                   // frames; the map is kept)
  long dark_events = 0;            // runs of consecutive dark frames
  long relocalizations = 0;        // tracked again in the same map after dark frames (no reset)
  long frames_to_relocalize_max = 0;  // frames with signal needed by the slowest of those relocalizations
  long ba_runs = 0;
  double ba_ms_total = 0.0;        // LocalMapperStats
  double ba_cpu_ms_total = 0.0;
  double ba_final_rmse_px = 0.0;   // last BA
  long right_missing_frames = 0;   // stereo tracker: frames without a right image
  long right_missing_events = 0;   // runs of consecutive frames without a right image
  long weak_scale_frames = 0;      // stereo tracker: tracked frames with a weakly observed metric scale
  long weak_scale_events = 0;      // runs of them
  long stereo_matched_frames = 0;  // frames matched left-right (the initialization and keyframes with a right image)
  long stereo_matches_last = 0;    // left-right matches of the last matched frame
  long stereo_matches_total = 0;   // summed over the matched frames
};


class Tracker {
 public:
  /// Throws std::invalid_argument for a null camera or invalid params.
  Tracker(CameraModelPtr camera, const TrackerParams& params);
  /// Stereo: the map is metric from the first frame (left camera = the tracked camera; poses are the left
  /// camera's). Throws std::invalid_argument for an incomplete rig or invalid params.
  Tracker(const StereoRig& rig, const TrackerParams& params);
  ~Tracker();
  Tracker(const Tracker&) = delete;
  Tracker& operator=(const Tracker&) = delete;

  /// Processes one frame. Keypoints in level-0 distorted pixels; descriptors N x 32 CV_8U.
  /// A frame with mismatched keypoints/descriptors is reported as lost (never throws on bad frame data).
  TrackResult track(const FeatureFrame& frame);
  /// Stereo frame: left and right features of one exposure. right == nullptr (or an empty frame): this frame has
  /// no right image; the tracker continues in its metric map with the left camera (TrackResult::right_missing,
  /// TrackerStats::right_missing_frames). On a monocular tracker the right frame is ignored.
  TrackResult track(const FeatureFrame& left, const FeatureFrame* right);
  /// Stereo frame whose right features are computed only if the tracker matches this frame (the stereo
  /// initialization and new keyframes; stereo_frame.h): right() is called at most once, inside this call.
  /// has_right false: no right image, as right == nullptr above.
  TrackResult track(const FeatureFrame& left, bool has_right, RightFeatures right);
  bool isStereo() const;
  /// The rig of a stereo tracker (left = the camera of the monocular constructor, right = null for mono).
  const StereoRig& rig() const;

  /// Positions (world) of the current map's points (the sliding window plus its fixed anchors).
  std::vector<Eigen::Vector3d> mapPoints() const;
  /// Poses of the keyframes currently in the map, oldest first.
  std::vector<KeyframePose> keyframePoses() const;
  TrackerStats stats() const;
  TrackingState state() const;
  const TrackerParams& params() const;
  /// Waits until the local-mapping thread has processed every queued keyframe (offline runs, tests).
  /// track() is called from one thread; the queries above may be called from any thread.
  void waitForMapping();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace iraf_vo
