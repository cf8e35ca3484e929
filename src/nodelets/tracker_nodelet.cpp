// TrackerNodelet: features (iraf_vo/Features) -> odometry, path, map_points, keyframes, tracking_status + TF.
// Thin: converts messages, holds the dynamic_reconfigure server, runs iraf_vo::Tracker (the ROS-free core, the same
// one iraf_vo_run uses) and keeps the published trajectory.
//
// Frames (REP-103 / REP-105):
//   * Poses are T_world_camera of the camera OPTICAL frame (REP-103 optical convention: z forward, x right,
//     y down), exactly the core's T_w_c.
//   * world_frame (default "odom") is the optical frame of the camera at the first initialization (not gravity
//     aligned: monocular VO has no gravity; its z axis is the initial viewing direction). Default "odom" because
//     this is drifting odometry without loop closure: REP-105's odom frame is continuous and drifts, while map is
//     expected to be globally consistent. Set ~world_frame:=map when this is the only pose source.
//   * camera_frame (~camera_frame, default: the image header's frame_id, e.g. cam0) is the child of the
//     odometry and of the TF world_frame -> camera_frame.
//   * Monocular scale: the first map has median scene depth 1 (arbitrary units).
//
// Timestamps (never crash, always log):
//   * stamp == last stamp: duplicate, dropped (ROS_WARN throttled).
//   * last - max_out_of_order < stamp < last: late / out-of-order frame, dropped (warning).
//   * stamp <= last - max_out_of_order (the bag looped or was restarted): warning, new tracker (new map, its
//     world frame = first camera again), the path and the recorded trajectory restart.
//
// Parameter changes (dynamic_reconfigure, cfg/Tracker.cfg): the core Tracker takes its parameters at
// construction. A change is applied at once (new tracker) while nothing is tracked yet / the tracker is lost;
// while tracking it waits for the next restart (time jump, or the `~reset` service: restarts on the next frame). A restart
// while tracking re-anchors the new map at the last published pose, so the path continues (scale of the new map:
// median depth 1 again; the core's loss recovery has the same caveat).
#include <dynamic_reconfigure/server.h>
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <boost/thread/recursive_mutex.hpp>
#include <cmath>
#include <memory>
#include <mutex>
#include <sstream>

#include "iraf_vo/Features.h"
#include "iraf_vo/TrackerConfig.h"
#include "iraf_vo/TrackingStatus.h"
#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/tracking/tracker.h"
#include "iraf_vo/tracking/tracker_params_io.h"

namespace iraf_vo {

namespace {

/// Copies every cfg field into TrackerParams by name (cfg/Tracker.cfg = TrackerParams field for field, checked by
/// test_tracking_params). false + *error naming the field when one is rejected.
bool toParams(const iraf_vo::TrackerConfig& c, TrackerParams* p, std::string* error) {
  for (const auto& d : iraf_vo::TrackerConfig::__getParamDescriptions__()) {
    boost::any v;
    d->getValue(c, v);
    std::ostringstream s;
    s.precision(17);
    if (d->type == "int") s << boost::any_cast<int>(v);
    else if (d->type == "double") s << boost::any_cast<double>(v);
    else if (d->type == "bool") s << (boost::any_cast<bool>(v) ? "true" : "false");
    else s << boost::any_cast<std::string>(v);
    if (!setTrackerParam(p, d->name, s.str(), error)) return false;
  }
  return true;
}

/// XmlRpc scalar -> text for setTrackerParam.
bool xmlToString(XmlRpc::XmlRpcValue& v, std::string* out) {
  std::ostringstream s;
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: s << (static_cast<bool>(v) ? "true" : "false"); break;
    case XmlRpc::XmlRpcValue::TypeInt: s << static_cast<int>(v); break;
    case XmlRpc::XmlRpcValue::TypeDouble: s.precision(17); s << static_cast<double>(v); break;
    case XmlRpc::XmlRpcValue::TypeString: s << static_cast<std::string>(v); break;
    default: return false;
  }
  *out = s.str();
  return true;
}

geometry_msgs::Pose toPose(const Eigen::Isometry3d& T) {
  geometry_msgs::Pose p;
  const Eigen::Quaterniond q(T.rotation());
  p.position.x = T.translation().x();
  p.position.y = T.translation().y();
  p.position.z = T.translation().z();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
  return p;
}

}  // namespace

class TrackerNodelet : public nodelet::Nodelet {
 public:
  ~TrackerNodelet() override {
    // Record the trajectory on shutdown (roslaunch Ctrl-C unloads the nodelets).
    std::lock_guard<std::mutex> lock(mutex_);
    if (!trajectory_file_.empty() && trajectory_.size() > 0) {
      std::string err;
      if (!writeTumTrajectory(trajectory_file_, trajectory_, &err))
        ROS_ERROR("tracker: ~trajectory_file %s: %s", trajectory_file_.c_str(), err.c_str());
    }
    tracker_.reset();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("queue_size", queue_size_, 10);
    pnh.param<std::string>("world_frame", world_frame_, "odom");
    pnh.param<std::string>("camera_frame", camera_frame_, "");
    pnh.param("publish_tf", publish_tf_, true);
    pnh.param("max_out_of_order", max_out_of_order_, 1.0);
    pnh.param<std::string>("trajectory_file", trajectory_file_, "");
    pnh.param("save_every_keyframe", save_every_keyframe_, true);
    pnh.param("path_publish_every", path_publish_every_, 1);
    if (path_publish_every_ < 1) path_publish_every_ = 1;

    // Every TrackerParams field may be set from ~name (e.g. the YAML `tracker:` section); bad values name the key.
    TrackerParams p;
    for (const std::string& name : trackerParamNames()) {
      XmlRpc::XmlRpcValue v;
      if (!pnh.getParam(name, v)) continue;
      std::string text, err;
      if (!xmlToString(v, &text) || !setTrackerParam(&p, name, text, &err))
        NODELET_ERROR("tracker: ignoring ~%s: %s", name.c_str(), err.empty() ? "not a scalar" : err.c_str());
    }
    {
      const std::string err = validate(p);
      if (!err.empty()) {
        NODELET_ERROR("tracker: %s; using the defaults", err.c_str());
        p = TrackerParams();
      }
    }
    params_ = p;
    pending_params_ = p;

    std::string camera_file;
    pnh.param<std::string>("camera_file", camera_file, "");
    std::string err;
    if (camera_file.empty()) {
      NODELET_ERROR("tracker: ~camera_file is not set (a calibration yaml, e.g. $(find iraf_vo)/config/euroc_cam0.yaml)"
                    "; not tracking");
    } else if (!(camera_ = loadCamera(camera_file, &err))) {
      NODELET_ERROR("tracker: ~camera_file %s: %s; not tracking", camera_file.c_str(), err.c_str());
    } else {
      NODELET_INFO("tracker: camera %s, world frame '%s'", camera_->describe().c_str(), world_frame_.c_str());
    }

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1, true);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
    keyframes_pub_ = nh.advertise<geometry_msgs::PoseArray>("keyframes", 1, true);
    status_pub_ = nh.advertise<iraf_vo::TrackingStatus>("tracking_status", 10);
    tf_ = std::make_shared<tf2_ros::TransformBroadcaster>();
    save_srv_ = pnh.advertiseService("save_trajectory", &TrackerNodelet::saveCb, this);
    reset_srv_ = pnh.advertiseService("reset", &TrackerNodelet::resetCb, this);

    reconfigure_ = std::make_shared<ReconfigureServer>(reconfigure_mutex_, pnh);
    reconfigure_->setCallback([this](iraf_vo::TrackerConfig& c, uint32_t) { configure(c); });

    if (camera_) sub_ = nh.subscribe("features", queue_size_, &TrackerNodelet::featuresCb, this);
  }

  void configure(const iraf_vo::TrackerConfig& c) {
    std::lock_guard<std::mutex> lock(mutex_);
    TrackerParams p = pending_params_;
    std::string err;
    if (!toParams(c, &p, &err) || !(err = validate(p)).empty()) {
      NODELET_ERROR("tracker: rejected parameters: %s", err.c_str());
      return;
    }
    pending_params_ = p;
    if (configured_once_) params_dirty_ = true;  // the first call only reports the startup values
    configured_once_ = true;
  }

  bool resetCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    restart_requested_ = true;
    res.success = true;
    res.message = "the tracker restarts on the next frame (new map, path continues)";
    return true;
  }

  bool saveCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (trajectory_file_.empty()) {
      res.success = false;
      res.message = "~trajectory_file is not set";
      return true;
    }
    std::string err;
    res.success = writeTumTrajectory(trajectory_file_, trajectory_, &err);
    res.message = res.success ? "wrote " + std::to_string(trajectory_.size()) + " poses to " + trajectory_file_
                              : trajectory_file_ + ": " + err;
    return true;
  }

  /// New core tracker with pending_params_. `anchor`: the new map's origin in world_frame (continuity).
  bool createTracker(const Eigen::Isometry3d& anchor) {
    if (tracker_) ++restarts_;
    tracker_.reset();  // joins the mapping thread of the old one
    try {
      tracker_ = std::make_unique<Tracker>(camera_, pending_params_);
    } catch (const std::exception& e) {
      NODELET_ERROR("tracker: cannot create the tracker: %s; keeping the previous parameters", e.what());
      pending_params_ = params_;
      tracker_ = std::make_unique<Tracker>(camera_, params_);
    }
    params_ = tracker_->params();
    params_dirty_ = false;
    anchor_ = anchor;
    internal_resets_base_ += internal_resets_last_;
    internal_resets_last_ = 0;
    return true;
  }

  void restartTrajectory() {
    path_ = nav_msgs::Path();
    trajectory_ = Trajectory();
  }

  void drop(const char* why, const iraf_vo::Features& msg) {
    ++dropped_;
    NODELET_WARN_THROTTLE(2.0, "tracker: dropping frame (stamp %.6f, last %.6f): %s", msg.header.stamp.toSec(),
                          last_stamp_.toSec(), why);
  }

  void featuresCb(const iraf_vo::FeaturesConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time stamp = msg->header.stamp;
    // ---- time checks ----
    if (have_last_stamp_) {
      if (stamp == last_stamp_) return drop("duplicated stamp", *msg);
      if (stamp < last_stamp_) {
        if ((last_stamp_ - stamp).toSec() < max_out_of_order_) return drop("out-of-order stamp", *msg);
        NODELET_WARN("tracker: time jumped back %.3f s (%.3f -> %.3f; bag loop / restart?): new map, the path restarts",
                     (last_stamp_ - stamp).toSec(), last_stamp_.toSec(), stamp.toSec());
        ++time_resets_;
        tracker_.reset();
        restartTrajectory();
        have_last_pose_ = false;
        last_published_ = Eigen::Isometry3d::Identity();
      }
    }
    // ---- message -> core frame ----
    FeatureFrame frame;
    std::string err;
    if (!fromMsg(*msg, &frame, &err)) {
      ++dropped_;
      NODELET_ERROR_THROTTLE(5.0, "tracker: dropping frame (stamp %.6f): %s", stamp.toSec(), err.c_str());
      return;
    }
    if (frame.width != camera_->width() || frame.height != camera_->height()) {
      ++dropped_;
      NODELET_ERROR_THROTTLE(5.0, "tracker: dropping frame (stamp %.6f): image %dx%d, but ~camera_file is %dx%d",
                             stamp.toSec(), frame.width, frame.height, camera_->width(), camera_->height());
      return;
    }
    last_stamp_ = stamp;
    have_last_stamp_ = true;
    checkScaleFactor(*msg);

    // ---- (re)create the tracker when needed ----
    const bool params_changed = params_dirty_;
    if (!tracker_) {
      createTracker(Eigen::Isometry3d::Identity());
    } else if (restart_requested_ ||
               (params_changed && tracker_->state() != TrackingState::kTracking)) {
      NODELET_INFO("tracker: restarting the tracker%s", params_changed ? " with the new parameters" : "");
      createTracker(have_last_pose_ ? last_published_ : Eigen::Isometry3d::Identity());
    }
    restart_requested_ = false;

    TrackResult r;
    try {
      r = tracker_->track(frame);
    } catch (const std::exception& e) {
      ++dropped_;
      NODELET_ERROR_THROTTLE(5.0, "tracker: frame %.6f: %s; restarting the tracker", stamp.toSec(), e.what());
      tracker_.reset();
      return;
    }
    const TrackerStats st = tracker_->stats();
    internal_resets_last_ = st.resets;
    // Counters over all trackers of this nodelet.
    ++frames_;
    if (r.state == TrackingState::kTracking) ++tracked_;
    if (r.state == TrackingState::kLost) ++lost_frames_;
    if (r.state == TrackingState::kLost && last_state_ == TrackingState::kTracking) ++lost_events_;
    if (r.is_keyframe) ++keyframes_;
    last_state_ = r.state;

    const std::string camera_frame = !camera_frame_.empty()           ? camera_frame_
                                     : !msg->header.frame_id.empty() ? msg->header.frame_id
                                                                      : std::string("camera");
    if (r.state == TrackingState::kTracking) {
      const Eigen::Isometry3d T = anchor_ * r.T_w_c;
      last_published_ = T;
      have_last_pose_ = true;
      publishPose(T, stamp, camera_frame);
    }
    const bool map_changed = r.is_keyframe || r.initialized_now;
    if (map_changed) publishMap(stamp);
    if (r.is_keyframe && save_every_keyframe_ && !trajectory_file_.empty()) {
      if (!writeTumTrajectory(trajectory_file_, trajectory_, &err))
        NODELET_ERROR_THROTTLE(10.0, "tracker: ~trajectory_file %s: %s", trajectory_file_.c_str(), err.c_str());
    }
    publishStatus(*msg, frame, r, st);
    if (r.state != TrackingState::kTracking) {
      NODELET_DEBUG_THROTTLE(1.0, "tracker: %s (%d inliers)", toString(r.state), r.inliers);
    }
  }

  // Keypoint size = 31 * scale_factor^octave (feature stage): warn once when it disagrees with ~scale_factor.
  void checkScaleFactor(const iraf_vo::Features& msg) {
    if (scale_checked_) return;
    for (size_t i = 0; i < msg.octave.size() && i < msg.size.size(); ++i) {
      if (msg.octave[i] != 1) continue;
      scale_checked_ = true;
      const double s = msg.size[i] / 31.0;
      if (std::abs(s - pending_params_.scale_factor) > 1e-3)
        NODELET_WARN("tracker: the features come from a pyramid with scale %.4f but ~scale_factor is %.4f: set "
                     "/tracker/scale_factor = /features/scale_factor", s, pending_params_.scale_factor);
      return;
    }
  }

  void publishPose(const Eigen::Isometry3d& T, const ros::Time& stamp, const std::string& camera_frame) {
    const geometry_msgs::Pose pose = toPose(T);
    nav_msgs::OdometryPtr odom = boost::make_shared<nav_msgs::Odometry>();
    odom->header.stamp = stamp;
    odom->header.frame_id = world_frame_;
    odom->child_frame_id = camera_frame;
    odom->pose.pose = pose;
    // Covariance unknown (monocular, arbitrary scale): -1 on the diagonal's first element marks it as unset.
    odom->pose.covariance[0] = -1.0;
    odom->twist.covariance[0] = -1.0;
    odom_pub_.publish(odom);

    geometry_msgs::PoseStamped ps;
    ps.header = odom->header;
    ps.pose = pose;
    path_.header = odom->header;
    path_.poses.push_back(ps);
    trajectory_.push_back(stamp.toSec(), T);
    if (++path_counter_ % path_publish_every_ == 0) path_pub_.publish(boost::make_shared<nav_msgs::Path>(path_));

    if (publish_tf_) {
      geometry_msgs::TransformStamped tf;
      tf.header = odom->header;
      tf.child_frame_id = camera_frame;
      tf.transform.translation.x = pose.position.x;
      tf.transform.translation.y = pose.position.y;
      tf.transform.translation.z = pose.position.z;
      tf.transform.rotation = pose.orientation;
      tf_->sendTransform(tf);
    }
  }

  void publishMap(const ros::Time& stamp) {
    const std::vector<Eigen::Vector3d> pts = tracker_->mapPoints();
    sensor_msgs::PointCloud2Ptr cloud = boost::make_shared<sensor_msgs::PointCloud2>();
    cloud->header.stamp = stamp;
    cloud->header.frame_id = world_frame_;
    sensor_msgs::PointCloud2Modifier mod(*cloud);
    mod.setPointCloud2FieldsByString(1, "xyz");
    mod.resize(pts.size());
    sensor_msgs::PointCloud2Iterator<float> x(*cloud, "x"), y(*cloud, "y"), z(*cloud, "z");
    for (const Eigen::Vector3d& p0 : pts) {
      const Eigen::Vector3d p = anchor_ * p0;
      *x = static_cast<float>(p.x());
      *y = static_cast<float>(p.y());
      *z = static_cast<float>(p.z());
      ++x, ++y, ++z;
    }
    map_points_ = static_cast<int>(pts.size());
    points_pub_.publish(cloud);

    const std::vector<KeyframePose> kfs = tracker_->keyframePoses();
    geometry_msgs::PoseArrayPtr arr = boost::make_shared<geometry_msgs::PoseArray>();
    arr->header = cloud->header;
    for (const KeyframePose& k : kfs) arr->poses.push_back(toPose(anchor_ * k.T_w_c));
    map_keyframes_ = static_cast<int>(kfs.size());
    keyframes_pub_.publish(arr);
  }

  void publishStatus(const iraf_vo::Features& msg, const FeatureFrame& frame, const TrackResult& r,
                     const TrackerStats& st) {
    iraf_vo::TrackingStatusPtr s = boost::make_shared<iraf_vo::TrackingStatus>();
    s->header = msg.header;
    s->state = static_cast<uint8_t>(r.state);
    static const char* names[] = {"NOT_INITIALIZED", "INITIALIZING", "TRACKING", "LOST"};
    s->state_name = names[static_cast<int>(r.state) & 3];
    s->keypoints = static_cast<int>(frame.keypoints.size());
    s->matches = r.matches;
    s->inliers = r.inliers;
    s->is_keyframe = r.is_keyframe;
    s->initialized_now = r.initialized_now;
    s->used_pnp = r.used_pnp;
    s->frames = frames_;
    s->tracked = tracked_;
    s->lost_frames = lost_frames_;
    s->lost_events = lost_events_;
    s->resets = internal_resets_base_ + st.resets + restarts_;
    s->time_resets = time_resets_;
    s->dropped_frames = dropped_;
    s->keyframes = keyframes_;
    s->map_keyframes = map_keyframes_;
    s->map_points = map_points_;
    s->ms_features = msg.ms_threshold + msg.ms_detect + msg.ms_cull;
    s->ms_prepare = r.timing.ms_prepare;
    s->ms_init = r.timing.ms_init;
    s->ms_match = r.timing.ms_match;
    s->ms_pose = r.timing.ms_pose;
    s->ms_keyframe = r.timing.ms_keyframe;
    s->ms_total = r.timing.ms_total;
    status_pub_.publish(s);
  }

  using ReconfigureServer = dynamic_reconfigure::Server<iraf_vo::TrackerConfig>;
  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<ReconfigureServer> reconfigure_;

  ros::Subscriber sub_;
  ros::Publisher odom_pub_, path_pub_, points_pub_, keyframes_pub_, status_pub_;
  ros::ServiceServer save_srv_, reset_srv_;
  std::shared_ptr<tf2_ros::TransformBroadcaster> tf_;

  int queue_size_ = 10;
  std::string world_frame_, camera_frame_, trajectory_file_;
  bool publish_tf_ = true, save_every_keyframe_ = true;
  double max_out_of_order_ = 1.0;
  int path_publish_every_ = 1;

  std::mutex mutex_;  // everything below: frame callback, reconfigure, service
  CameraModelPtr camera_;
  TrackerParams params_, pending_params_;
  bool restart_requested_ = false;
  bool params_dirty_ = false, configured_once_ = false;
  bool scale_checked_ = false;
  std::unique_ptr<Tracker> tracker_;
  Eigen::Isometry3d anchor_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_published_ = Eigen::Isometry3d::Identity();
  bool have_last_pose_ = false;
  ros::Time last_stamp_;
  bool have_last_stamp_ = false;
  TrackingState last_state_ = TrackingState::kNotInitialized;
  long frames_ = 0, tracked_ = 0, lost_frames_ = 0, lost_events_ = 0, keyframes_ = 0, dropped_ = 0;
  long time_resets_ = 0, restarts_ = 0, internal_resets_base_ = 0, internal_resets_last_ = 0;
  long path_counter_ = 0;
  int map_points_ = 0, map_keyframes_ = 0;
  nav_msgs::Path path_;
  Trajectory trajectory_;
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::TrackerNodelet, nodelet::Nodelet)
