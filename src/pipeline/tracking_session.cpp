#include "iraf_vo/pipeline/tracking_session.h"

#include <cstdio>
#include <stdexcept>

namespace iraf_vo {

namespace {

std::string seconds(int64_t ns, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, static_cast<double>(ns) * 1e-9);
  return buf;
}

}  // namespace

TrackingSession::TrackingSession(CameraModelPtr camera, const TrackerParams& params, const SessionOptions& options)
    : camera_(std::move(camera)), options_(options), params_(params), pending_params_(params) {
  if (!camera_) throw std::invalid_argument("TrackingSession: null camera");
}

TrackingSession::~TrackingSession() = default;

void TrackingSession::setParams(const TrackerParams& params) {
  pending_params_ = params;
  params_dirty_ = true;
}

void TrackingSession::requestRestart() { restart_requested_ = true; }

bool TrackingSession::paramsDeferred() const { return tracker_ && tracker_->state() == TrackingState::kTracking; }

SessionCounters TrackingSession::counters() const {
  SessionCounters c = counters_;
  c.resets = internal_resets_base_ + internal_resets_last_ + restarts_;
  return c;
}

void TrackingSession::drop(SessionStep* step, SessionMessage::Level level, const std::string& why) {
  ++counters_.dropped;
  step->messages.push_back({level, "dropping frame " + why, level == SessionMessage::Level::kError ? "error" : "drop"});
  step->counters = counters();
}

void TrackingSession::restartAfterTimeJump(int64_t stamp_ns, SessionStep* step) {
  step->messages.push_back({SessionMessage::Level::kWarn, "time jumped back " + seconds(last_stamp_ns_ - stamp_ns, 3) +
                                                              " s (" + seconds(last_stamp_ns_, 3) + " -> " +
                                                              seconds(stamp_ns, 3) +
                                                              "; bag loop / restart?): new map, the path restarts",
                            "time_jump"});
  ++counters_.time_resets;
  epoch_cause_ = "time_reset";
  tracker_.reset();
  trajectory_ = Trajectory();
  have_last_pose_ = false;
  last_published_ = Eigen::Isometry3d::Identity();
  step->time_jump = true;
}

void TrackingSession::createTracker(const Eigen::Isometry3d& anchor, SessionStep* step) {
  if (tracker_) ++restarts_, epoch_cause_ = "restart";
  tracker_.reset();  // joins the mapping thread of the old one
  try {
    tracker_ = rig_ ? std::make_unique<Tracker>(*rig_, pending_params_)
                    : std::make_unique<Tracker>(camera_, pending_params_);
  } catch (const std::exception& e) {
    step->messages.push_back({SessionMessage::Level::kError,
                              std::string("cannot create the tracker: ") + e.what() + "; keeping the previous parameters",
                              "error"});
    pending_params_ = params_;
    tracker_ = rig_ ? std::make_unique<Tracker>(*rig_, params_) : std::make_unique<Tracker>(camera_, params_);
  }
  params_ = tracker_->params();
  params_dirty_ = false;
  anchor_ = anchor;
  internal_resets_base_ += internal_resets_last_;
  internal_resets_last_ = 0;
}

TrackingSession::TrackingSession(const StereoRig& rig, const TrackerParams& params, const SessionOptions& options)
    : TrackingSession(rig.left, params, options) {
  rig_ = std::make_unique<StereoRig>(rig);
}

SessionStep TrackingSession::process(int64_t stamp_ns, const FeatureFrame* frame, const std::string& frame_error) {
  return process(stamp_ns, frame, nullptr, frame_error);
}

SessionStep TrackingSession::process(int64_t stamp_ns, const FeatureFrame* frame, const FeatureFrame* right,
                                     const std::string& frame_error) {
  SessionStep step;
  // ---- stamp rules ----
  if (have_last_stamp_ && stamp_ns <= last_stamp_ns_) {
    const std::string when = "(stamp " + seconds(stamp_ns, 6) + ", last " + seconds(last_stamp_ns_, 6) + "): ";
    if (stamp_ns == last_stamp_ns_) return drop(&step, SessionMessage::Level::kWarn, when + "duplicated stamp"), step;
    if ((last_stamp_ns_ - stamp_ns) * 1e-9 < options_.max_out_of_order)
      return drop(&step, SessionMessage::Level::kWarn, when + "out-of-order stamp"), step;
    restartAfterTimeJump(stamp_ns, &step);
  }
  const std::string at = "(stamp " + seconds(stamp_ns, 6) + "): ";
  if (!frame) return drop(&step, SessionMessage::Level::kError, at + frame_error), step;
  if (frame->width != camera_->width() || frame->height != camera_->height())
    return drop(&step, SessionMessage::Level::kError,
                at + "image " + std::to_string(frame->width) + "x" + std::to_string(frame->height) +
                    ", but the camera is " + std::to_string(camera_->width()) + "x" +
                    std::to_string(camera_->height())),
           step;
  last_stamp_ns_ = stamp_ns;
  have_last_stamp_ = true;

  // ---- (re)create the tracker when needed ----
  const bool params_changed = params_dirty_;
  if (!tracker_) {
    createTracker(Eigen::Isometry3d::Identity(), &step);
  } else if (restart_requested_ || (params_changed && tracker_->state() != TrackingState::kTracking)) {
    step.messages.push_back({SessionMessage::Level::kWarn,
                             std::string("restarting the tracker") + (params_changed ? " with the new parameters" : "") +
                                 (have_last_pose_ ? " (new map, anchored at the last pose)" : " (new map)"),
                             "restart"});
    createTracker(have_last_pose_ ? last_published_ : Eigen::Isometry3d::Identity(), &step);
  }
  restart_requested_ = false;

  if (rig_ && right && (right->width != rig_->right->width() || right->height != rig_->right->height())) {
    step.messages.push_back({SessionMessage::Level::kError,
                             at + "right image " + std::to_string(right->width) + "x" + std::to_string(right->height) +
                                 ", but the right camera is " + std::to_string(rig_->right->width()) + "x" +
                                 std::to_string(rig_->right->height()) + ": tracked with the left image only",
                             "error"});
    right = nullptr;
  }
  try {
    step.result = rig_ ? tracker_->track(*frame, right) : tracker_->track(*frame);
  } catch (const std::exception& e) {
    tracker_.reset();
    return drop(&step, SessionMessage::Level::kError, at + e.what() + "; restarting the tracker"), step;
  }
  step.tracked_frame = true;
  if (tracker_->stats().resets > internal_resets_last_) {
    step.messages.push_back({SessionMessage::Level::kWarn,
                             "map reset: lost for lost_frames_before_reset frames, initializing a new map", "reset"});
    epoch_cause_ = "map_reset";
  }
  internal_resets_last_ = tracker_->stats().resets;
  countFrame(step.result, &step);
  const TrackResult& r = step.result;
  if (r.state == TrackingState::kTracking) {
    step.has_pose = true;
    step.T_world_camera = anchor_ * r.T_w_c;
    // The anchor is rigid: [position, world rotation] covariance rotates with its rotation.
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    A.topLeftCorner<3, 3>() = A.bottomRightCorner<3, 3>() = anchor_.rotation();
    step.covariance = A * r.covariance * A.transpose();
    last_published_ = step.T_world_camera;
    have_last_pose_ = true;
    trajectory_.push_back(static_cast<double>(stamp_ns) * 1e-9, step.T_world_camera);
  }
  if (r.is_keyframe || r.initialized_now) collectMap(&step);
  std::string err;
  if (r.is_keyframe && options_.save_every_keyframe && !options_.trajectory_file.empty() && !saveTrajectory(&err))
    step.messages.push_back({SessionMessage::Level::kError, err, "error"});
  step.counters = counters();
  return step;
}

void TrackingSession::countFrame(const TrackResult& r, SessionStep* step) {
  using L = SessionMessage::Level;
  ++counters_.frames;
  if (r.state == TrackingState::kTracking) ++counters_.tracked;
  if (r.state == TrackingState::kLost) ++counters_.lost_frames;
  if (!r.rejected.empty()) {
    ++counters_.rejected;
    step->messages.push_back({L::kWarn, "pose rejected by the health monitor: " + r.rejected, "rejected"});
  }
  if (r.state == TrackingState::kLost && last_state_ == TrackingState::kTracking) {
    ++counters_.lost_events;
    step->messages.push_back({L::kWarn, "LOST (" + std::to_string(r.inliers) + " inliers of " +
                                            std::to_string(r.matches) + " matches" +
                                            (r.rejected.empty() ? "" : "; rejected: " + r.rejected) +
                                            (r.too_dark.empty() ? "" : "; " + r.too_dark) +
                                            "): relocalizing, the map resets after lost_frames_before_reset frames" +
                                            (r.too_dark.empty() ? "" : " with signal (dark_relocalization_frames)"),
                              "lost"});
  }
  if (r.relocalized_after_frames > 0)
    step->messages.push_back({L::kInfo,
                              "relocalized in the same map " + std::to_string(r.relocalized_after_frames) +
                                  " frame(s) after the light returned (" + std::to_string(r.inliers) + " inliers)",
                              "relocalized"});
  if (r.initialized_now) {
    ++counters_.epoch;
    step->new_epoch = true;
    step->epoch_cause = counters_.epoch == 1 ? "initial" : epoch_cause_;
    epoch_cause_ = "reinitialized";  // unless a reset / restart / time jump says otherwise before the next map
    if (counters_.initializations > 0)
      step->messages.push_back({L::kWarn, "re-initialized: new map (" + std::to_string(r.inliers) + " inliers)",
                                "reinit"});
    else
      step->messages.push_back({L::kInfo, "initialized (" + std::to_string(r.inliers) + " inliers)", "init"});
    ++counters_.initializations;
  }
  if (r.is_keyframe) ++counters_.keyframes;
  countMetricScale(r, step);
  last_state_ = r.state;
}

void TrackingSession::countMetricScale(const TrackResult& r, SessionStep* step) {
  using L = SessionMessage::Level;
  if (r.initialized_now) counters_.metric_scale_weak = false;  // a new map: the tracker's monitor restarted
  if (r.state != TrackingState::kTracking || r.close_inliers_mean < 0.0) return;  // not a tracked metric map
  counters_.close_inliers_mean = r.close_inliers_mean;
  counters_.metric_scale_weak = r.metric_scale_weak;
  if (r.metric_scale_weak) ++counters_.weak_scale_frames;
  if (!r.metric_scale_changed) return;
  char buf[256];
  if (r.metric_scale_weak) {
    std::snprintf(buf, sizeof(buf),
                  "metric scale weakly observed: %.1f pose inliers per frame near enough for a stereo depth "
                  "(stereo_scale_min_close_inliers): the scale rests on far points and may drift",
                  r.close_inliers_mean);
    step->messages.push_back({L::kWarn, buf, "scale_weak"});
  } else {
    std::snprintf(buf, sizeof(buf), "metric scale observed again: %.1f close pose inliers per frame",
                  r.close_inliers_mean);
    step->messages.push_back({L::kInfo, buf, "scale_ok"});
  }
}

void TrackingSession::collectMap(SessionStep* step) {
  step->map_changed = true;
  for (const Eigen::Vector3d& p : tracker_->mapPoints()) step->map_points.push_back(anchor_ * p);
  for (const KeyframePose& k : tracker_->keyframePoses()) step->keyframe_poses.push_back(anchor_ * k.T_w_c);
  counters_.map_points = static_cast<int>(step->map_points.size());
  counters_.map_keyframes = static_cast<int>(step->keyframe_poses.size());
}

bool TrackingSession::saveTrajectory(std::string* error) const { return saveTrajectory("", error); }

bool TrackingSession::saveTrajectory(const std::string& path, std::string* error) const {
  const std::string& file = path.empty() ? options_.trajectory_file : path;
  if (file.empty()) {
    *error = "no trajectory file set";
    return false;
  }
  std::string err;
  if (writeTumTrajectory(file, trajectory_, &err)) return true;
  *error = file + ": " + err;
  return false;
}

}  // namespace iraf_vo
