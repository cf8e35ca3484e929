// Tracker::Impl, the tracker's state (tracking thread) and its steps, shared by tracker.cpp (the state machine)
// and tracker_init.cpp (map initialization, monocular and stereo). Private to src/tracking.
#pragma once

#include "iraf_vo/tracking/tracker.h"

#include "iraf_vo/common/wall_clock.h"
#include "iraf_vo/tracking/health_monitor.h"
#include "iraf_vo/tracking/keyframe_policy.h"
#include "iraf_vo/tracking/local_mapper.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/map_initializer.h"
#include "iraf_vo/tracking/metric_scale_monitor.h"
#include "iraf_vo/tracking/pose_covariance.h"
#include "iraf_vo/tracking/pose_tracker.h"
#include "iraf_vo/tracking/relocalizer.h"
#include "iraf_vo/tracking/signal_check.h"
#include "iraf_vo/tracking/stereo_frame.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>

namespace iraf_vo {

struct Tracker::Impl {
  CameraModelPtr cam;
  StereoRig rig;  // rig.right == nullptr: monocular
  const TrackerParams p;
  Map map;
  LocalMapper mapper;
  MapInitializer initializer;
  PoseTracker pose_tracker;
  TrackingHealthMonitor health;
  SignalCheck signal;
  Relocalizer relocalizer;
  MetricScaleMonitor scale_monitor;     // stereo: whether the metric map's scale is observed
  ForwardMotionWindow forward_window;   // monocular: sustained forward motion (keyframe rule (e))
  std::unique_ptr<StereoFrame> stereo;  // null: monocular

  mutable std::mutex stats_mutex;
  TrackerStats stats;  // guarded by stats_mutex (the mapper keeps its BA stats)
  std::atomic<TrackingState> state{TrackingState::kNotInitialized};

  // ---- tracking thread only ----
  long frame_counter = 0;
  Frame last;                                                     // last tracked frame
  long last_ref_kf = -1;                                          // keyframe the last frame's pose is relative to
  Eigen::Isometry3d T_last_rel_kf = Eigen::Isometry3d::Identity();  // T_last_c_w * T_kf_c_w^-1
  Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
  bool have_velocity = false;
  // The motion model when the light went: after darkness the relocalization also searches from the last pose moved
  // on at that velocity over the frames since (a vehicle keeps going in the dark).
  Eigen::Isometry3d velocity_before_dark = Eigen::Isometry3d::Identity();
  bool have_velocity_before_dark = false;
  bool moved_on_after_dark = false;  // this frame was tracked from that seed
  bool metric_map = false;  // the map was made from a stereo frame (its scale is observed)
  PoseCovarianceCalibrator covariance_calibrator;  // of the poses output as TRACKING
  long last_kf_id = -1;
  int frames_since_kf = 0;
  double kf_close_untracked_share = 0.0;  // stereo: the last keyframe's close left-right matches without a map
                                          // point, per keypoint of it
  int consecutive_lost = 0;
  bool reinitializing = false;  // map was reset after a loss and is being re-initialized
  bool have_last_good = false;
  Eigen::Isometry3d last_good_T_w_c = Eigen::Isometry3d::Identity();
  double last_median_depth = 1.0;
  bool last_dark = false;  // the previous frame was too dark
  bool young_map_noisy = false;  // the map started on an image below init_min_map_baseline_snr
  bool map_settled = true;  // the map's keyframes span init_min_map_baseline of the depth: poses are reported

  Impl(CameraModelPtr c, const TrackerParams& params, const StereoRig& stereo_rig = StereoRig())
      : cam(std::move(c)), rig(stereo_rig), p(params), mapper(*cam, p, &map), initializer(*cam, p), pose_tracker(*cam, p), health(p), signal(p), relocalizer(*cam, p),
        scale_monitor(p) {
    if (!rig.right) return;
    stereo = std::make_unique<StereoFrame>(rig, p);
    mapper.setStereo(&rig);
    pose_tracker.setStereo(&rig);
  }

  template <class F>
  void updateStats(F&& f) {
    std::lock_guard<std::mutex> lk(stats_mutex);
    f(stats);
  }

  TrackResult track(const FeatureFrame& in, bool has_right = false, RightFeatures right = RightFeatures());
  void beginStereo(bool has_right, RightFeatures right, const cv::Mat& left_image, TrackResult* res);
  const std::vector<StereoMatch>& stereoMatches(Frame& cur, TrackResult* res);
  bool initializeMap(Frame& cur, TrackResult* res);
  bool initializeStereo(Frame& cur, TrackResult* res);
  bool mapBaselineSettled(const Frame& cur) const;
  bool trackWithMotionModel(Frame& cur, TrackResult* res);
  /// After darkness: the last pose moved on at the velocity before the dark over the frames since the last tracked
  /// one; none without that velocity.
  std::optional<Eigen::Isometry3d> movedOnSeed(const Frame& cur, const Eigen::Isometry3d& T_last) const;
  Eigen::Isometry3d lastPose() const;
  /// Orders relocalization candidates by the map inliers tracking from each ends with (most first; ties keep the
  /// relocalizer's order).
  void rankByTrackedInliers(const Frame& cur, std::vector<RelocalizationCandidate>* candidates) const;
  /// A PnP seed of fewer than kEnoughPnPInliers: the projection search is repeated around the refined pose.
  static bool roughSeed(const RelocalizationCandidate& c) { return c.pnp_inliers < Relocalizer::kEnoughPnPInliers; }
  /// A metric (stereo) map without a motion model (the first frame after the stereo start or after a loss): the
  /// pose tracking starts with brute force + PnP (PoseTracker::trackLocalMap's prediction_unknown).
  bool predictionUnknown() const { return metric_map && !have_velocity; }
  /// A pose whose inliers' median depth exceeds dark_relocalization_max_depth_ratio x the last tracked frame's (on a
  /// washed-out frame only the far points may match; their depth is the least known, the pose 0.1 m off).
  bool farPointsOnly(const PoseTrackingResult& r) const {
    return p.dark_relocalization_max_depth_ratio > 0.0 && r.has_median_depth && last_median_depth > 0.0 &&
           r.median_depth > p.dark_relocalization_max_depth_ratio * last_median_depth;
  }
  bool trackFrom(Frame& cur, const Eigen::Isometry3d& T_last, const Eigen::Isometry3d& T_predicted, TrackResult* res,
                 int min_search_inliers = 0, bool rough_prediction = false, bool prediction_known = false);
  bool relocalizeAfterDarkness(Frame& cur, TrackResult* res);
  Eigen::Matrix<double, 6, 6> initialPoseInformation(const Frame& cur) const;
  std::string checkHealth(const Frame& cur, const PoseTrackingResult& r, const Eigen::Isometry3d& T_last,
                          const Eigen::Isometry3d& T_predicted);
  bool addKeyframeIfNeeded(Frame& cur, TrackResult* res);
  /// The motion model's translation lies within keyframe_forward_deg of the optical axis (either way).
  bool movingForward() const {
    return have_velocity && movesAlongOpticalAxis(velocity.translation(), p.keyframe_forward_deg);
  }
  void handleLostFrame(const Frame& cur);
  TrackResult darkFrame(SteadyClock::time_point t_start, TrackResult res);
  void resetMap();
  void onTracked(const Frame& cur, TrackResult* res, bool is_keyframe);
  /// Stereo: the frame's close inliers (TrackResult::close_inliers; the stereo keyframe rule counts them too), into
  /// the scale monitor on a metric map (close_inliers_mean, metric_scale_weak ...).
  void observeMetricScale(const Frame& cur, TrackResult* res);
  TrackResult notTracked(TrackingState reported, SteadyClock::time_point t_start, TrackResult res) const {
    res.state = reported;
    res.T_w_c = last_good_T_w_c;
    res.timing.ms_total = msSince(t_start);
    return res;
  }
};

}  // namespace iraf_vo
