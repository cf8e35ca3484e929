// The tracker's state machine (tracking thread): initialization -> tracking -> lost -> relocalization or
// reset. It owns the map, the local mapper, the initializer and the pose tracker and coordinates them
// (see tracker.h for the whole algorithm).
#include "tracker_impl.h"

#include "iraf_vo/common/wall_clock.h"
#include "iraf_vo/tracking/pose_covariance.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

namespace iraf_vo {

const char* toString(TrackingState s) {
  switch (s) {
    case TrackingState::kNotInitialized: return "not_initialized";
    case TrackingState::kInitializing: return "initializing";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
  }
  return "?";
}

TrackResult Tracker::Impl::track(const FeatureFrame& in, bool has_right, RightFeatures right) {
  const auto t_start = SteadyClock::now();
  TrackResult res;
  Frame cur;
  std::string err;
  auto t0 = SteadyClock::now();
  const bool ok_input = Frame::fromFeatures(in, *cam, frame_counter, &cur, &err);
  res.timing.ms_prepare = msSince(t0);
  ++frame_counter;
  updateStats([](TrackerStats& s) { s.frames++; });
  // Bad frame: report it as not tracked, keep the state machine as is.
  if (!ok_input) return notTracked(state == TrackingState::kTracking ? TrackingState::kLost : state.load(), t_start, res);
  res.too_dark = signal.noSignal(in.signal);
  const bool was_dark = last_dark;
  last_dark = !res.too_dark.empty();
  if (last_dark) {
    if (!was_dark) updateStats([](TrackerStats& s) { s.dark_events++; });
    return darkFrame(t_start, res);
  }
  signal.lightFrame();
  if (stereo) beginStereo(has_right, std::move(right), in.image, &res);

  if (state == TrackingState::kNotInitialized || state == TrackingState::kInitializing) {
    t0 = SteadyClock::now();
    const bool done = initializeMap(cur, &res);
    res.timing.ms_init = msSince(t0);
    if (!done) {
      state = initializer.hasReference() ? TrackingState::kInitializing : TrackingState::kNotInitialized;
      if (!reinitializing) return notTracked(state, t_start, res);
      updateStats([](TrackerStats& s) { s.lost_frames++; });  // after a loss: lost frames of the same event
      return notTracked(TrackingState::kLost, t_start, res);
    }
    state = TrackingState::kTracking;
    reinitializing = false;
    res.initialized_now = true;
    signal.restart();
    health.restart();
    const int new_keyframes = res.stereo ? 1 : 2;  // a stereo map starts from one keyframe
    updateStats([new_keyframes](TrackerStats& s) {
      s.initializations++;
      s.keyframes += new_keyframes;
    });
    mapper.acceptKeyframe(last_kf_id);
    young_map_noisy = !(p.init_min_map_baseline_snr > 0.0) ||
                      (in.signal.measured && in.signal.snr < p.init_min_map_baseline_snr);
    map_settled = mapBaselineSettled(cur);
    onTracked(cur, &res, true);  // before the mapper can move the keyframe: the last frame follows its BA
    t0 = SteadyClock::now();
    mapper.insertKeyframe(last_kf_id);
    res.timing.ms_keyframe = msSince(t0);
    res.timing.ms_total = msSince(t_start);
    return res;
  }

  // kTracking or kLost (relocalization attempts before the reset)
  if (state == TrackingState::kLost) have_velocity = false;
  // One tracking step sees one version of the map: a BA result is written back before or after it, never
  // between the pose estimate, the keyframe created from it and T_last_rel_kf (see Map::lockUpdates).
  std::unique_lock<std::mutex> map_update = map.lockUpdates();
  if (stereo && p.stereo_match_every_frame) stereoMatches(cur, &res);  // right residuals in the pose refinement
  moved_on_after_dark = false;
  if (!trackWithMotionModel(cur, &res) && !relocalizeAfterDarkness(cur, &res)) {
    map_update.unlock();
    health.restart();
    const bool reported = map_settled;
    handleLostFrame(cur);
    return notTracked(reported ? TrackingState::kLost : TrackingState::kInitializing, t_start, res);
  }
  state = TrackingState::kTracking;
  consecutive_lost = 0;
  res.relocalized_after_frames = signal.trackedFrame();
  if (res.relocalized_after_frames > 0) {
    // The motion since the last pose spans the dark frames: no velocity for the next prediction, unless the pose
    // came from the velocity before the dark.
    have_velocity = moved_on_after_dark;
    if (have_velocity) velocity = velocity_before_dark;
    have_velocity_before_dark = false;
    health.restart();
    updateStats([&res](TrackerStats& s) {
      s.relocalizations++;
      s.frames_to_relocalize_max = std::max<long>(s.frames_to_relocalize_max, res.relocalized_after_frames);
    });
  }
  ++frames_since_kf;
  observeMetricScale(cur, &res);
  t0 = SteadyClock::now();
  const bool new_keyframe = addKeyframeIfNeeded(cur, &res);
  if (!map_settled) map_settled = mapBaselineSettled(cur);
  onTracked(cur, &res, res.is_keyframe);
  map_update.unlock();
  if (new_keyframe) mapper.insertKeyframe(last_kf_id);  // BA: here (synchronous) or on the mapping thread
  res.timing.ms_keyframe = msSince(t0);
  res.timing.ms_total = msSince(t_start);
  return res;
}

bool Tracker::Impl::trackWithMotionModel(Frame& cur, TrackResult* res) {
  // Prediction; the last frame's pose follows its reference keyframe if BA moved it.
  const Eigen::Isometry3d T_last = lastPose();
  const Eigen::Isometry3d T_predicted = have_velocity ? velocity * T_last : T_last;
  const bool after_dark = signal.awaitingRelocalization();
  // After darkness: where the velocity before the dark has taken the camera is a seed too (a vehicle keeps going in
  // the dark); when a search from there ends with more map inliers than one from the last pose, the relocalization's
  // ranked candidates decide (that seed among them).
  if (after_dark) {
    const std::optional<Eigen::Isometry3d> moved_on = movedOnSeed(cur, T_last);
    if (moved_on && pose_tracker.inliersFrom(cur, *moved_on, map, false, true) >
                        pose_tracker.inliersFrom(cur, T_last, map, predictionUnknown(), false))
      return false;
  }
  // After darkness the last pose is only a guess: a relocalization from the search around it needs
  // kMinAcceptedInliers before that search is narrowed around the refined pose (PoseTracker::trackLocalMap).
  const int min_search_inliers = after_dark ? Relocalizer::kMinAcceptedInliers : 0;
  return trackFrom(cur, T_last, T_predicted, res, min_search_inliers);
}

// The last frame's pose, following its reference keyframe if a BA has moved it since.
Eigen::Isometry3d Tracker::Impl::lastPose() const {
  Eigen::Isometry3d T_kf;
  return map.keyframePose(last_ref_kf, &T_kf) ? T_last_rel_kf * T_kf : last.T_c_w;
}

bool Tracker::Impl::trackFrom(Frame& cur, const Eigen::Isometry3d& T_last, const Eigen::Isometry3d& T_predicted,
                              TrackResult* res, int min_search_inliers, bool rough_prediction, bool prediction_known) {
  const bool prediction_unknown = predictionUnknown() && !prediction_known;
  const PoseTrackingResult r =
      pose_tracker.trackLocalMap(cur, T_predicted, &map, prediction_unknown, min_search_inliers, rough_prediction);
  res->matches = r.matches;
  res->inliers = r.inliers;
  res->used_pnp = r.used_pnp;
  res->timing.ms_match += r.ms_match;
  res->timing.ms_pose += r.ms_pose;
  if (!r.tracked) return false;
  if (signal.awaitingRelocalization() && r.inliers < Relocalizer::kMinAcceptedInliers) {
    res->rejected = "relocalization after darkness: " + std::to_string(r.inliers) + " map inliers < " +
                    std::to_string(Relocalizer::kMinAcceptedInliers);
    return false;
  }
  if (signal.awaitingRelocalization() && farPointsOnly(r)) {
    char buf[96];
    std::snprintf(buf, sizeof(buf), "relocalization after darkness: inliers at %.1fx the depth tracked before",
                  r.median_depth / last_median_depth);
    res->rejected = buf;
    return false;
  }
  res->inlier_ratio = r.refine_matches > 0 ? static_cast<double>(r.inliers) / r.refine_matches : 0.0;
  res->median_chi2 = r.median_chi2;
  if (stereo && !cur.right_obs.empty()) res->right_inliers = r.right_inliers;
  res->covariance = worldPoseCovariance(r.information, cur.T_c_w);
  res->rejected = checkHealth(cur, r, T_last, T_predicted);
  if (!res->rejected.empty()) {
    updateStats([](TrackerStats& s) { s.rejected++; });
    return false;
  }
  health.accept(T_last.inverse(), cur.T_c_w.inverse());
  if (r.has_median_depth) last_median_depth = r.median_depth;
  if (last_kf_id >= 0) {  // velocity from the (possibly BA-updated) last pose
    velocity = cur.T_c_w * T_last.inverse();
    velocity.linear() = Eigen::Quaterniond(velocity.rotation()).normalized().toRotationMatrix();
    have_velocity = true;
  }
  return true;
}

Eigen::Matrix<double, 6, 6> Tracker::Impl::initialPoseInformation(const Frame& cur) const {
  std::unordered_map<long, Eigen::Vector3d> position;
  for (const LocalPoint& lp : map.localPoints()) position[lp.id] = lp.p_w;
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> sigma;
  for (size_t i = 0; i < cur.size(); ++i) {
    auto it = position.find(cur.point_id[i]);
    if (it == position.end()) continue;
    P.push_back(it->second);
    uv.emplace_back(cur.keypoints[i].pt.x, cur.keypoints[i].pt.y);
    sigma.push_back(cur.sigma(cur.keypoints[i].octave));
  }
  return poseInformation(*cam, P, uv, sigma, cur.T_c_w);
}

std::string Tracker::Impl::checkHealth(const Frame& cur, const PoseTrackingResult& r, const Eigen::Isometry3d& T_last,
                                       const Eigen::Isometry3d& T_predicted) {
  HealthInput in;
  in.inliers = r.inliers;
  in.refine_matches = r.refine_matches;
  in.median_chi2 = r.median_chi2;
  in.T_w_c = cur.T_c_w.inverse();
  in.have_motion_model = have_velocity;
  in.T_w_last = T_last.inverse();
  in.T_w_predicted = T_predicted.inverse();
  in.median_depth = r.has_median_depth ? r.median_depth : last_median_depth;
  in.ba_scale_change = mapper.takeScaleChange();
  in.metric_scale = metric_map && stereo && stereo->hasRight();
  in.duplicate_of_last = cur.size() == last.size() && cur.size() > 0 &&
                         std::equal(cur.keypoints.begin(), cur.keypoints.end(), last.keypoints.begin(),
                                    [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.pt == b.pt; }) &&
                         cv::norm(cur.descriptors, last.descriptors, cv::NORM_HAMMING) == 0;
  return health.check(in);
}

bool Tracker::Impl::addKeyframeIfNeeded(Frame& cur, TrackResult* res) {
  KeyframeCandidate c;
  c.frames_since_keyframe = frames_since_kf;
  c.inliers = res->inliers;
  forward_window.add(!stereo && movingForward(), p.keyframe_forward_frames);
  if (c.frames_since_keyframe >= p.min_frames_between_keyframes) {
    // The ratio test's reference keyframe: the last one, or while recovering from darkness the one sharing the most
    // points with the frame (ORB-SLAM's reference keyframe): a keyframe made on a frame still recovering its exposure
    // holds few points, and with it as reference no keyframe would come while the map ages.
    const long ref_kf = signal.recovering() ? map.mostCovisibleKeyframe(cur.point_id, last_kf_id) : last_kf_id;
    if (!stereo && have_velocity && p.keyframe_close_steps > 0) {  // the close-point rule (keyframe_policy.h)
      const double max_depth = p.keyframe_close_steps * velocity.translation().norm();
      c.close_tracked = map.pointsNearerThan(cur.point_id, cur.T_c_w, max_depth);
      c.reference_tracked = map.trackedPoints(ref_kf, 2, max_depth, &c.reference_close);
    } else {
      c.reference_tracked = map.trackedPoints(ref_kf, 2);
    }
    c.forward = p.keyframe_forward_deg > 0.0 && forward_window.sustained();  // the forward rule (keyframe_policy.h)
    if (stereo) {  // the stereo close-point rule (keyframe_policy.h)
      c.stereo_close_tracked = res->close_inliers;  // observeMetricScale
      c.stereo_close_untracked_share = kf_close_untracked_share;
    }
  }
  if (!needNewKeyframe(c, p)) return false;
  std::vector<StereoMapPoint> stereo_points;
  if (stereo) {
    const std::vector<StereoMatch>& m = stereoMatches(cur, res);
    // Matched only now (stereo_match_every_frame false): the keyframe's pose again, with its right residuals.
    if (!p.stereo_match_every_frame) res->right_inliers = std::max(0, pose_tracker.refineWithRight(cur, map));
    stereo_points = stereoMapPoints(m, cur, true);
    kf_close_untracked_share = closeShareWithoutPoint(m, cur, stereo->closeDepth());
  }
  // mapped right here: the next frames match its new points (stereo: its close points first)
  last_kf_id = mapper.addKeyframe(cur, stereo_points);
  updateStats([](TrackerStats& s) { s.keyframes++; });
  frames_since_kf = 0;
  res->is_keyframe = true;
  return true;
}

void Tracker::Impl::observeMetricScale(const Frame& cur, TrackResult* res) {
  if (!stereo) return;
  res->close_inliers = map.pointsNearerThan(cur.point_id, cur.T_c_w, stereo->closeDepth());
  if (!metric_map) return;
  res->metric_scale_changed = scale_monitor.add(res->close_inliers);
  res->metric_scale_weak = scale_monitor.weak();
  res->close_inliers_mean = scale_monitor.mean();
  if (!res->metric_scale_weak) return;
  const bool new_run = res->metric_scale_changed;
  updateStats([new_run](TrackerStats& s) {
    s.weak_scale_frames++;
    if (new_run) s.weak_scale_events++;
  });
}

void Tracker::Impl::handleLostFrame(const Frame& cur) {
  // A young map whose poses are not reported yet (init_min_map_baseline): its losses are part of the initialization.
  const bool was_tracking = state == TrackingState::kTracking && map_settled;
  const bool reported = map_settled;
  updateStats([was_tracking, reported](TrackerStats& s) {
    if (reported) s.lost_frames++;
    if (was_tracking) s.lost_events++;
  });
  state = TrackingState::kLost;
  if (++consecutive_lost <= signal.lostFramesBeforeReset()) return;
  updateStats([](TrackerStats& s) { s.resets++; });
  resetMap();
  signal.restart();
  initializer.setReference(cur);  // this frame starts the new initialization
  reinitializing = reported;
  state = initializer.hasReference() ? TrackingState::kInitializing : TrackingState::kNotInitialized;
}

// A frame too dark to track: with a map, LOST with the map and the last pose kept for the relocalization when the
// light returns (no reset counted); before a map exists the initialization waits for the light.
TrackResult Tracker::Impl::darkFrame(SteadyClock::time_point t_start, TrackResult res) {
  const bool has_map = state == TrackingState::kTracking || state == TrackingState::kLost;
  const bool was_tracking = state == TrackingState::kTracking && map_settled;
  updateStats([&](TrackerStats& s) {
    s.dark_frames++;
    if (has_map || reinitializing) s.lost_frames++;
    if (was_tracking) s.lost_events++;
  });
  if (!has_map) return notTracked(reinitializing ? TrackingState::kLost : state.load(), t_start, res);
  signal.darkFrame();
  state = TrackingState::kLost;
  if (have_velocity) velocity_before_dark = velocity, have_velocity_before_dark = true;
  have_velocity = false;
  health.restart();
  return notTracked(TrackingState::kLost, t_start, res);
}

void Tracker::Impl::resetMap() {
  mapper.clearQueue();
  map.clear();
  initializer.clearReference();
  metric_map = false;
  have_velocity = false;
  have_velocity_before_dark = false;
  last_kf_id = -1;
  last_ref_kf = -1;
  frames_since_kf = 0;
  kf_close_untracked_share = 0.0;
  forward_window.clear();
  scale_monitor.restart();
  consecutive_lost = 0;
  map_settled = true;
  state = TrackingState::kNotInitialized;
}

void Tracker::Impl::onTracked(const Frame& cur, TrackResult* res, bool is_keyframe) {
  // A young map below init_min_map_baseline is tracked and mapped, its frames reported INITIALIZING (no pose).
  res->state = map_settled ? TrackingState::kTracking : TrackingState::kInitializing;
  res->is_keyframe = is_keyframe;
  res->T_w_c = cur.T_c_w.inverse();
  if (res->initialized_now) covariance_calibrator.start(cur.T_c_w, cur.index);
  else res->covariance = covariance_calibrator.calibrate(res->covariance, res->median_chi2, cur.T_c_w, cur.index);
  res->keypoint_inlier.assign(cur.point_id.size(), 0);
  for (size_t i = 0; i < cur.point_id.size(); ++i) res->keypoint_inlier[i] = cur.point_id[i] >= 0;
  last_good_T_w_c = res->T_w_c;
  have_last_good = true;
  last = cur;
  Eigen::Isometry3d T_kf;
  last_ref_kf = map.keyframePose(last_kf_id, &T_kf) ? last_kf_id : -1;
  T_last_rel_kf = last_ref_kf >= 0 ? cur.T_c_w * T_kf.inverse() : Eigen::Isometry3d::Identity();
  res->reference_keyframe_id = last_ref_kf;
  res->T_kf_c = T_last_rel_kf.inverse();
  if (map_settled) updateStats([](TrackerStats& s) { s.tracked++; });
}

// ============================================================================================
Tracker::Tracker(CameraModelPtr camera, const TrackerParams& params) {
  if (!camera) throw std::invalid_argument("Tracker: camera model is null");
  const std::string err = validate(params);
  if (!err.empty()) throw std::invalid_argument("Tracker: " + err);
  impl_ = std::make_unique<Impl>(std::move(camera), params);
  impl_->rig.left = impl_->cam;
}

Tracker::Tracker(const StereoRig& rig, const TrackerParams& params) {
  std::string err = validate(rig);
  if (!err.empty()) throw std::invalid_argument("Tracker: " + err);
  err = validate(params);
  if (!err.empty()) throw std::invalid_argument("Tracker: " + err);
  impl_ = std::make_unique<Impl>(rig.left, params, rig);
}

Tracker::~Tracker() = default;

TrackResult Tracker::track(const FeatureFrame& frame) { return impl_->track(frame); }
TrackResult Tracker::track(const FeatureFrame& left, const FeatureFrame* right) {
  if (!right || right->keypoints.empty()) return impl_->track(left);
  return impl_->track(left, true, [right] { return *right; });
}
TrackResult Tracker::track(const FeatureFrame& left, bool has_right, RightFeatures right) {
  return impl_->track(left, has_right, std::move(right));
}
bool Tracker::isStereo() const { return impl_->rig.right != nullptr; }
const StereoRig& Tracker::rig() const { return impl_->rig; }
std::vector<Eigen::Vector3d> Tracker::mapPoints() const { return impl_->map.pointPositions(); }
std::vector<KeyframePose> Tracker::keyframePoses() const { return impl_->map.keyframePoses(); }

TrackerStats Tracker::stats() const {
  TrackerStats s;
  {
    std::lock_guard<std::mutex> lk(impl_->stats_mutex);
    s = impl_->stats;
  }
  const LocalMapperStats m = impl_->mapper.stats();
  s.ba_runs = m.ba_runs;
  s.ba_ms_total = m.ba_ms_total;
  s.ba_cpu_ms_total = m.ba_cpu_ms_total;
  s.ba_final_rmse_px = m.ba_final_rmse_px;
  return s;
}

TrackingState Tracker::state() const { return impl_->state.load(); }
const TrackerParams& Tracker::params() const { return impl_->p; }
void Tracker::waitForMapping() { impl_->mapper.waitUntilIdle(); }

}  // namespace iraf_vo
