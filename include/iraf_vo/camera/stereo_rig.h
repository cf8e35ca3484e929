// A calibrated camera pair (ROS-free): the left (reference) camera, the right camera and the rigid transform
// between them. Rectified or not: each camera keeps its own model (pinhole radial-tangential or Kannala-Brandt),
// the stereo matcher works on bearings with T_r_l, so no rectification is needed.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Geometry>
#include <string>

namespace iraf_vo {

struct StereoRig {
  CameraModelPtr left, right;
  /// Left camera -> right camera: p_r = T_r_l * p_l (from the two T_BS: T_r_l = T_BS_r^-1 * T_BS_l).
  Eigen::Isometry3d T_r_l = Eigen::Isometry3d::Identity();
  /// |t of T_r_l| in metres.
  double baseline() const;
};

/// "" for a usable rig, else what is wrong (a camera missing, T_r_l not finite or not a rotation, baseline 0).
std::string validate(const StereoRig& rig);

/// Builds T_r_l from the cameras' T_BS and checks the pair (both cameras set, baseline > 0, finite transform).
/// false + *error naming what is wrong.
bool makeStereoRig(CameraModelPtr left, CameraModelPtr right, StereoRig* rig, std::string* error);

/// Two camera yaml files (any layout loadCamera reads; each with its T_BS). false + *error naming the file.
bool loadStereoRig(const std::string& left_yaml, const std::string& right_yaml, StereoRig* rig, std::string* error);

}  // namespace iraf_vo
