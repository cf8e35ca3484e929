#include "iraf_vo/ros/camera_source.h"

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/pipeline/run_monitor.h"

namespace iraf_vo {

void CameraSource::start(ros::NodeHandle& nh, const std::string& camera_file, const CameraInfoOptions& options,
                         Listener on_event) {
  listener_ = std::move(on_event);
  if (!camera_file.empty()) {
    if (loadFile(camera_file))
      listener_(Event::kConfigured, "camera " + camera()->describe() + " from " + camera_file);
    else
      listener_(Event::kInvalid, reason());
    return;
  }
  useCameraInfo(nh.resolveName("camera_info"), options);
  sub_ = nh.subscribe<sensor_msgs::CameraInfo>("camera_info", 2, [this](const sensor_msgs::CameraInfoConstPtr& m) {
    std::string text;
    const Event e = onCameraInfo(*m, &text);
    if (e != Event::kNone && listener_) listener_(e, text);
  });
}

bool CameraSource::loadFile(const std::string& path) {
  std::lock_guard<std::mutex> lock(mutex_);
  file_ = path;
  file_error_.clear();
  camera_ = loadCamera(path, &file_error_);
  return camera_ != nullptr;
}

void CameraSource::useCameraInfo(const std::string& topic, const CameraInfoOptions& options) {
  std::lock_guard<std::mutex> lock(mutex_);
  file_.clear();
  topic_ = topic;
  options_ = options;
}

CameraSource::Event CameraSource::onCameraInfo(const sensor_msgs::CameraInfo& info, std::string* message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!file_.empty()) return Event::kNone;
  std::string what;
  if (have_info_ && camera_ && !calibrationDiffers(last_info_, info, &what)) return Event::kNone;
  std::string error;
  CameraModelPtr cam = cameraFromCameraInfo(info, &error, options_);
  if (!cam) {
    const bool repeated = info_error_ == error;
    info_error_ = error;
    *message = "invalid camera_info on " + topic_ + ": " + error +
               (camera_ ? "; keeping the previous calibration" : "; not tracking");
    return repeated ? Event::kNone : Event::kInvalid;
  }
  const bool changed = camera_ != nullptr;
  info_error_.clear();
  camera_ = cam;
  last_info_ = info;
  have_info_ = true;
  *message = changed ? "calibration changed on " + topic_ + " (" + what + "): " + cam->describe()
                     : "calibration from " + topic_ + ": " + cam->describe();
  return changed ? Event::kChanged : Event::kConfigured;
}

CameraModelPtr CameraSource::camera() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return camera_;
}

sensor_msgs::CameraInfo CameraSource::cameraInfo() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return have_info_ ? last_info_ : sensor_msgs::CameraInfo();
}

std::string CameraSource::reason() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (camera_) return "";
  return calibrationReason(file_, file_error_, topic_, info_error_);
}

}  // namespace iraf_vo
