// Ceres building blocks shared by the pose-only refinement (pose_optimization.cpp) and the bundle adjustment
// (bundle_adjustment.cpp): the pose parameter block, its manifold and the reprojection costs. Internal to src/tracking.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/tracking/geometry.h"

#include <ceres/ceres.h>

namespace iraf_vo {
namespace ceres_blocks {

// Pose block layout: [tx ty tz qx qy qz qw] of T_c_w. Tangent: [dt, dtheta] with the left perturbation
// t' = t + dt, R' = Exp(dtheta) R. The cost functions fill the first 6 columns of their 2x7 pose Jacobian
// with the tangent Jacobian, so PlusJacobian = [I6; 0].
class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    Eigen::Map<const Eigen::Vector3d> t(x);
    Eigen::Map<const Eigen::Quaterniond> q(x + 3);
    Eigen::Map<const Eigen::Vector3d> dt(delta);
    Eigen::Map<const Eigen::Vector3d> dth(delta + 3);
    Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta);
    Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
    const double angle = dth.norm();
    Eigen::Quaterniond dq = angle > 1e-12 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, dth / angle))
                                          : Eigen::Quaterniond(1.0, 0.5 * dth.x(), 0.5 * dth.y(), 0.5 * dth.z());
    q_out = (dq * q).normalized();
    t_out = t + dt;
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Map<const Eigen::Vector3d> ty(y), tx(x);
    Eigen::Map<const Eigen::Quaterniond> qy(y + 3), qx(x + 3);
    Eigen::Map<Eigen::Vector3d> dt(y_minus_x), dth(y_minus_x + 3);
    dt = ty - tx;
    Eigen::AngleAxisd aa(qy * qx.conjugate());
    dth = aa.angle() * aa.axis();
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
};

inline void poseToBlock(const Eigen::Isometry3d& T, double* b) {
  (Eigen::Map<Eigen::Vector3d>(b)) = T.translation();
  Eigen::Quaterniond q(T.rotation());
  q.normalize();
  b[3] = q.x(); b[4] = q.y(); b[5] = q.z(); b[6] = q.w();
}

inline Eigen::Isometry3d blockToPose(const double* b) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(b[6], b[3], b[4], b[5]);
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(b[0], b[1], b[2]);
  return T;
}

// r = (pi(R p_w + t) - uv) / sigma
class ReprojectionCost final : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  ReprojectionCost(const CameraModel* cam, const Eigen::Vector2d& uv, double sigma)
      : cam_(cam), uv_(uv), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    Eigen::Map<const Eigen::Vector3d> t(params[0]);
    Eigen::Map<const Eigen::Quaterniond> q(params[0] + 3);
    Eigen::Map<const Eigen::Vector3d> p_w(params[1]);
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const Eigen::Vector3d Rp = R * p_w;
    const Eigen::Vector3d p_c = Rp + t;
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    // Cost-only evaluations (trial steps) pass no Jacobians: the projection's Jacobian is not formed then.
    if (p_c.z() <= 1e-6 || !cam_->project(p_c, &uv, jacobians ? &J : nullptr)) return false;
    (Eigen::Map<Eigen::Vector2d>(residuals)) = (uv - uv_) * inv_sigma_;
    if (jacobians) {
      J *= inv_sigma_;
      if (jacobians[0]) {
        Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> Jp(jacobians[0]);
        Jp.leftCols<3>() = J;
        Jp.block<2, 3>(0, 3) = -J * skew(Rp);
        Jp.col(6).setZero();
      }
      if (jacobians[1]) {
        Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jx(jacobians[1]);
        Jx = J * R;
      }
    }
    return true;
  }

 private:
  const CameraModel* cam_;
  Eigen::Vector2d uv_;
  double inv_sigma_;
};

class PoseOnlyCost final : public ceres::SizedCostFunction<2, 7> {
 public:
  PoseOnlyCost(const CameraModel* cam, const Eigen::Vector3d& p_w, const Eigen::Vector2d& uv, double sigma)
      : cam_(cam), p_w_(p_w), uv_(uv), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    Eigen::Map<const Eigen::Vector3d> t(params[0]);
    Eigen::Map<const Eigen::Quaterniond> q(params[0] + 3);
    const Eigen::Vector3d Rp = q.toRotationMatrix() * p_w_;
    const Eigen::Vector3d p_c = Rp + t;
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    const bool want_jacobian = jacobians && jacobians[0];
    if (p_c.z() <= 1e-6 || !cam_->project(p_c, &uv, want_jacobian ? &J : nullptr)) return false;
    (Eigen::Map<Eigen::Vector2d>(residuals)) = (uv - uv_) * inv_sigma_;
    if (want_jacobian) {
      J *= inv_sigma_;
      Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> Jp(jacobians[0]);
      Jp.leftCols<3>() = J;
      Jp.block<2, 3>(0, 3) = -J * skew(Rp);
      Jp.col(6).setZero();
    }
    return true;
  }

 private:
  const CameraModel* cam_;
  Eigen::Vector3d p_w_;
  Eigen::Vector2d uv_;
  double inv_sigma_;
};
}  // namespace ceres_blocks
}  // namespace iraf_vo
