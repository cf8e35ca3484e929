// TrackerNodelet: features (iraf_vo/Features) -> odometry, path, map_points, keyframes, tracking_status, TF,
// /diagnostics. Thin: converts messages and publishes what iraf_vo::TrackingSession (run rules: stamps, restarts,
// anchor, trajectory, counters, warnings), iraf_vo::OdometryOutput (base frame, covariance, twist) and
// run_monitor.h (missed frames, rates, status line) return. Calibration: ~camera_file or camera_info (CameraSource).
// Stereo (~stereo): right/features paired with features by StereoFeatureInput; calibration ~camera_file +
// ~right_camera_file (their T_BS) or camera_info + right/camera_info (R and P: stereoExtrinsicsFromCameraInfo);
// ~stereo_images: image_enhanced + right/image_enhanced for the matches' sub-pixel refinement (as offline).
// Frames (REP-103 / REP-105; docs/ros_interface.md "Frames"): world_frame (default odom) = the base frame (~base_frame; empty = the
// camera optical frame, as before) at the start of the map; child = base_frame (or the camera frame).
#include <diagnostic_updater/diagnostic_updater.h>
#include <nav_msgs/Path.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <pluginlib/class_list_macros.hpp>

#include "iraf_vo/Features.h"
#include "iraf_vo/SaveTrajectory.h"
#include "iraf_vo/TrackerConfig.h"
#include "iraf_vo/pipeline/input_watchdog.h"
#include "iraf_vo/pipeline/run_monitor.h"
#include "iraf_vo/pipeline/pipeline_params.h"
#include "iraf_vo/ros/camera_source.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/ros/tracking_conversion.h"
#include "iraf_vo/tracking/tracker_params.h"
#include "stage_nodelet.h"
#include "stereo_feature_input.h"

namespace iraf_vo {

namespace {

/// One console line in rosconsole's layout, flushed at once.
void printAtShutdown(FILE* out, const char* level, const std::string& text) {
  std::fprintf(out, "[%5s] [%.9f]: %s\n", level, ros::WallTime::now().toSec(), text.c_str());
  std::fflush(out);
}

}  // namespace

class TrackerNodelet : public StageNodelet<TrackerParams, iraf_vo::TrackerConfig> {
 public:
  TrackerNodelet() : StageNodelet(trackerParamTable()) {}
  ~TrackerNodelet() override {
    // The summary and the trajectory on shutdown (roslaunch Ctrl-C unloads the nodelets). Printed straight to the
    // console: on Ctrl-C the manager shuts rosconsole down while the nodelets unload, and ROS_INFO lines from here
    // were lost.
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) {
      printAtShutdown(stdout, "INFO", "tracker: " + sessionSummary(session_->counters(), monitor_.missed()));
      std::string err;
      if (!opts_.trajectory_file.empty() && session_->trajectory().size() > 0) {
        if (session_->saveTrajectory(&err))
          printAtShutdown(stdout, "INFO", "tracker: trajectory written to " + opts_.trajectory_file + " (" +
                                              std::to_string(session_->trajectory().size()) + " poses)");
        else
          printAtShutdown(stderr, "ERROR", "tracker: ~trajectory_file " + err);
      }
    }
    session_.reset();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    int queue_size = 10;
    CameraInfoOptions info_opts;
    std::string camera_file;
    pnh.param("queue_size", queue_size, 10);
    pnh.param<std::string>("world_frame", world_frame_, "odom");
    pnh.param<std::string>("camera_frame", camera_frame_, "");
    pnh.param<std::string>("base_frame", base_frame_, "");
    pnh.param("base_from_camera_file", base_from_file_, false);
    pnh.param("publish_tf", publish_tf_, true);
    pnh.param("max_out_of_order", opts_.max_out_of_order, 1.0);
    pnh.param<std::string>("trajectory_file", opts_.trajectory_file, "");
    pnh.param("save_every_keyframe", opts_.save_every_keyframe, true);
    pnh.param("path_max_poses", path_max_poses_, 10000);
    pnh.param("path_publish_period", path_publish_period_, 1.0);
    pnh.param("status_period", status_period_, 10.0);
    pnh.param("use_rectified", info_opts.use_rectified, false);
    pnh.param<std::string>("camera_file", camera_file, "");
    pnh.param("resolution_rule", resolution_rule_, true);
    std::string right_camera_file;
    StereoPairingParams pairing;
    pnh.param("stereo", stereo_, false);
    pnh.param<std::string>("right_camera_file", right_camera_file, "");
    pnh.param("stereo_sync_tolerance", pairing.tolerance, pairing.tolerance);
    pnh.param("stereo_max_wait", pairing.max_wait, pairing.max_wait);
    bool stereo_images = true;
    pnh.param("stereo_images", stereo_images, true);
    use_rectified_ = info_opts.use_rectified;
    double input_timeout = 3.0;
    pnh.param("input_timeout", input_timeout, 3.0);
    watchdog_.setDeadAfter(input_timeout);

    readStartupParams(TrackerParams(), [](const TrackerParams& p) { return validate(p); });  // ~name: YAML tracker:

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1, true);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
    keyframes_pub_ = nh.advertise<geometry_msgs::PoseArray>("keyframes", 1, true);
    status_pub_ = nh.advertise<iraf_vo::TrackingStatus>("tracking_status", 10);
    events_pub_ = nh.advertise<iraf_vo::TrackingEvent>("tracking_events", 10, true);
    tf_ = std::make_shared<tf2_ros::TransformBroadcaster>();
    static_tf_ = std::make_shared<tf2_ros::StaticTransformBroadcaster>();
    if (!base_frame_.empty()) tf_listener_ = std::make_shared<tf2_ros::TransformListener>(tf_buffer_);
    save_srv_ = pnh.advertiseService("save_trajectory", &TrackerNodelet::saveCb, this);
    reset_srv_ = pnh.advertiseService("reset", &TrackerNodelet::resetCb, this);
    updater_ = makeUpdater(nh, pnh, getName());
    updater_->add("tracking", this, &TrackerNodelet::diagnose);
    startReconfigure();  // its first callback: the startup values
    auto on_camera = [this](CameraSource::Event e, const std::string& text) {
      if (e == CameraSource::Event::kInvalid) NODELET_ERROR("tracker: %s", text.c_str());
      if (e == CameraSource::Event::kChanged) NODELET_WARN("tracker: %s: restarting the tracker (new map)", text.c_str());
      if (e != CameraSource::Event::kInvalid) startSession(text);
    };
    if (stereo_) {
      ros::NodeHandle right_nh(nh, "right");
      right_camera_src_.start(right_nh, right_camera_file, info_opts, on_camera);
      if (camera_file.empty() != right_camera_file.empty())
        NODELET_ERROR("tracker: stereo: give both ~camera_file and ~right_camera_file, or neither (camera_info + "
                      "right/camera_info); the one given is used, the other camera from its camera_info");
    }
    camera_src_.start(nh, camera_file, info_opts, on_camera);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), &TrackerNodelet::timerCb, this);
    sub_ = nh.subscribe("features", queue_size, &TrackerNodelet::featuresCb, this);
    if (stereo_)
      stereo_input_.start(nh, queue_size, pairing, [this](const FeaturesConstPtr& l, const FeaturesConstPtr& r) { track(l, r); },
                          [this](const SessionMessage& m) {
                            std::lock_guard<std::mutex> lock(mutex_);
                            log(m);
                          },
                          [this](const FeaturesConstPtr&) {
                            std::lock_guard<std::mutex> wlock(watchdog_mutex_);
                            for (const SessionMessage& m : right_watchdog_.onFrame(ros::WallTime::now().toSec()))
                              NODELET_INFO("tracker: %s", m.text.c_str());
                          });
    if (stereo_ && stereo_images) stereo_input_.startImages(nh, pnh, static_cast<size_t>(queue_size) + 5);
    {
      std::lock_guard<std::mutex> lock(watchdog_mutex_);
      watchdog_.arm(sub_.getTopic(), ros::WallTime::now().toSec());
      right_watchdog_.setDeadAfter(input_timeout);
      if (stereo_) right_watchdog_.arm(stereo_input_.rightTopic(), ros::WallTime::now().toSec());
    }
    // Silence on the features topic: an error after ~input_timeout s (the enhance nodelet warns about the camera).
    watchdog_timer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
      std::vector<SessionMessage> messages;
      {
        std::lock_guard<std::mutex> lock(watchdog_mutex_);
        messages = watchdog_.check(ros::WallTime::now().toSec());
        // The right camera's silence: a warning (the left frames go on alone meanwhile).
        for (SessionMessage m : right_watchdog_.check(ros::WallTime::now().toSec()))
          if (m.level == SessionMessage::Level::kError) m.level = SessionMessage::Level::kWarn, messages.push_back(m);
      }
      for (const SessionMessage& m : messages) {
        if (m.level == SessionMessage::Level::kError) NODELET_ERROR("tracker: %s", m.text.c_str());
        if (m.level == SessionMessage::Level::kWarn) NODELET_WARN("tracker: %s (tracking with the left camera)", m.text.c_str());
      }
    });
  }

  // A camera configured or changed: a new session once every camera of the rig is known.
  void startSession(const std::string& why) {
    const CameraModelPtr cam = camera_src_.camera();
    if (!cam || (stereo_ && !right_camera_src_.camera())) return;
    StereoRig rig;
    if (stereo_ && !makeRig(&rig)) return;
    if (resolution_rule_) {  // before mutex_: replaceParams takes the reconfigure lock, whose callback takes mutex_
      TrackerParams p = params();
      const std::string rule = applyTrackerResolutionRule(*cam, userSet(), &p);
      replaceParams(p);
      NODELET_INFO("tracker: resolution rule, %s (~parameters given are kept; ~resolution_rule false: off)",
                   rule.c_str());
    }
    std::lock_guard<std::mutex> lock(mutex_);
    NODELET_INFO("tracker: %s, world frame '%s'", why.c_str(), world_frame_.c_str());
    session_ = stereo_ ? std::make_unique<TrackingSession>(rig, params(), opts_)
                       : std::make_unique<TrackingSession>(cam, params(), opts_);
    if (stereo_) NODELET_INFO("tracker: stereo, baseline %.4f m", rig.baseline());
    odom_out_.reset();
    path_ = nav_msgs::Path();
  }

  // Without a calibration: tracking_status with the reason at 1 Hz. Always: /diagnostics.
  void timerCb(const ros::WallTimerEvent&) {
    const std::string reason = camera_src_.reason();
    if (!reason.empty()) {
      status_pub_.publish(toNoCalibrationStatusMsg(reason, ros::Time::now()));
      NODELET_WARN_THROTTLE(10.0, "tracker: %s", reason.c_str());
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      publishPathThrottled(true);
    }
    updater_->force_update();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& d) {
    std::lock_guard<std::mutex> lock(mutex_);
    const CameraModelPtr cam = camera_src_.camera();
    const double now = ros::WallTime::now().toSec();
    HealthReport r = monitor_.health(camera_src_.reason(), cam ? cam->describe() : "",
                                     session_ ? session_->counters() : SessionCounters(), now);
    std::string silence;
    std::lock_guard<std::mutex> wlock(watchdog_mutex_);
    const HealthReport::Level l = watchdog_.level(now, &silence);
    if (l >= r.level && l != HealthReport::kOk) r.level = l, r.summary = silence;
    if (stereo_) {
      // A silent right camera is a WARN: the odometry goes on with the left one.
      if (right_watchdog_.level(now, &silence) != HealthReport::kOk && r.level == HealthReport::kOk)
        r.level = HealthReport::kWarn, r.summary = silence + " (tracking with the left camera only)";
    }
    fillDiagnostics(r, d);
    if (stereo_) {
      const StereoCounters c = stereo_input_.counters();
      d.add("stereo pairs", c.pairs);
      d.add("left-only frames", c.left_only);
      d.add("right frames dropped (unpaired)", c.dropped_right);
      d.add("right camera", stereo_input_.rightMissing() ? "missing" : "ok");
      d.add("stereo pairs without images (not sub-pixel refined)", stereo_input_.unrefinedPairs());
    }
  }

  bool hasListeners() override { return true; }  // the sink of the graph: always subscribed
  void subscribeInputs() override {}
  void unsubscribeInputs() override {}

  void onParams(const TrackerParams& p, const iraf_vo::TrackerConfig&) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) session_->setParams(p);  // before the session exists: the startup values (params())
  }

  std::string changeNote() override {
    std::lock_guard<std::mutex> lock(mutex_);
    return session_ && session_->paramsDeferred()
               ? ": stored, applies at the next reset (~reset service, or when tracking is lost)"
               : "";
  }

  bool resetCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) session_->requestRestart();
    res.success = session_ != nullptr;
    res.message = session_ ? "the tracker restarts on the next frame (new map, path continues)" : camera_src_.reason();
    return true;
  }

  bool saveCb(iraf_vo::SaveTrajectory::Request& req, iraf_vo::SaveTrajectory::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string path = req.path.empty() ? opts_.trajectory_file : req.path;
    std::string err = path.empty() ? "no path given and ~trajectory_file is not set"
                                   : !session_ ? camera_src_.reason() : "";
    res.success = !path.empty() && session_ && session_->saveTrajectory(path, &err);
    res.path = res.success ? path : "";
    res.message = res.success ? "wrote " + std::to_string(session_->trajectory().size()) + " poses to " + path : err;
    if (res.success) NODELET_INFO("tracker: trajectory written to %s (%zu poses)", path.c_str(), session_->trajectory().size());
    else NODELET_ERROR("tracker: save_trajectory: %s", err.c_str());
    return true;
  }

  void log(const SessionMessage& m) {
    if (!monitor_.allow(m, ros::WallTime::now().toSec())) return;
    if (m.level == SessionMessage::Level::kInfo) NODELET_INFO("tracker: %s", m.text.c_str());
    else if (m.level == SessionMessage::Level::kWarn) NODELET_WARN("tracker: %s", m.text.c_str());
    else NODELET_ERROR("tracker: %s", m.text.c_str());
  }

  // The left (or only) camera's features: monitored on arrival, tracked at once (mono) or once paired (stereo).
  void featuresCb(const iraf_vo::FeaturesConstPtr& msg) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const double now = ros::WallTime::now().toSec();
      for (const SessionMessage& m : monitor_.onInput(now, msg->header.stamp.toNSec(), msg->rejected_before)) log(m);
      std::lock_guard<std::mutex> wlock(watchdog_mutex_);
      for (const SessionMessage& m : watchdog_.onFrame(now, monitor_.period())) NODELET_INFO("tracker: %s", m.text.c_str());
    }
    if (stereo_) stereo_input_.addLeft(msg);  // calls track() when paired or when the left frame goes alone
    else track(msg, nullptr);
  }

  /// The rig of the two configured cameras: T_r_l from the files' T_BS or from the two camera_info messages.
  bool makeRig(StereoRig* rig) {
    std::string err;
    const CameraModelPtr left = camera_src_.camera(), right = right_camera_src_.camera();
    bool ok = false;
    if (camera_src_.usesFile() && right_camera_src_.usesFile()) {
      ok = makeStereoRig(left, right, rig, &err);
    } else {
      rig->left = left;
      rig->right = right;
      ok = stereoExtrinsicsFromCameraInfo(camera_src_.cameraInfo(), right_camera_src_.cameraInfo(), use_rectified_,
                                          &rig->T_r_l, &err) &&
           (err = validate(*rig)).empty();
    }
    if (!ok) NODELET_ERROR("tracker: stereo: %s: not tracking", err.c_str());
    return ok;
  }

  void track(const iraf_vo::FeaturesConstPtr& msg, const iraf_vo::FeaturesConstPtr& right_msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const double now = ros::WallTime::now().toSec();
    const int64_t stamp_ns = static_cast<int64_t>(msg->header.stamp.toNSec());
    if (!session_) return;  // no calibration: timerCb reports why
    FeatureFrame frame, right;
    std::string err, warning, right_err;
    const bool ok = fromMsg(*msg, &frame, &err, &warning);
    if (!warning.empty()) NODELET_WARN_ONCE("tracker: %s", warning.c_str());
    const bool right_ok = right_msg && fromMsg(*right_msg, &right, &right_err, &warning);
    if (right_msg && !right_ok) NODELET_WARN_THROTTLE(5.0, "tracker: right features: %s", right_err.c_str());
    std::string image_err;  // the pair's images (sub-pixel refinement); without them: one warning, counted
    if (ok && right_ok && stereo_input_.withImages() &&
        !stereo_input_.attachImages(stamp_ns, right_msg->header.stamp.toNSec(), &frame, &right, &image_err))
      NODELET_WARN_ONCE("tracker: stereo: %s: such pairs' stereo matches are not sub-pixel refined (depths less "
                        "accurate; counted in /diagnostics)", image_err.c_str());
    const SessionStep step = session_->process(stamp_ns, ok ? &frame : nullptr, right_ok ? &right : nullptr, err);
    for (const SessionMessage& m : step.messages) log(m);
    if (step.time_jump) path_ = nav_msgs::Path();
    publishEvents(step, msg->header);
    if (step.time_jump || step.result.initialized_now) odom_out_.reset();
    monitor_.onStep(step);
    if (!step.tracked_frame) return;
    const std::string camera_frame = !camera_frame_.empty()          ? camera_frame_
                                     : !msg->header.frame_id.empty() ? msg->header.frame_id
                                                                     : std::string("camera");
    const bool base_ok = resolveBase(camera_frame);
    std_msgs::Header h;
    h.stamp = msg->header.stamp;
    h.frame_id = world_frame_;
    if (step.has_pose && base_ok) publishPose(step, h, base_frame_.empty() ? camera_frame : base_frame_), monitor_.onOdometry(now);
    if (step.map_changed && base_ok) {
      points_pub_.publish(toCloudMsg(odom_out_.toOdom(step.map_points), h));
      keyframes_pub_.publish(toPoseArrayMsg(odom_out_.toOdom(step.keyframe_poses), h));  // camera poses in odom
    }
    iraf_vo::TrackingStatusPtr st = toStatusMsg(step, msg->header, static_cast<int>(frame.keypoints.size()),
                                                msg->ms_threshold + msg->ms_detect + msg->ms_cull);
    st->missed_frames = monitor_.missed();
    status_pub_.publish(st);
    NODELET_INFO_THROTTLE(status_period_, "tracker: %s", monitor_.statusLine(step, now).c_str());
  }

  // tracking_events: the time jump and the new map / scale epoch of this frame.
  void publishEvents(const SessionStep& step, const std_msgs::Header& frame_header) {
    std_msgs::Header h = frame_header;
    h.frame_id = world_frame_;
    if (step.time_jump)
      events_pub_.publish(toEventMsg(iraf_vo::TrackingEvent::TIME_RESET, step.counters.epoch, "time_reset", h));
    if (step.new_epoch) {
      events_pub_.publish(toEventMsg(iraf_vo::TrackingEvent::NEW_MAP, step.counters.epoch, step.epoch_cause, h));
      NODELET_INFO("tracker: map / scale epoch %ld (%s)", step.counters.epoch, step.epoch_cause.c_str());
    }
  }

  // /path at most every ~path_publish_period s (wall), the rest from the 1 Hz timer (force): the whole path is not
  // re-sent at the camera rate. Under mutex_.
  void publishPathThrottled(bool force) {
    const ros::WallTime now = ros::WallTime::now();
    if (!path_dirty_ || (!force && (now - last_path_pub_).toSec() < path_publish_period_)) return;
    path_pub_.publish(boost::make_shared<nav_msgs::Path>(path_));
    last_path_pub_ = now;
    path_dirty_ = false;
  }

  // The static camera -> base transform, once: from the camera yaml's T_BS (~base_from_camera_file) or from TF.
  bool resolveBase(const std::string& camera_frame) {
    if (base_frame_.empty() || have_base_) return true;
    if (base_from_file_) {
      const CameraModelPtr cam = camera_src_.camera();
      odom_out_.setBaseFromCamera(Eigen::Isometry3d(cam->T_BS));
      // The camera frame joins the TF tree: base_frame -> camera frame (static, latched on /tf_static).
      std_msgs::Header h;
      h.stamp = ros::Time::now();
      h.frame_id = base_frame_;
      static_tf_->sendTransform(toTransformMsg(Eigen::Isometry3d(cam->T_BS), h, camera_frame));
      NODELET_INFO("tracker: %s -> %s from the camera file's T_BS (published as a static TF)", camera_frame.c_str(),
                   base_frame_.c_str());
      return have_base_ = true;
    }
    try {
      const auto t = tf_buffer_.lookupTransform(base_frame_, camera_frame, ros::Time(0));
      odom_out_.setBaseFromCamera(fromTransformMsg(t.transform));
      NODELET_INFO("tracker: %s -> %s from TF", camera_frame.c_str(), base_frame_.c_str());
      return have_base_ = true;
    } catch (const tf2::TransformException& e) {
      NODELET_WARN_THROTTLE(2.0, "tracker: no odometry yet: waiting for the static TF %s -> %s (robot_state_publisher"
                            " / static_transform_publisher, or ~base_from_camera_file): %s", base_frame_.c_str(),
                            camera_frame.c_str(), e.what());
      return false;
    }
  }

  void publishPose(const SessionStep& step, const std_msgs::Header& h, const std::string& child) {
    const OdometrySample s = odom_out_.update(h.stamp.toSec(), step.T_world_camera, step.covariance);
    nav_msgs::OdometryPtr odom = toOdometryMsg(s, h, child);
    odom_pub_.publish(odom);
    geometry_msgs::PoseStamped ps;
    ps.header = h;
    ps.pose = odom->pose.pose;
    path_.header = h;
    path_.poses.push_back(ps);
    if (path_max_poses_ > 0 && static_cast<int>(path_.poses.size()) > path_max_poses_)
      path_.poses.erase(path_.poses.begin(), path_.poses.begin() + (path_.poses.size() - path_max_poses_));
    path_dirty_ = true;
    publishPathThrottled(false);
    if (publish_tf_) tf_->sendTransform(toTransformMsg(s.T_odom_base, h, child));
  }

  ros::Subscriber sub_;
  ros::Publisher odom_pub_, path_pub_, points_pub_, keyframes_pub_, status_pub_, events_pub_;
  ros::ServiceServer save_srv_, reset_srv_;
  ros::WallTimer timer_, watchdog_timer_;
  std::mutex watchdog_mutex_;  // watchdog_ (frame callback, its timer, diagnostics)
  InputWatchdog watchdog_{"features"}, right_watchdog_{"right features"};
  std::shared_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::shared_ptr<tf2_ros::StaticTransformBroadcaster> static_tf_;
  tf2_ros::Buffer tf_buffer_;
  std::shared_ptr<tf2_ros::TransformListener> tf_listener_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  std::string world_frame_, camera_frame_, base_frame_;
  bool resolution_rule_ = true;  // size- and focal-dependent fields from the camera (pipeline_params.h)
  bool publish_tf_ = true, base_from_file_ = false;
  int path_max_poses_ = 10000;       // /path keeps the newest poses (<= 0: unbounded)
  double path_publish_period_ = 1.0;  // [s] /path is published at most this often (and by the 1 Hz timer)
  double status_period_ = 10.0;
  SessionOptions opts_;
  CameraSource camera_src_, right_camera_src_;
  bool stereo_ = false, use_rectified_ = false;
  StereoFeatureInput stereo_input_;

  std::mutex mutex_;  // everything below: frame callback, reconfigure, services, timer
  std::unique_ptr<TrackingSession> session_;
  OdometryOutput odom_out_;
  bool have_base_ = false;
  TrackerMonitor monitor_;
  nav_msgs::Path path_;
  bool path_dirty_ = false;
  ros::WallTime last_path_pub_;
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::TrackerNodelet, nodelet::Nodelet)
