// Pose-only refinement of T_c_w (geometry.h conventions) and its Gauss-Newton building blocks. ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace iraf_vo {

/// One observation's Gauss-Newton terms of 6-dof pose normal equations: the lower triangle (j <= i) of *H gets
/// w Jp^T Jp and *g gets w Jp^T r, every entry rounded exactly as by Eigen's `H.noalias() += w * Jp.transpose() * Jp`
/// (w Jp(k, i) first). The strict upper triangle is not touched (copyLowerToUpper after the last observation).
inline void addWeightedNormalEquations(const Eigen::Matrix<double, 2, 6>& Jp, const Eigen::Vector2d& r, double w,
                                       Eigen::Matrix<double, 6, 6>* H, Eigen::Matrix<double, 6, 1>* g) {
  for (int i = 0; i < 6; ++i) {
    const double wa = w * Jp(0, i), wb = w * Jp(1, i);
    for (int j = 0; j <= i; ++j) (*H)(i, j) += wa * Jp(0, j) + wb * Jp(1, j);
    (*g)(i) += wa * r(0) + wb * r(1);
  }
}

/// H(i, j) = H(j, i) for j > i.
inline void copyLowerToUpper(Eigen::Matrix<double, 6, 6>* H) {
  for (int j = 1; j < 6; ++j)
    for (int i = 0; i < j; ++i) (*H)(i, j) = (*H)(j, i);
}

struct PoseOptimizationOptions {
  int rounds = 3;                  // solve -> classify outliers (chi2) -> solve again
  int max_num_iterations = 10;     // per round
  double chi2_threshold = 5.991;   // 2 dof, 95 %
  double huber_delta = 2.447;      // sqrt(5.991), on the sigma-normalized residual
  /// false: Levenberg-Marquardt on the 6x6 normal equations (same residual / Jacobian, ~10x faster than
  /// building a ceres::Problem per frame); true: ceres::Solve with PoseOnlyCost + Huber.
  bool use_ceres = false;
};

/// A stereo frame's right-image observations of the same points: per observation its right pixel and sigma
/// (sigma <= 0: not seen in the right image), the right camera and T_r_l (left camera -> right camera).
struct RightObservations {
  const CameraModel* camera = nullptr;
  Eigen::Isometry3d T_r_l = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> sigma;
  /// The observations with a right pixel (0 without a camera).
  int count() const;
};

/// Pose-only refinement of T_c_w from 3D points and their observed pixels (sigma per observation).
/// `inlier` (in/out, same size) marks which observations are used; updated by the chi2 test of each round.
/// right (optional, same size): each right observation adds the residual of the point projected through T_r_l
/// into the right camera, used while it passes its own chi2 test (5.991 sigma^2) and its left one does; the
/// inliers are decided on the left image, as without it. Levenberg-Marquardt only (use_ceres is ignored then).
/// Returns the number of inliers after the last round; *right_inliers (optional): the right residuals in use.
int optimizePose(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, const PoseOptimizationOptions& options, Eigen::Isometry3d* T_c_w,
                 std::vector<char>* inlier, const RightObservations* right = nullptr, int* right_inliers = nullptr);

}  // namespace iraf_vo
