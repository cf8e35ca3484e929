// Consistency of a pose covariance with the frame-to-frame error (iraf_vo_pose_nees): for consecutive tracked
// poses of one map, the error of the relative motion (camera centre step and world-frame rotation step, after the
// Sim(3) alignment of the whole run to the ground truth) against C_k + C_k-1:  NEES = e^T (C_k + C_k-1)^-1 e.
// A consistent covariance gives a mean NEES equal to the degrees of freedom (6; 3 for position, 3 for rotation).
// Covariances in TrackResult::covariance's convention: [x y z rx ry rz] of T_w_c in the world frame.
#pragma once

#include "iraf_vo/eval/trajectory_eval.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace iraf_vo {

struct CovariancePose {
  double stamp = 0.0;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Identity();
  long map = 0;  // poses of different maps are not compared
};

struct FrameToFrameError {
  size_t index = 0;  // of the later pose in the input
  Eigen::Matrix<double, 6, 1> error = Eigen::Matrix<double, 6, 1>::Zero();  // [centre step, rotation step]
  double nees = 0.0, nees_position = 0.0, nees_rotation = 0.0;
};

/// The frame-to-frame errors of `poses` (sorted by stamp) against `gt`; false with *err when the alignment
/// fails. *alignment (optional) receives the run's evaluation (ATE, scale).
bool frameToFrameNees(const Trajectory& gt, const std::vector<CovariancePose>& poses, std::vector<FrameToFrameError>* out,
                      std::string* err, EvalResult* alignment = nullptr);

/// Mean of the 6-dof NEES (0 for none).
double meanNees(const std::vector<FrameToFrameError>& errors);

}  // namespace iraf_vo
