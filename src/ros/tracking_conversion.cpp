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
  s->frames = c.frames;
  s->tracked = c.tracked;
  s->lost_frames = c.lost_frames;
  s->lost_events = c.lost_events;
  s->resets = c.resets;
  s->time_resets = c.time_resets;
  s->dropped_frames = c.dropped;
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

}  // namespace iraf_vo
