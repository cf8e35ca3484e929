// The run rules of a live tracker (used by TrackerNodelet; ROS-free): stamp checks, when parameter changes and
// restarts take effect, the anchor that keeps the published trajectory continuous across restarts, the recorded
// trajectory and the counters over every tracker of the session.
//
// Timestamps (never crash, always report):
//   * stamp == last stamp: duplicate, dropped.
//   * last - max_out_of_order < stamp < last: late / out-of-order frame, dropped.
//   * stamp <= last - max_out_of_order (a bag looped or was restarted): new tracker (new map, its world frame = the
//     first camera again); the recorded trajectory restarts.
// Events reported as kWarn messages (the nodelet's ROS_WARN): every dropped frame, a time jump, TRACKING -> LOST
// (with the health monitor's reason when it rejected the pose), a rejected pose, a re-initialization after the first
// one, a map reset inside the core tracker.
// Parameters: the core Tracker takes its parameters at construction. setParams() is applied at once (new tracker)
// while nothing is tracked yet / the tracker is lost; while tracking it waits for the next restart (time jump, or
// requestRestart(): restarts on the next frame). A restart while tracking re-anchors the new map at the last
// published pose, so the trajectory continues (scale of the new map: median depth 1 again).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/tracking/tracker.h"

namespace iraf_vo {

struct SessionOptions {
  double max_out_of_order = 1.0;    // [s] older stamps within this window are dropped, older ones restart the map
  std::string trajectory_file;      // TUM file of the recorded trajectory ("" = none)
  bool save_every_keyframe = true;  // rewrite trajectory_file at every keyframe
};

/// Counters over every tracker of the session.
struct SessionCounters {
  long frames = 0, tracked = 0, lost_frames = 0, lost_events = 0, keyframes = 0, dropped = 0;
  long resets = 0;                        // map resets inside the core trackers + session restarts
  long time_resets = 0;                   // restarts after a time jump back
  long rejected = 0;                      // poses rejected by the core's health monitor (reported LOST)
  long initializations = 0;               // completed (re-)initializations
  long epoch = 0;                         // map / scale epoch: 0 before the first map, +1 at every new map
  int map_points = 0, map_keyframes = 0;  // of the last published map
  // Stereo (TrackResult::close_inliers_mean / metric_scale_weak of the last tracked frame of a metric map):
  double close_inliers_mean = -1.0;       // -1: monocular, or no metric map tracked yet
  bool metric_scale_weak = false;
  long weak_scale_frames = 0;             // tracked frames with a weakly observed metric scale
};

struct SessionMessage {
  enum class Level { kInfo, kWarn, kError };
  Level level = Level::kInfo;
  std::string text;
  /// What happened, for per-kind console throttling: "drop", "time_jump", "lost", "rejected", "reinit", "reset",
  /// "restart", "relocalized", "scale_weak", "scale_ok", "error".
  std::string key;
};

/// What one frame produced: what to publish and what to log.
struct SessionStep {
  bool tracked_frame = false;  // false: the frame was dropped (messages say why)
  bool time_jump = false;      // the map and the recorded trajectory restarted: restart published paths too
  bool new_epoch = false;      // this frame starts a new map / scale epoch (counters.epoch)
  std::string epoch_cause;     // then why: initial | reinitialized | map_reset | restart | time_reset
  TrackResult result;
  bool has_pose = false;                                             // result.state == kTracking
  Eigen::Isometry3d T_world_camera = Eigen::Isometry3d::Identity();  // anchored
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();  // of T_world_camera (anchored)
  bool map_changed = false;                       // keyframe or initialization: map_points / keyframe_poses are set
  std::vector<Eigen::Vector3d> map_points;        // anchored
  std::vector<Eigen::Isometry3d> keyframe_poses;  // anchored T_world_camera, oldest first
  SessionCounters counters;
  std::vector<SessionMessage> messages;
};

class TrackingSession {
 public:
  /// Throws std::invalid_argument for a null camera.
  TrackingSession(CameraModelPtr camera, const TrackerParams& params, const SessionOptions& options);
  /// A stereo camera (validated by the caller; its left camera is the camera of the frames): stereo trackers.
  TrackingSession(const StereoRig& rig, const TrackerParams& params, const SessionOptions& options);
  ~TrackingSession();

  /// One frame. `frame` null: it could not be decoded (`frame_error` says why): the stamp rules still apply, then it
  /// is dropped.
  SessionStep process(int64_t stamp_ns, const FeatureFrame* frame, const std::string& frame_error = "");
  /// A stereo frame: `right` null = no right image for this frame (Tracker::track(left, nullptr)); a right frame of
  /// another size than the right camera is not used (an error message says so). Monocular session: right ignored.
  SessionStep process(int64_t stamp_ns, const FeatureFrame* frame, const FeatureFrame* right,
                      const std::string& frame_error = "");
  bool isStereo() const { return rig_ != nullptr; }

  /// New parameters (validated by the caller): applied at the next frame unless tracking, else at the next restart.
  void setParams(const TrackerParams& params);
  /// Restart (new map, trajectory continues) at the next frame.
  void requestRestart();
  /// True when setParams() would wait for the next restart (the tracker is tracking).
  bool paramsDeferred() const;

  /// The parameters of the current tracker (setParams() values once applied).
  const TrackerParams& params() const { return params_; }
  const Trajectory& trajectory() const { return trajectory_; }
  /// Writes the recorded trajectory to options.trajectory_file. false + *error.
  bool saveTrajectory(std::string* error) const;
  /// Writes it to `path` ("" = options.trajectory_file). false + *error naming the file.
  bool saveTrajectory(const std::string& path, std::string* error) const;
  SessionCounters counters() const;

 private:
  void drop(SessionStep* step, SessionMessage::Level level, const std::string& why);
  void createTracker(const Eigen::Isometry3d& anchor, SessionStep* step);
  void restartAfterTimeJump(int64_t stamp_ns, SessionStep* step);
  void countFrame(const TrackResult& r, SessionStep* step);
  void countMetricScale(const TrackResult& r, SessionStep* step);
  void collectMap(SessionStep* step);

  CameraModelPtr camera_;
  std::unique_ptr<StereoRig> rig_;  // null: monocular
  SessionOptions options_;
  TrackerParams params_, pending_params_;
  bool params_dirty_ = false, restart_requested_ = false;
  std::unique_ptr<Tracker> tracker_;
  Eigen::Isometry3d anchor_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_published_ = Eigen::Isometry3d::Identity();
  bool have_last_pose_ = false;
  int64_t last_stamp_ns_ = 0;
  bool have_last_stamp_ = false;
  TrackingState last_state_ = TrackingState::kNotInitialized;
  SessionCounters counters_;
  long restarts_ = 0, internal_resets_base_ = 0, internal_resets_last_ = 0;
  std::string epoch_cause_ = "initial";  // why the next map starts (set when the current one ends)
  Trajectory trajectory_;
};

}  // namespace iraf_vo
