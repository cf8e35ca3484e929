// Pose uncertainty of the pose refinement (geometry.h conventions): information, world covariance and its
// calibration. ROS-free.
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

/// How far the tracked pose is from a predicted one, in worldPoseCovariance's coordinates:
/// [camera centre - predicted centre, log(R_w_c R_w_pred^T)].
Eigen::Matrix<double, 6, 1> worldPoseDeviation(const Eigen::Isometry3d& T_c_w, const Eigen::Isometry3d& T_c_w_predicted);

/// Calibration of the refinement's covariance against the frame-to-frame error (iraf_vo_pose_nees; the table in
/// docs/evaluation.md). The refinement's covariance assumes sigma = scale_factor^octave px per inlier and fixed
/// map points; the calibrated one is
///     C = s^2 C_refinement + prediction_weight * d d^T
/// s^2: the a-posteriori variance factor of this frame, median chi2 of the inliers / 1.386 (the median of
///      chi2(2)), at least variance_factor_floor: the pixel noise the frame shows;
/// d:   the pose's deviation (worldPoseDeviation) from the constant-velocity extrapolation of the two poses
///      tracked before it, as they were output: a pose that jumps off the smooth motion (errors of the map
///      points it was measured against, a map the bundle adjustment has just moved), which the fixed-map
///      covariance cannot see, gets an uncertainty along that jump.
struct PoseCovarianceCalibration {
  double variance_factor_floor = 0.2;
  double prediction_weight = 0.12;
};

/// The calibrated world covariance (see PoseCovarianceCalibration) from the refinement's (worldPoseCovariance),
/// the inliers' median chi2 and the deviation from the prediction (worldPoseDeviation).
Eigen::Matrix<double, 6, 6> calibratedPoseCovariance(const Eigen::Matrix<double, 6, 6>& refinement_covariance,
                                                     double median_chi2,
                                                     const Eigen::Matrix<double, 6, 1>& deviation,
                                                     const PoseCovarianceCalibration& calibration = {});

/// Applies calibratedPoseCovariance along one track: remembers the poses it output to predict the next.
class PoseCovarianceCalibrator {
 public:
  explicit PoseCovarianceCalibrator(const PoseCovarianceCalibration& calibration = {}) : calibration_(calibration) {}
  /// A new track (a new map) starting with the pose of frame `frame_index`.
  void start(const Eigen::Isometry3d& T_c_w, long frame_index);
  /// The calibrated covariance of the pose T_c_w tracked in frame `frame_index`. The prediction extrapolates the
  /// poses of frames frame_index - 2 and - 1; with only frame_index - 1 tracked it is that pose (no velocity);
  /// with neither (after a loss or dark frames) d = 0.
  Eigen::Matrix<double, 6, 6> calibrate(const Eigen::Matrix<double, 6, 6>& refinement_covariance, double median_chi2,
                                        const Eigen::Isometry3d& T_c_w, long frame_index);

 private:
  struct TrackedPose {
    long frame = -1;
    Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  };
  PoseCovarianceCalibration calibration_;
  TrackedPose last_, before_last_;
  bool have_last_ = false, have_before_last_ = false;
};

}  // namespace iraf_vo
