// Pose uncertainty from the pose refinement (pose_covariance.h). ROS-free.
#include "iraf_vo/tracking/pose_covariance.h"

#include "iraf_vo/tracking/geometry.h"

#include <algorithm>
#include <cmath>

namespace iraf_vo {

Eigen::Matrix<double, 6, 6> poseInformation(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w,
                                            const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& sigma,
                                            const Eigen::Isometry3d& T_c_w) {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  const Eigen::Matrix3d R = T_c_w.rotation();
  for (size_t i = 0; i < p_w.size(); ++i) {
    const Eigen::Vector3d Rp = R * p_w[i];
    const Eigen::Vector3d pc = Rp + T_c_w.translation();
    Eigen::Vector2d pr;
    Eigen::Matrix<double, 2, 3> J;
    if (pc.z() <= 1e-6 || !cam.project(pc, &pr, &J)) continue;
    Eigen::Matrix<double, 2, 6> Jp;
    Jp.leftCols<3>() = J / sigma[i];
    Jp.rightCols<3>() = -Jp.leftCols<3>() * skew(Rp);
    H.noalias() += Jp.transpose() * Jp;
  }
  return H;
}

Eigen::Matrix<double, 6, 6> worldPoseCovariance(const Eigen::Matrix<double, 6, 6>& information,
                                                const Eigen::Isometry3d& T_c_w) {
  // c = -R^T t. With t' = t + dt, R' = Exp(dtheta) R: dc = -R^T (dt + [t]x dtheta); the world-frame rotation
  // perturbation of R_wc = R^T is -R^T dtheta.
  const Eigen::Matrix3d Rt = T_c_w.rotation().transpose();
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topLeftCorner<3, 3>() = -Rt;
  A.topRightCorner<3, 3>() = -Rt * skew(T_c_w.translation());
  A.bottomRightCorner<3, 3>() = -Rt;
  // Regularized inverse: a pose seen by too few / degenerate points gets a large but finite covariance.
  Eigen::Matrix<double, 6, 6> Hr = information;
  Hr.diagonal().array() += 1e-9 * std::max(1.0, information.diagonal().maxCoeff());
  const Eigen::Matrix<double, 6, 6> C = Hr.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
  Eigen::Matrix<double, 6, 6> out = A * C * A.transpose();
  return 0.5 * (out + out.transpose());
}

Eigen::Matrix<double, 6, 1> worldPoseDeviation(const Eigen::Isometry3d& T_c_w, const Eigen::Isometry3d& T_c_w_predicted) {
  const Eigen::Isometry3d T_w_c = T_c_w.inverse(), T_w_p = T_c_w_predicted.inverse();
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = T_w_c.translation() - T_w_p.translation();
  const Eigen::AngleAxisd aa(T_w_c.rotation() * T_w_p.rotation().transpose());
  d.tail<3>() = aa.angle() * aa.axis();
  return d;
}

Eigen::Matrix<double, 6, 6> calibratedPoseCovariance(const Eigen::Matrix<double, 6, 6>& refinement_covariance,
                                                     double median_chi2,
                                                     const Eigen::Matrix<double, 6, 1>& deviation,
                                                     const PoseCovarianceCalibration& calibration) {
  constexpr double kMedianChi2TwoDof = 1.386;  // 2 ln 2
  if (!std::isfinite(median_chi2) || !deviation.allFinite()) return refinement_covariance;
  const double variance_factor = std::max(calibration.variance_factor_floor, median_chi2 / kMedianChi2TwoDof);
  return variance_factor * refinement_covariance + calibration.prediction_weight * deviation * deviation.transpose();
}

void PoseCovarianceCalibrator::start(const Eigen::Isometry3d& T_c_w, long frame_index) {
  last_ = {frame_index, T_c_w};
  have_last_ = true;
  have_before_last_ = false;
}

Eigen::Matrix<double, 6, 6> PoseCovarianceCalibrator::calibrate(const Eigen::Matrix<double, 6, 6>& refinement_covariance,
                                                                double median_chi2, const Eigen::Isometry3d& T_c_w,
                                                                long frame_index) {
  Eigen::Matrix<double, 6, 1> deviation = Eigen::Matrix<double, 6, 1>::Zero();
  const bool have_last = have_last_ && last_.frame == frame_index - 1;
  if (have_last && have_before_last_ && before_last_.frame == frame_index - 2) {
    const Eigen::Isometry3d velocity = last_.T_c_w * before_last_.T_c_w.inverse();
    deviation = worldPoseDeviation(T_c_w, velocity * last_.T_c_w);
  } else if (have_last) {
    deviation = worldPoseDeviation(T_c_w, last_.T_c_w);
  }
  before_last_ = last_;
  have_before_last_ = have_last_;
  last_ = {frame_index, T_c_w};
  have_last_ = true;
  return calibratedPoseCovariance(refinement_covariance, median_chi2, deviation, calibration_);
}

}  // namespace iraf_vo
