#include "iraf_vo/ros/camera_info.h"

#include <sensor_msgs/distortion_models.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "iraf_vo/camera/camera_loader.h"

namespace iraf_vo {

namespace {

namespace dm = sensor_msgs::distortion_models;

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

template <typename Array>
bool allZero(const Array& a) {
  return std::all_of(a.begin(), a.end(), [](double v) { return v == 0.0; });
}

/// "" when every value is finite, else "D[2] = nan is not finite".
template <typename Array>
std::string nonFinite(const char* field, const Array& a) {
  for (size_t i = 0; i < a.size(); ++i)
    if (!std::isfinite(a[i])) return std::string(field) + "[" + std::to_string(i) + "] = " + num(a[i]) + " is not finite";
  return "";
}

CameraModelPtr fail(std::string* error, const std::string& msg) {
  if (error) *error = "camera_info: " + msg;
  return nullptr;
}

}  // namespace

CameraModelPtr cameraFromCameraInfo(const sensor_msgs::CameraInfo& info, std::string* error,
                                    const CameraInfoOptions& options) {
  if (info.width == 0 || info.height == 0)
    return fail(error, "width x height = " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                           " must be positive (camera not calibrated or driver not set up?)");
  if (info.width > 100000 || info.height > 100000)
    return fail(error, "width x height = " + std::to_string(info.width) + "x" + std::to_string(info.height) + " is out of range");
  for (const std::string& bad : {nonFinite("K", info.K), nonFinite("D", info.D), nonFinite("P", info.P), nonFinite("R", info.R)})
    if (!bad.empty()) return fail(error, bad);
  const bool roi_full = (info.roi.width == 0 && info.roi.height == 0 && info.roi.x_offset == 0 && info.roi.y_offset == 0) ||
                        (info.roi.x_offset == 0 && info.roi.y_offset == 0 && info.roi.width == info.width &&
                         info.roi.height == info.height);
  if (info.binning_x > 1 || info.binning_y > 1)
    return fail(error, "binning_x / binning_y = " + std::to_string(info.binning_x) + " / " + std::to_string(info.binning_y) +
                           " is not supported (publish full-resolution images or a camera_info for the binned size)");
  if (!roi_full)
    return fail(error, "roi " + std::to_string(info.roi.width) + "x" + std::to_string(info.roi.height) + "+" +
                           std::to_string(info.roi.x_offset) + "+" + std::to_string(info.roi.y_offset) +
                           " is not supported (only the full image)");

  const bool rectified = options.use_rectified || info.D.empty() || allZero(info.D);
  std::string model = "pinhole-radtan";
  std::vector<double> params;
  const char* source = "K";
  if (rectified) {
    const bool p_set = !allZero(info.P);
    if (p_set) {
      if (info.P[1] != 0.0 || info.P[4] != 0.0 || info.P[8] != 0.0 || info.P[9] != 0.0 || info.P[10] != 1.0)
        return fail(error, "P must be [fx' 0 cx' Tx; 0 fy' cy' Ty; 0 0 1 0] (no skew), got P[1] = " + num(info.P[1]) +
                               ", P[10] = " + num(info.P[10]));
      params = {info.P[0], info.P[5], info.P[2], info.P[6]};
      source = "P";
    } else if (options.use_rectified) {
      return fail(error, "P is all zeros: cannot use the rectified calibration (use_rectified is set)");
    }
  }
  if (params.empty()) {
    if (allZero(info.K)) return fail(error, "K is all zeros (uncalibrated camera): calibrate it or set ~camera_file");
    if (info.K[1] != 0.0 || info.K[3] != 0.0 || info.K[6] != 0.0 || info.K[7] != 0.0 || info.K[8] != 1.0)
      return fail(error, "K must be [fx 0 cx; 0 fy cy; 0 0 1] (no skew), got K[1] = " + num(info.K[1]) +
                             ", K[8] = " + num(info.K[8]));
    params = {info.K[0], info.K[4], info.K[2], info.K[5]};
  }

  const std::string& d = info.distortion_model;
  const size_t n = info.D.size();
  if (rectified) {
    params.insert(params.end(), 4, 0.0);  // no distortion: k1 k2 p1 p2 = 0
  } else if (d == dm::PLUMB_BOB) {
    if (n != 4 && n != 5)
      return fail(error, "D has " + std::to_string(n) + " values; plumb_bob needs 4 or 5 (k1 k2 p1 p2 [k3])");
    params.insert(params.end(), info.D.begin(), info.D.end());
  } else if (d == dm::RATIONAL_POLYNOMIAL) {
    if (n != 8) return fail(error, "D has " + std::to_string(n) + " values; rational_polynomial needs 8 (k1 k2 p1 p2 k3 k4 k5 k6)");
    if (info.D[5] != 0.0 || info.D[6] != 0.0 || info.D[7] != 0.0)
      return fail(error, "distortion_model rational_polynomial with k4..k6 = " + num(info.D[5]) + ", " + num(info.D[6]) + ", " +
                             num(info.D[7]) + " is not supported (camera models: plumb_bob, equidistant; recalibrate with "
                             "plumb_bob or publish rectified images and set use_rectified)");
    params.insert(params.end(), info.D.begin(), info.D.begin() + 5);
  } else if (d == dm::EQUIDISTANT || d == "fisheye") {
    if (n != 4) return fail(error, "D has " + std::to_string(n) + " values; equidistant needs 4 (k1 k2 k3 k4)");
    model = "kannala-brandt";
    params.insert(params.end(), info.D.begin(), info.D.end());
  } else {
    return fail(error, "distortion_model '" + d + "' is not supported (plumb_bob, rational_polynomial with k4..k6 = 0, "
                       "equidistant; or rectified images)");
  }
  std::string err;
  CameraModelPtr cam = makeCamera(model, static_cast<int>(info.width), static_cast<int>(info.height), params, &err);
  if (!cam) {
    const bool intrinsic = err.rfind("fx", 0) == 0 || err.rfind("fy", 0) == 0 || err.rfind("cx", 0) == 0 || err.rfind("cy", 0) == 0;
    return fail(error, std::string(intrinsic ? source : "D") + ": " + err);
  }
  return cam;
}

bool calibrationDiffers(const sensor_msgs::CameraInfo& a, const sensor_msgs::CameraInfo& b, std::string* what) {
  const char* field = nullptr;
  if (a.width != b.width || a.height != b.height) field = "width x height";
  else if (a.distortion_model != b.distortion_model) field = "distortion_model";
  else if (a.D != b.D) field = "D";
  else if (a.K != b.K) field = "K";
  else if (a.R != b.R) field = "R";
  else if (a.P != b.P) field = "P";
  else if (a.binning_x != b.binning_x || a.binning_y != b.binning_y) field = "binning";
  else if (a.roi.x_offset != b.roi.x_offset || a.roi.y_offset != b.roi.y_offset || a.roi.width != b.roi.width ||
           a.roi.height != b.roi.height)
    field = "roi";
  if (field && what) *what = field;
  return field != nullptr;
}

bool stereoExtrinsicsFromCameraInfo(const sensor_msgs::CameraInfo& left, const sensor_msgs::CameraInfo& right,
                                    bool use_rectified, Eigen::Isometry3d* T_r_l, std::string* error) {
  auto failed = [error](const std::string& msg) {
    if (error) *error = "stereo camera_info: " + msg;
    return false;
  };
  for (const sensor_msgs::CameraInfo* info : {&left, &right}) {
    const std::string which = info == &left ? "left" : "right";
    if (!nonFinite("P", info->P).empty() || !nonFinite("R", info->R).empty())
      return failed(which + " P or R is not finite");
    if (!(info->P[0] > 0.0) || !(info->P[5] > 0.0)) return failed(which + " P has no focal length (P[0], P[5])");
  }
  const double tx = right.P[3] / right.P[0] - left.P[3] / left.P[0];
  const double ty = right.P[7] / right.P[5] - left.P[7] / left.P[5];
  if (tx == 0.0 && ty == 0.0)
    return failed("the right P has no baseline (P[3] = Tx = -fx * baseline is 0): not a stereo calibration; give "
                  "~camera_file and ~right_camera_file with their T_BS instead");
  Eigen::Matrix3d R_l = Eigen::Matrix3d::Identity(), R_r = Eigen::Matrix3d::Identity();
  if (!use_rectified) {
    R_l = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(left.R.data());
    R_r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(right.R.data());
    if (allZero(left.R)) R_l.setIdentity();  // an unset R: the camera is its own rectified frame
    if (allZero(right.R)) R_r.setIdentity();
    for (const Eigen::Matrix3d* R : {&R_l, &R_r})
      if ((*R * R->transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R->determinant() < 0)
        return failed(std::string(R == &R_l ? "left" : "right") + " R is not a rotation");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_r.transpose() * R_l;
  T.translation() = R_r.transpose() * Eigen::Vector3d(tx, ty, 0.0);
  *T_r_l = T;
  return true;
}

}  // namespace iraf_vo
