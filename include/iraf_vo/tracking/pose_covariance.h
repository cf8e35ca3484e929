// Pose uncertainty of the pose refinement (geometry.h conventions): information and world covariance. ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace iraf_vo {

/// Information matrix (J^T J of the sigma-normalized residuals) of T_c_w in its left-perturbation tangent
/// [dt, dtheta] (t' = t + dt, R' = Exp(dtheta) R) over the given observations.
Eigen::Matrix<double, 6, 6> poseInformation(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w,
                                            const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& sigma,
                                            const Eigen::Isometry3d& T_c_w);

/// Covariance of the camera pose T_w_c = T_c_w^-1 in the world frame, [x y z rx ry rz] (position, then a small
/// rotation about the world axes), from the information matrix of T_c_w (poseInformation).
Eigen::Matrix<double, 6, 6> worldPoseCovariance(const Eigen::Matrix<double, 6, 6>& information,
                                                const Eigen::Isometry3d& T_c_w);

}  // namespace iraf_vo
