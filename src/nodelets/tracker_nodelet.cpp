// TrackerNodelet: features (iraf_vo/Features) -> odometry, path, map_points, keyframes, tracking_status + TF.
// Thin: converts messages and publishes what iraf_vo::TrackingSession (the ROS-free run rules around the core
// Tracker: stamp checks, parameter restarts, anchor, recorded trajectory, counters) returns for each frame.
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
// Timestamps and parameter changes (dynamic_reconfigure, cfg/Tracker.cfg; the `~reset` service): see
// include/iraf_vo/pipeline/tracking_session.h. A time jump back restarts the published path too.
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <pluginlib/class_list_macros.hpp>

#include "iraf_vo/Features.h"
#include "iraf_vo/TrackerConfig.h"
#include "iraf_vo/TrackingStatus.h"
#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/pipeline/tracking_session.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/ros/tracking_conversion.h"
#include "iraf_vo/tracking/tracker_params_io.h"
#include "stage_nodelet.h"

namespace iraf_vo {

class TrackerNodelet : public StageNodelet<TrackerParams, iraf_vo::TrackerConfig> {
 public:
  TrackerNodelet() : StageNodelet(trackerParamTable()) {}
  ~TrackerNodelet() override {
    // Record the trajectory on shutdown (roslaunch Ctrl-C unloads the nodelets).
    std::lock_guard<std::mutex> lock(mutex_);
    std::string err;
    if (session_ && !trajectory_file_.empty() && session_->trajectory().size() > 0 && !session_->saveTrajectory(&err))
      ROS_ERROR("tracker: ~trajectory_file %s", err.c_str());
    session_.reset();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    int queue_size = 10;
    SessionOptions opts;
    pnh.param("queue_size", queue_size, 10);
    pnh.param<std::string>("world_frame", world_frame_, "odom");
    pnh.param<std::string>("camera_frame", camera_frame_, "");
    pnh.param("publish_tf", publish_tf_, true);
    pnh.param("max_out_of_order", opts.max_out_of_order, 1.0);
    pnh.param<std::string>("trajectory_file", opts.trajectory_file, "");
    pnh.param("save_every_keyframe", opts.save_every_keyframe, true);
    pnh.param("path_publish_every", path_publish_every_, 1);
    path_publish_every_ = std::max(1, path_publish_every_);
    trajectory_file_ = opts.trajectory_file;

    // Every TrackerParams field may be set from ~name (e.g. the YAML `tracker:` section); bad values name the key.
    TrackerParams p;
    std::vector<std::string> errors;
    readPrivateParams(table(), pnh, &p, &errors);
    for (const std::string& e : errors) NODELET_ERROR("tracker: %s", e.c_str());
    const std::string err = validate(p);
    if (!err.empty()) NODELET_ERROR("tracker: %s; using the defaults", err.c_str());
    setParams(err.empty() ? p : TrackerParams());

    std::string camera_file, cam_err;
    pnh.param<std::string>("camera_file", camera_file, "");
    CameraModelPtr camera;
    if (camera_file.empty()) {
      NODELET_ERROR(
          "tracker: ~camera_file is not set (a calibration yaml, e.g. $(find iraf_vo)/config/euroc_cam0.yaml)"
          "; not tracking");
    } else if (!(camera = loadCamera(camera_file, &cam_err))) {
      NODELET_ERROR("tracker: ~camera_file %s: %s; not tracking", camera_file.c_str(), cam_err.c_str());
    } else {
      NODELET_INFO("tracker: camera %s, world frame '%s'", camera->describe().c_str(), world_frame_.c_str());
    }

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry", 10);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1, true);
    points_pub_ = nh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
    keyframes_pub_ = nh.advertise<geometry_msgs::PoseArray>("keyframes", 1, true);
    status_pub_ = nh.advertise<iraf_vo::TrackingStatus>("tracking_status", 10);
    tf_ = std::make_shared<tf2_ros::TransformBroadcaster>();
    save_srv_ = pnh.advertiseService("save_trajectory", &TrackerNodelet::saveCb, this);
    reset_srv_ = pnh.advertiseService("reset", &TrackerNodelet::resetCb, this);
    startReconfigure();  // its first callback: the startup values
    if (!camera) return;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      session_ = std::make_unique<TrackingSession>(camera, params(), opts);
    }
    sub_ = nh.subscribe("features", queue_size, &TrackerNodelet::featuresCb, this);
  }

  // The tracker subscribes whenever it has a camera (its outputs are latched / TF).
  bool hasListeners() override { return true; }
  void subscribeInputs() override {}
  void unsubscribeInputs() override {}

  void onParams(const TrackerParams& p, const iraf_vo::TrackerConfig&) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) session_->setParams(p);  // before the session exists: the startup values (params())
  }

  bool resetCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) session_->requestRestart();
    res.success = true;
    res.message = "the tracker restarts on the next frame (new map, path continues)";
    return true;
  }

  bool saveCb(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string err;
    res.success = !trajectory_file_.empty() && session_ && session_->saveTrajectory(&err);
    res.message = trajectory_file_.empty() ? "~trajectory_file is not set"
                  : res.success
                      ? "wrote " + std::to_string(session_->trajectory().size()) + " poses to " + trajectory_file_
                      : err;
    return true;
  }

  void featuresCb(const iraf_vo::FeaturesConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    FeatureFrame frame;
    std::string err, warning;
    const bool ok = fromMsg(*msg, &frame, &err, &warning);
    if (!warning.empty()) NODELET_WARN_ONCE("tracker: %s", warning.c_str());
    const SessionStep step =
        session_->process(static_cast<int64_t>(msg->header.stamp.toNSec()), ok ? &frame : nullptr, err);
    for (const SessionMessage& m : step.messages) {
      if (m.level == SessionMessage::Level::kInfo)
        NODELET_INFO("tracker: %s", m.text.c_str());
      else if (m.level == SessionMessage::Level::kWarn)
        NODELET_WARN_THROTTLE(2.0, "tracker: %s", m.text.c_str());
      else
        NODELET_ERROR_THROTTLE(5.0, "tracker: %s", m.text.c_str());
    }
    if (step.time_jump) path_ = nav_msgs::Path();
    if (!step.tracked_frame) return;
    const std::string camera_frame = !camera_frame_.empty()          ? camera_frame_
                                     : !msg->header.frame_id.empty() ? msg->header.frame_id
                                                                     : std::string("camera");
    if (step.has_pose) publishPose(step.T_world_camera, msg->header.stamp, camera_frame);
    if (step.map_changed) {
      std_msgs::Header h;
      h.stamp = msg->header.stamp;
      h.frame_id = world_frame_;
      points_pub_.publish(toCloudMsg(step.map_points, h));
      keyframes_pub_.publish(toPoseArrayMsg(step.keyframe_poses, h));
    }
    status_pub_.publish(toStatusMsg(step, msg->header, static_cast<int>(frame.keypoints.size()),
                                    msg->ms_threshold + msg->ms_detect + msg->ms_cull));
    if (!step.has_pose)
      NODELET_DEBUG_THROTTLE(1.0, "tracker: %s (%d inliers)", toString(step.result.state), step.result.inliers);
  }

  void publishPose(const Eigen::Isometry3d& T, const ros::Time& stamp, const std::string& camera_frame) {
    nav_msgs::OdometryPtr odom = boost::make_shared<nav_msgs::Odometry>();
    odom->header.stamp = stamp;
    odom->header.frame_id = world_frame_;
    odom->child_frame_id = camera_frame;
    odom->pose.pose = toPoseMsg(T);
    // Covariance unknown (monocular, arbitrary scale): -1 on the diagonal's first element marks it as unset.
    odom->pose.covariance[0] = -1.0;
    odom->twist.covariance[0] = -1.0;
    odom_pub_.publish(odom);

    geometry_msgs::PoseStamped ps;
    ps.header = odom->header;
    ps.pose = odom->pose.pose;
    path_.header = odom->header;
    path_.poses.push_back(ps);
    if (++path_counter_ % path_publish_every_ == 0) path_pub_.publish(boost::make_shared<nav_msgs::Path>(path_));

    if (publish_tf_) {
      geometry_msgs::TransformStamped tf;
      tf.header = odom->header;
      tf.child_frame_id = camera_frame;
      tf.transform.translation.x = ps.pose.position.x;
      tf.transform.translation.y = ps.pose.position.y;
      tf.transform.translation.z = ps.pose.position.z;
      tf.transform.rotation = ps.pose.orientation;
      tf_->sendTransform(tf);
    }
  }

  ros::Subscriber sub_;
  ros::Publisher odom_pub_, path_pub_, points_pub_, keyframes_pub_, status_pub_;
  ros::ServiceServer save_srv_, reset_srv_;
  std::shared_ptr<tf2_ros::TransformBroadcaster> tf_;
  std::string world_frame_, camera_frame_, trajectory_file_;
  bool publish_tf_ = true;
  int path_publish_every_ = 1;

  std::mutex mutex_;  // everything below: frame callback, reconfigure, services
  std::unique_ptr<TrackingSession> session_;
  nav_msgs::Path path_;
  long path_counter_ = 0;
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::TrackerNodelet, nodelet::Nodelet)
