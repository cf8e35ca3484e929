// Kannala-Brandt equidistant fisheye model (Kalibr "equidistant", OpenCV cv::fisheye, ROS "equidistant"),
// e.g. TUM-VI cam0.
#pragma once

#include "iraf_vo/camera/camera_model.h"

namespace iraf_vo {

/// theta = atan2(sqrt(X^2 + Y^2), Z),
/// theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
/// u = fx theta_d X / r + cx,  v = fy theta_d Y / r + cy   (r = sqrt(X^2 + Y^2)).
/// Valid for theta below the first turning point of theta_d(theta) (capped at pi), so points slightly
/// behind the image plane (Z <= 0) still project when the lens sees them.
class KannalaBrandt : public CameraModel {
 public:
  /// Use makeCamera() (camera_loader.h) for validated construction from untrusted values.
  KannalaBrandt(int width, int height, double fx, double fy, double cx, double cy, double k1 = 0.0,
                double k2 = 0.0, double k3 = 0.0, double k4 = 0.0);

  std::string modelName() const override { return "kannala-brandt"; }
  CameraKind kind() const override { return CameraKind::kFisheye; }
  std::string distortionModel() const override { return "equidistant"; }
  bool project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
               Eigen::Matrix<double, 2, 3>* J = nullptr) const override;
  /// Newton on theta for theta_d(theta) = |m|, then bearing = (sin(theta) m/|m|, cos(theta)).
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const override;
  /// fx fy cx cy k1 k2 k3 k4.
  std::vector<double> parameters() const override;
  double focal() const override { return 0.5 * (fx_ + fy_); }

  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  double k1() const { return k1_; }
  double k2() const { return k2_; }
  double k3() const { return k3_; }
  double k4() const { return k4_; }
  /// Largest incidence angle (rad) accepted by project() / returned by unproject().
  double maxTheta() const { return theta_max_; }

 private:
  /// theta_d(theta) and its derivative.
  double thetaD(double theta, double* dtheta_d = nullptr) const;

  double fx_, fy_, cx_, cy_, k1_, k2_, k3_, k4_;
  double theta_max_;
};

}  // namespace iraf_vo
