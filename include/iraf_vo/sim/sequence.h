// Writing simulated sequences and degrading real ones (ROS-free): ASL/EuRoC folder layout
//   OUT/mav0/cam0/data.csv, OUT/mav0/cam0/data/<ns>.png, OUT/mav0/cam0/sensor.yaml,
//   stereo: OUT/mav0/cam1/ the same (right camera, same timestamps, sensor.yaml with T_BS = T_C0_C1),
//   OUT/groundtruth.txt (TUM: "t[s] tx ty tz qx qy qz qw", T_W_C, seconds with 9 decimals),
//   OUT/events.csv (photometric events, frame ranges).
#pragma once

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/sim/image_formation.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/renderer.h"

namespace iraf_vo {

/// The simulator's camera: "pinhole" (EuRoC cam0 pinhole-radtan 752x480), "fisheye" (TUM-VI cam0
/// Kannala-Brandt 512x512), "kitti" (KITTI odometry cam0, 1241x376, f 718.9, rectified), "davis240"
/// (240x180, f 200, radial k1 -0.1 k2 0.02) or a sensor.yaml path (loadCamera). width/height > 0 rescale the built-in
/// intrinsics to that resolution. Returns null and sets *error on failure.
CameraModelPtr makeSimCamera(const std::string& camera, int width, int height, std::string* error);

/// EuRoC/Kalibr sensor.yaml with T_BS (the camera in the body frame; the simulator's body is cam0) and rate_hz.
bool writeSensorYaml(const CameraModel& camera, double rate_hz, const std::string& path, std::string* error,
                     const Eigen::Isometry3d& T_BS = Eigen::Isometry3d::Identity());

/// "sec.nnnnnnnnn" from integer nanoseconds (exact, no floating point).
std::string nsToSecondsString(int64_t ns);
/// TUM line "t tx ty tz qx qy qz qw" (t with 9 decimals).
std::string tumLine(int64_t stamp_ns, const Eigen::Isometry3d& T_W_C);

/// mkdir -p. Returns false (and sets *error) when a component cannot be created.
bool makeDirs(const std::string& path, std::string* error);

struct SimFrame {
  int index = 0;
  int64_t stamp_ns = 0;
  Eigen::Isometry3d T_W_C = Eigen::Isometry3d::Identity();
  cv::Mat image;  // CV_8UC1
  cv::Mat right_image;  // CV_8UC1, stereo simulations: cam1 (same exposure and gain, own sensor noise), else empty
  cv::Mat depth;  // CV_32FC1 z-depth (m) when SimParams::write_depth (or the light profile needs it), else empty
  FrameLight light;  // exposure, gain, scene light of the frame (light-profile simulations)
  FrameLight right_light;  // the same for cam1 (stereo)
};

struct SimulateReport {
  int frames = 0;
  double render_ms = 0.0;       // total rendering time
  double photometric_ms = 0.0;  // total photometric-event time
  double write_ms = 0.0;        // PNG + csv writing
};

/// Renders params.frames frames along the trajectory, applies the photometric events, writes the ASL
/// folder to out_dir (skipped when out_dir is empty) and calls on_frame (optional) for every frame.
/// With SimParams::write_depth also OUT/mav0/depth0/data.csv + data/<ns>.png (CV_16UC1, z-depth in mm,
/// 0 = no hit) of the mid-exposure pose.
bool simulateSequence(const Renderer& renderer, const TrajectoryParams& traj, const PhotometricParams& photometric,
                      const std::string& out_dir, const std::function<void(const SimFrame&)>& on_frame,
                      SimulateReport* report, std::string* error);

/// The same with the camera model: each frame is rendered with the shutter open for the exposure the
/// auto-exposure chose (ImageFormation settles it on frame 0 first), lit and exposed by `light`; also
/// writes OUT/exposure.csv (writeExposureCsv). Glare lamps: where the optical axis meets the scene at
/// evenly spread times of the path.
bool simulateSequence(const Renderer& renderer, const TrajectoryParams& traj, const LightProfile& light,
                      const std::string& out_dir, const std::function<void(const SimFrame&)>& on_frame,
                      SimulateReport* report, std::string* error);

/// Stereo: the same, plus the right camera `right` (its Renderer::setPoseInRig gives T_C0_C1) rendered at
/// the same times with the shutter open as long as the left's, formed with the exposure and gain the
/// left camera's auto-exposure chose and its own sensor noise; writes OUT/mav0/cam1. Ground truth stays
/// the left camera's. `right` null: monocular.
bool simulateSequence(const Renderer& renderer, const Renderer* right, const TrajectoryParams& traj,
                      const LightProfile& light, const std::string& out_dir,
                      const std::function<void(const SimFrame&)>& on_frame, SimulateReport* report,
                      std::string* error);

/// Rows of an ASL data.csv: (timestamp ns, file name). Returns false when the file cannot be read.
bool readAslCsv(const std::string& path, std::vector<std::pair<int64_t, std::string>>* rows, std::string* error);

}  // namespace iraf_vo
