#include "iraf_vo/camera/stereo_rig.h"

#include "iraf_vo/camera/camera_loader.h"

#include <cmath>

namespace iraf_vo {

double StereoRig::baseline() const { return T_r_l.translation().norm(); }

std::string validate(const StereoRig& rig) {
  if (!rig.left || !rig.right) return std::string("stereo rig: the ") + (rig.left ? "right" : "left") + " camera is missing";
  if (!rig.T_r_l.matrix().allFinite()) return "stereo rig: T_r_l is not finite";
  const Eigen::Matrix3d R = rig.T_r_l.linear();
  if (!((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-3))
    return "stereo rig: the rotation of T_r_l is not orthonormal";
  if (!(rig.baseline() > 1e-4))
    return "stereo rig: baseline 0 (both cameras at the same place): give each camera its own T_BS";
  return "";
}

bool makeStereoRig(CameraModelPtr left, CameraModelPtr right, StereoRig* rig, std::string* error) {
  auto fail = [error](const std::string& msg) {
    if (error) *error = msg;
    return false;
  };
  if (!left || !right) return fail(std::string("stereo rig: the ") + (left ? "right" : "left") + " camera is missing");
  if (!left->T_BS.allFinite() || !right->T_BS.allFinite()) return fail("stereo rig: T_BS is not finite");
  Eigen::Isometry3d T_b_l, T_b_r;
  T_b_l.matrix() = left->T_BS;
  T_b_r.matrix() = right->T_BS;
  StereoRig r;
  r.left = std::move(left);
  r.right = std::move(right);
  r.T_r_l = T_b_r.inverse() * T_b_l;
  const std::string problem = validate(r);
  if (!problem.empty()) return fail(problem);
  *rig = r;
  return true;
}

bool loadStereoRig(const std::string& left_yaml, const std::string& right_yaml, StereoRig* rig, std::string* error) {
  std::string err;
  CameraModelPtr left = loadCamera(left_yaml, &err);
  if (!left) {
    if (error) *error = "stereo rig: left camera: " + err;
    return false;
  }
  CameraModelPtr right = loadCamera(right_yaml, &err);
  if (!right) {
    if (error) *error = "stereo rig: right camera: " + err;
    return false;
  }
  if (!makeStereoRig(left, right, rig, &err)) {
    if (error) *error = err + " (" + left_yaml + ", " + right_yaml + ")";
    return false;
  }
  return true;
}

}  // namespace iraf_vo
