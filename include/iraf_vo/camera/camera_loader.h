// Camera construction: validated factory + yaml loader/writer (yaml-cpp, ROS-free).
//
// Accepted yaml layouts (auto-detected):
//  1. EuRoC / Kalibr sensor.yaml:  camera_model: pinhole, intrinsics: [fu, fv, cu, cv],
//     distortion_model: radial-tangential | radtan | equidistant | equi | none,
//     distortion_coefficients (or distortion_coeffs): [k1, k2, p1, p2] or [k1, k2, k3, k4],
//     resolution: [w, h], optional T_BS: {rows: 4, cols: 4, data: [16 values, row-major]}.
//     A leading "%YAML:1.0" directive line (OpenCV style, as in EuRoC files) is stripped before parsing.
//  2. Kalibr camchain: the same keys under a top-level "cam0" map; T_cam_imu (4x4 nested list) gives
//     T_BS = inverse(T_cam_imu).
//  3. ROS camera_info yaml (camera_calibration_parsers): image_width, image_height, camera_name,
//     camera_matrix {rows: 3, cols: 3, data: [fx 0 cx 0 fy cy 0 0 1]},
//     distortion_model: plumb_bob (4 or 5 coefficients k1 k2 p1 p2 [k3]) | equidistant (k1..k4),
//     distortion_coefficients {rows, cols, data}.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"

namespace iraf_vo {

/// Model names: "pinhole-radtan" (params fx fy cx cy k1 k2 p1 p2 [k3]) or "kannala-brandt"
/// (params fx fy cx cy k1 k2 k3 k4). Validates everything (finite values, fx, fy > 0, width, height > 0,
/// parameter count); returns nullptr and fills *error (if non-null) on failure.
CameraModelPtr makeCamera(const std::string& model, int width, int height, const std::vector<double>& params,
                          std::string* error, const Eigen::Matrix4d& T_BS = Eigen::Matrix4d::Identity());

/// Loads a camera yaml (any layout above). nullptr + *error naming the file and the key on failure.
CameraModelPtr loadCamera(const std::string& path, std::string* error);

/// Same from yaml text; `source` names it in error messages.
CameraModelPtr loadCameraFromString(const std::string& yaml_text, const std::string& source, std::string* error);

/// Writes the camera in the EuRoC/Kalibr sensor.yaml layout (readable by loadCamera). false + *error on failure.
bool saveCamera(const CameraModel& camera, const std::string& path, std::string* error);

}  // namespace iraf_vo
