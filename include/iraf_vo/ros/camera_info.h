// ROS glue (libiraf_vo_ros, not the core): calibration from sensor_msgs/CameraInfo.
//
// The nodelets use it when `~camera_file` is empty: the first camera_info message of the camera gives the model,
// and calibrationDiffers() tells when a later one changed the calibration (the tracker then restarts cleanly).
#pragma once

#include <sensor_msgs/CameraInfo.h>

#include <Eigen/Geometry>
#include <string>

#include "iraf_vo/camera/camera_model.h"

namespace iraf_vo {

struct CameraInfoOptions {
  /// The images are rectified (e.g. `image_rect` from image_proc): use P's fx fy cx cy, no distortion.
  bool use_rectified = false;
};

/// Builds a core camera model (camera_loader.h's makeCamera) from a CameraInfo message:
///  - distortion_model "plumb_bob" (D = k1 k2 p1 p2 [k3]) -> pinhole-radtan;
///  - "rational_polynomial" (D = k1 k2 p1 p2 k3 k4 k5 k6) -> pinhole-radtan when k4 = k5 = k6 = 0, else an error
///    (the core has no rational model);
///  - "equidistant" (D = k1 k2 k3 k4, Kannala-Brandt) -> kannala-brandt;
///  - rectified input: options.use_rectified, an empty D or an all-zero D -> pinhole from P (fx = P[0], fy = P[5],
///    cx = P[2], cy = P[6]) without distortion (K when P is all zeros and the flag is off).
/// Invalid messages (zero width / height, all-zero K = uncalibrated camera, NaN / inf, skew, wrong D length,
/// unknown distortion model, binning or ROI) give nullptr + *error naming the field, e.g.
/// "camera_info: D has 3 values; plumb_bob needs 4 or 5 (k1 k2 p1 p2 [k3])". Never throws.
CameraModelPtr cameraFromCameraInfo(const sensor_msgs::CameraInfo& info, std::string* error,
                                    const CameraInfoOptions& options = CameraInfoOptions());

/// True when a and b describe a different calibration (size, distortion model, D, K, R, P, binning, ROI);
/// the header (stamp, frame_id, seq) is ignored. *what (optional) names the first differing field.
bool calibrationDiffers(const sensor_msgs::CameraInfo& a, const sensor_msgs::CameraInfo& b, std::string* what = nullptr);

/// The left -> right transform of a stereo pair from its two CameraInfo messages, as camera_calibration's stereo
/// calibrator and stereo drivers write them (what stereo_image_proc relies on): R rotates each camera into the common
/// rectified frame, the right P carries Tx = -fx' * baseline (P[3]) and Ty (P[7]). p_r = T_r_l * p_l with
/// T_r_l = R_r^T * (R_l * p_l + t), t = (Tx / fx' - Tx_l / fx_l, Ty / fy' - Ty_l / fy_l, 0).
/// use_rectified (the images are the rectified ones): both R are the identity. false + *error (naming the field)
/// when the right P has no Tx / Ty (not a stereo calibration), fx' is 0 or an R is not a rotation.
bool stereoExtrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
                                    bool use_rectified, Eigen::Isometry3d* T_r_l, std::string* error);

}  // namespace iraf_vo
