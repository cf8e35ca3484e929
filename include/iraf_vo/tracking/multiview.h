// Multi-view basics on bearings (geometry.h conventions): triangulation, parallax, reprojection error, PnP.
// ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace iraf_vo {

/// Linear (DLT on bearings, [b]x P X = 0) triangulation of a point seen as bearing b1 from T1_c_w and
/// b2 from T2_c_w. Returns false when the system is degenerate (point at infinity).
bool triangulateBearings(const Eigen::Isometry3d& T1_c_w, const Eigen::Vector3d& b1,
                         const Eigen::Isometry3d& T2_c_w, const Eigen::Vector3d& b2, Eigen::Vector3d* p_w);

/// Parallax angle (radians) at p_w between the two camera centres.
double parallaxAngle(const Eigen::Isometry3d& T1_c_w, const Eigen::Isometry3d& T2_c_w, const Eigen::Vector3d& p_w);

/// Squared pixel reprojection error of p_w in a camera; < 0 when the point does not project.
double reprojectionError2(const CameraModel& cam, const Eigen::Isometry3d& T_c_w, const Eigen::Vector3d& p_w,
                          const Eigen::Vector2d& uv);

/// cv::solvePnPRansac (AP3P minimal solver) on normalized coordinates of the bearings, threshold in pixels.
/// Returns the number of inliers (0 on failure); *T_c_w is written only on success.
int solvePnPBearings(const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector3d>& bearings,
                     double focal, double threshold_px, int iterations, Eigen::Isometry3d* T_c_w,
                     std::vector<char>* inliers = nullptr);

}  // namespace iraf_vo
