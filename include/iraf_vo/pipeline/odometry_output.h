// Odometry of the robot base from the camera poses (ROS-free; used by TrackerNodelet). REP-105 frames:
//
//   world  = the optical frame of the camera at the start of the map (the core's world frame, z forward, y down)
//   odom   = the BASE frame at that same instant: T_odom_world = T_base_camera (B), so a z-up base gives a z-up odom
//   T_odom_base(t) = B * T_world_camera(t) * B^-1
// With B = identity (no ~base_frame) odom = world and base = camera: today's camera-optical odometry.
//
// Pose covariance: the core's T_w_c covariance is [x y z rx ry rz] = (camera centre in the world, world-frame rotation
// perturbation R' = Exp(dtheta) R), see TrackResult::covariance (sigma = scale_factor^octave px per keypoint, map
// units). It is mapped to (base position in odom, odom-frame rotation) with the Jacobian
//   J = [ R_B  -R_B [R_wc t_cb]x ]      (t_cb: base origin in the camera frame; lever arm)
//       [ 0     R_B              ]
// and made symmetric positive definite (eigenvalues clamped to >= min_variance).
// Twist (REP-105: in the child = base frame): finite difference of consecutive published poses (the core's constant
// velocity motion model), linear in map units / s, angular in rad / s; its covariance: (C_k + C_k-1) / dt^2 in the
// base frame. Unknown (first pose after a (re)start, dt <= 0 or dt > max_dt): has_twist = false.
// Scale caveat: B's translation is metric while monocular map units are arbitrary: the lever arm is only exact when
// the map scale happens to be metric; for a camera near the base origin the effect is small.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace iraf_vo {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

struct OdometrySample {
  Eigen::Isometry3d T_odom_base = Eigen::Isometry3d::Identity();
  Matrix6d pose_covariance = Matrix6d::Identity();  // [x y z rx ry rz] in odom
  bool has_twist = false;
  Vector6d twist = Vector6d::Zero();  // [vx vy vz wx wy wz] in the base frame
  Matrix6d twist_covariance = Matrix6d::Identity();
};

/// Symmetrized copy of c with eigenvalues clamped to >= min_variance (NaN / inf entries: min_variance * 1e12 * I).
Matrix6d positiveDefinite(const Matrix6d& c, double min_variance = 1e-12);

/// Covariance of the base pose in odom from the camera pose covariance in the world (see the header comment).
Matrix6d baseCovariance(const Matrix6d& cov_world_camera, const Eigen::Isometry3d& T_world_camera,
                        const Eigen::Isometry3d& T_base_camera);

class OdometryOutput {
 public:
  explicit OdometryOutput(const Eigen::Isometry3d& T_base_camera = Eigen::Isometry3d::Identity(), double max_dt = 1.0);
  void setBaseFromCamera(const Eigen::Isometry3d& T_base_camera);
  const Eigen::Isometry3d& baseFromCamera() const { return B_; }
  /// One tracked frame: the camera pose (anchored world frame) and its covariance.
  OdometrySample update(double stamp, const Eigen::Isometry3d& T_world_camera, const Matrix6d& cov_world_camera);
  /// Map points / keyframe (camera) poses of the world frame in odom (odom = B * world).
  std::vector<Eigen::Vector3d> toOdom(const std::vector<Eigen::Vector3d>& points_world) const;
  std::vector<Eigen::Isometry3d> toOdom(const std::vector<Eigen::Isometry3d>& poses_world) const;
  /// Forget the previous pose (new map after a time jump / restart): no twist until the next pose.
  void reset() { have_prev_ = false; }

 private:
  Eigen::Isometry3d B_;
  double max_dt_;
  bool have_prev_ = false;
  double prev_stamp_ = 0.0;
  OdometrySample prev_;
};

}  // namespace iraf_vo
