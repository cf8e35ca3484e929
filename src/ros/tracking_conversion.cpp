#include "iraf_vo/ros/tracking_conversion.h"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <boost/make_shared.hpp>
#include <cctype>

namespace iraf_vo {

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& T) {
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

sensor_msgs::PointCloud2Ptr toCloudMsg(const std::vector<Eigen::Vector3d>& points, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2Ptr cloud = boost::make_shared<sensor_msgs::PointCloud2>();
  cloud->header = header;
  sensor_msgs::PointCloud2Modifier mod(*cloud);
  mod.setPointCloud2FieldsByString(1, "xyz");
  mod.resize(points.size());
  sensor_msgs::PointCloud2Iterator<float> x(*cloud, "x"), y(*cloud, "y"), z(*cloud, "z");
  for (const Eigen::Vector3d& p : points) {
    *x = static_cast<float>(p.x());
    *y = static_cast<float>(p.y());
    *z = static_cast<float>(p.z());
    ++x, ++y, ++z;
  }
  return cloud;
}

geometry_msgs::PoseArrayPtr toPoseArrayMsg(const std::vector<Eigen::Isometry3d>& poses,
                                           const std_msgs::Header& header) {
  geometry_msgs::PoseArrayPtr arr = boost::make_shared<geometry_msgs::PoseArray>();
  arr->header = header;
  for (const Eigen::Isometry3d& T : poses) arr->poses.push_back(toPoseMsg(T));
  return arr;
}

std::string stateName(TrackingState s) {
  std::string n = toString(s);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::toupper(c); });
  return n;
}

std::string statusReason(const TrackResult& r) {
  if (!r.too_dark.empty()) return r.too_dark;
  if (!r.rejected.empty()) return r.rejected;
  if (r.state != TrackingState::kTracking && !r.init_status.empty()) return "initializing: " + r.init_status;
  return "";
}

iraf_vo::TrackingStatusPtr toStatusMsg(const SessionStep& step, const std_msgs::Header& header, int keypoints,
                                       double ms_features) {
  const TrackResult& r = step.result;
  const SessionCounters& c = step.counters;
  iraf_vo::TrackingStatusPtr s = boost::make_shared<iraf_vo::TrackingStatus>();
  s->header = header;
  s->state = static_cast<uint8_t>(r.state);
  s->state_name = stateName(r.state);
  s->keypoints = keypoints;
  s->matches = r.matches;
  s->inliers = r.inliers;
  s->is_keyframe = r.is_keyframe;
  s->initialized_now = r.initialized_now;
  s->used_pnp = r.used_pnp;
  s->epoch = static_cast<uint32_t>(c.epoch);
  s->frames = c.frames;
  s->tracked = c.tracked;
  s->lost_frames = c.lost_frames;
  s->lost_events = c.lost_events;
  s->resets = c.resets;
  s->time_resets = c.time_resets;
  s->dropped_frames = c.dropped;
  s->rejected_poses = c.rejected;
  s->reason = statusReason(r);
  s->keyframes = c.keyframes;
  s->map_keyframes = c.map_keyframes;
  s->map_points = c.map_points;
  s->ms_features = ms_features;
  s->ms_prepare = r.timing.ms_prepare;
  s->ms_init = r.timing.ms_init;
  s->ms_match = r.timing.ms_match;
  s->ms_pose = r.timing.ms_pose;
  s->ms_keyframe = r.timing.ms_keyframe;
  s->ms_total = r.timing.ms_total;
  return s;
}

iraf_vo::TrackingEventPtr toEventMsg(const std::string& kind, long epoch, const std::string& cause,
                                     const std_msgs::Header& header) {
  iraf_vo::TrackingEventPtr e = boost::make_shared<iraf_vo::TrackingEvent>();
  e->header = header;
  e->kind = kind;
  e->epoch = static_cast<uint32_t>(epoch);
  e->cause = cause;
  if (kind == iraf_vo::TrackingEvent::TIME_RESET)
    e->text = "the stamps jumped back: the path and the recorded trajectory restart, a new map follows";
  else
    e->text = "map / scale epoch " + std::to_string(epoch) + " starts (" + cause +
              "): poses are not comparable with the previous epoch's";
  return e;
}

iraf_vo::TrackingStatusPtr toNoCalibrationStatusMsg(const std::string& reason, const ros::Time& stamp) {
  iraf_vo::TrackingStatusPtr s = boost::make_shared<iraf_vo::TrackingStatus>();
  s->header.stamp = stamp;
  s->state = static_cast<uint8_t>(TrackingState::kNotInitialized);
  s->state_name = stateName(TrackingState::kNotInitialized);
  s->reason = reason;
  return s;
}

nav_msgs::OdometryPtr toOdometryMsg(const OdometrySample& s, const std_msgs::Header& header,
                                    const std::string& child_frame) {
  nav_msgs::OdometryPtr odom = boost::make_shared<nav_msgs::Odometry>();
  odom->header = header;
  odom->child_frame_id = child_frame;
  odom->pose.pose = toPoseMsg(s.T_odom_base);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) odom->pose.covariance[6 * r + c] = s.pose_covariance(r, c);
  if (s.has_twist) {
    odom->twist.twist.linear.x = s.twist(0);
    odom->twist.twist.linear.y = s.twist(1);
    odom->twist.twist.linear.z = s.twist(2);
    odom->twist.twist.angular.x = s.twist(3);
    odom->twist.twist.angular.y = s.twist(4);
    odom->twist.twist.angular.z = s.twist(5);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) odom->twist.covariance[6 * r + c] = s.twist_covariance(r, c);
  }  // else (first pose of a map): twist and its covariance all zero = not filled (nav_msgs/Odometry has no marker)
  return odom;
}

geometry_msgs::TransformStamped toTransformMsg(const Eigen::Isometry3d& T, const std_msgs::Header& header,
                                               const std::string& child_frame) {
  geometry_msgs::TransformStamped tf;
  tf.header = header;
  tf.child_frame_id = child_frame;
  const geometry_msgs::Pose p = toPoseMsg(T);
  tf.transform.translation.x = p.position.x;
  tf.transform.translation.y = p.position.y;
  tf.transform.translation.z = p.position.z;
  tf.transform.rotation = p.orientation;
  return tf;
}

Eigen::Isometry3d fromTransformMsg(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return T;
}

}  // namespace iraf_vo
