// Geometry conventions of the monocular tracker and the cross-product matrix. Everything works on unit bearing
// vectors (CameraModel::unproject) or on pixels through CameraModel::project (with its 2x3 Jacobian), so
// pinhole-radtan and Kannala-Brandt both work. ROS-free.
//
// Conventions: T_c_w maps world points into the camera (REP-103 optical frame, z forward);
// the published pose is T_w_c = T_c_w^-1. Pixel noise of a keypoint at pyramid level o is
// sigma = scale_factor^o (pixels); chi2 gates use 2 dof (5.991 at 95 %).
#pragma once

#include <Eigen/Core>

namespace iraf_vo {

/// Cross-product matrix: skew(v) x = v.cross(x).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace iraf_vo
