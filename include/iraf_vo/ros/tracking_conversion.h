// ROS glue (not part of the ROS-free core): tracking results -> geometry / sensor / iraf_vo messages.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "iraf_vo/TrackingEvent.h"
#include "iraf_vo/TrackingStatus.h"
#include "iraf_vo/pipeline/odometry_output.h"
#include "iraf_vo/pipeline/tracking_session.h"

namespace iraf_vo {

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& T);
/// xyz float32 cloud.
sensor_msgs::PointCloud2Ptr toCloudMsg(const std::vector<Eigen::Vector3d>& points, const std_msgs::Header& header);
geometry_msgs::PoseArrayPtr toPoseArrayMsg(const std::vector<Eigen::Isometry3d>& poses, const std_msgs::Header& header);
/// TrackingStatus.state_name: NOT_INITIALIZED | INITIALIZING | TRACKING | LOST (= toString(state) in capitals).
std::string stateName(TrackingState s);
/// TrackingStatus.reason of a frame: the health monitor's rejection, else while (re-)initializing why this frame did
/// not initialize the map ("initializing: <the initializer's reason>"), else "".
std::string statusReason(const TrackResult& r);
/// The status of one processed frame: its result, the session counters, its keypoints and feature-stage time.
iraf_vo::TrackingStatusPtr toStatusMsg(const SessionStep& step, const std_msgs::Header& header, int keypoints,
                                       double ms_features);
/// The 1 Hz status while there is no calibration: state NOT_INITIALIZED, reason set, counters zero.
iraf_vo::TrackingStatusPtr toNoCalibrationStatusMsg(const std::string& reason, const ros::Time& stamp);
/// A discontinuity for `tracking_events`: kind TrackingEvent::NEW_MAP (cause: SessionStep::epoch_cause) or TIME_RESET.
iraf_vo::TrackingEventPtr toEventMsg(const std::string& kind, long epoch, const std::string& cause,
                                     const std_msgs::Header& header);
/// Odometry (pose + covariance; twist + covariance when known, else both all zero: not filled) of header.frame_id ->
/// child_frame.
nav_msgs::OdometryPtr toOdometryMsg(const OdometrySample& s, const std_msgs::Header& header,
                                    const std::string& child_frame);
geometry_msgs::TransformStamped toTransformMsg(const Eigen::Isometry3d& T, const std_msgs::Header& header,
                                               const std::string& child_frame);
/// tf2 transform -> Eigen.
Eigen::Isometry3d fromTransformMsg(const geometry_msgs::Transform& t);

}  // namespace iraf_vo
