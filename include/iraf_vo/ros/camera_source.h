// ROS glue (libiraf_vo_ros): where a nodelet's calibration comes from: `~camera_file` when set, else the camera's
// `camera_info` topic (image_proc style: <camera ns>/camera_info, remapped in the launch files). ROS-free apart from
// the CameraInfo message type; the nodelet owns the subscriber and calls onCameraInfo().
//
//   * file: loaded once (loadFile); an error keeps the source without a camera and gives reason().
//   * camera_info: the first valid message configures (kConfigured); an identical one later is kNone; a different
//     calibration (calibrationDiffers) gives kChanged with the new model (the tracker restarts cleanly); an invalid
//     one gives kInvalid (reason() names the field; a camera configured before stays in use).
#pragma once

#include <ros/node_handle.h>
#include <ros/subscriber.h>
#include <sensor_msgs/CameraInfo.h>

#include <functional>

#include <mutex>
#include <string>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/ros/camera_info.h"

namespace iraf_vo {

class CameraSource {
 public:
  enum class Event { kNone, kConfigured, kChanged, kInvalid };

  using Listener = std::function<void(Event, const std::string& message)>;
  /// A nodelet's setup: camera_file non-empty: loadFile() and on_event(kConfigured | kInvalid) at once; else
  /// camera_info mode on nh's `camera_info` (resolved, remappable) with on_event for every kConfigured / kChanged /
  /// kInvalid message.
  void start(ros::NodeHandle& nh, const std::string& camera_file, const CameraInfoOptions& options, Listener on_event);

  /// Loads ~camera_file; false + reason() on failure.
  bool loadFile(const std::string& path);
  /// camera_info mode (no file): topic is only used in messages.
  void useCameraInfo(const std::string& topic, const CameraInfoOptions& options);
  bool usesFile() const { return !file_.empty(); }

  /// A camera_info message (ignored in file mode: kNone). *message: what to log for kChanged / kInvalid.
  Event onCameraInfo(const sensor_msgs::CameraInfo& info, std::string* message);

  CameraModelPtr camera() const;
  /// The camera_info message in use (camera_info mode, once configured; else an empty message).
  sensor_msgs::CameraInfo cameraInfo() const;
  /// Why there is no camera yet ("" when there is one).
  std::string reason() const;

 private:
  mutable std::mutex mutex_;
  std::string file_, file_error_, topic_, info_error_;
  CameraInfoOptions options_;
  CameraModelPtr camera_;
  bool have_info_ = false;
  sensor_msgs::CameraInfo last_info_;
  ros::Subscriber sub_;
  Listener listener_;
};

}  // namespace iraf_vo
