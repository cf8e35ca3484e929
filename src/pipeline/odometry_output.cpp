#include "iraf_vo/pipeline/odometry_output.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace iraf_vo {

namespace {

Matrix6d blockRotate(const Eigen::Matrix3d& R, const Matrix6d& c) {
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = R;
  J.bottomRightCorner<3, 3>() = R;
  return J * c * J.transpose();
}

}  // namespace

Matrix6d positiveDefinite(const Matrix6d& c, double min_variance) {
  if (!c.allFinite()) return Matrix6d::Identity() * (min_variance * 1e12);
  const Matrix6d s = 0.5 * (c + c.transpose());
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(s);
  const Vector6d ev = es.eigenvalues().cwiseMax(min_variance);
  return es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
}

Matrix6d baseCovariance(const Matrix6d& cov_world_camera, const Eigen::Isometry3d& T_world_camera,
                        const Eigen::Isometry3d& T_base_camera) {
  const Eigen::Matrix3d RB = T_base_camera.rotation();
  const Eigen::Vector3d t_cb = T_base_camera.inverse().translation();  // base origin in the camera frame
  Matrix6d J = Matrix6d::Zero();
  J.topLeftCorner<3, 3>() = RB;
  const Eigen::Vector3d lever = T_world_camera.rotation() * t_cb;
  for (int i = 0; i < 3; ++i) J.block<3, 1>(0, 3 + i) = -RB * lever.cross(Eigen::Vector3d::Unit(i));  // -R_B [lever]x
  J.bottomRightCorner<3, 3>() = RB;
  return positiveDefinite(J * cov_world_camera * J.transpose());
}

OdometryOutput::OdometryOutput(const Eigen::Isometry3d& T_base_camera, double max_dt)
    : B_(T_base_camera), max_dt_(max_dt) {}

void OdometryOutput::setBaseFromCamera(const Eigen::Isometry3d& T_base_camera) {
  B_ = T_base_camera;
  reset();
}

std::vector<Eigen::Vector3d> OdometryOutput::toOdom(const std::vector<Eigen::Vector3d>& points_world) const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points_world.size());
  for (const Eigen::Vector3d& p : points_world) out.push_back(B_ * p);
  return out;
}

std::vector<Eigen::Isometry3d> OdometryOutput::toOdom(const std::vector<Eigen::Isometry3d>& poses_world) const {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(poses_world.size());
  for (const Eigen::Isometry3d& T : poses_world) out.push_back(B_ * T);
  return out;
}

OdometrySample OdometryOutput::update(double stamp, const Eigen::Isometry3d& T_world_camera,
                                      const Matrix6d& cov_world_camera) {
  OdometrySample s;
  s.T_odom_base = B_ * T_world_camera * B_.inverse();
  s.pose_covariance = baseCovariance(cov_world_camera, T_world_camera, B_);
  const double dt = stamp - prev_stamp_;
  if (have_prev_ && dt > 0.0 && dt <= max_dt_) {
    const Eigen::Isometry3d d = prev_.T_odom_base.inverse() * s.T_odom_base;  // motion in the previous base frame
    const Eigen::AngleAxisd aa(d.rotation());
    // Express in the current base frame (REP-105: twist in child_frame_id).
    const Eigen::Matrix3d R_cur_prev = d.rotation().transpose();
    s.twist.head<3>() = R_cur_prev * d.translation() / dt;
    s.twist.tail<3>() = aa.axis() * aa.angle() / dt;  // the axis is the same in both frames
    const Eigen::Matrix3d R_base_odom = s.T_odom_base.rotation().transpose();
    s.twist_covariance =
        positiveDefinite(blockRotate(R_base_odom, s.pose_covariance + prev_.pose_covariance) / (dt * dt));
    s.has_twist = true;
  }
  prev_ = s;
  prev_stamp_ = stamp;
  have_prev_ = true;
  return s;
}

}  // namespace iraf_vo
