// Pinhole camera with radial-tangential (OpenCV "plumb_bob" / Kalibr "radtan") distortion, e.g. EuRoC cam0.
#pragma once

#include "iraf_vo/camera/camera_model.h"

namespace iraf_vo {

/// x = X/Z, y = Y/Z, r^2 = x^2 + y^2,
/// x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
/// y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
/// u = fx x_d + cx,  v = fy y_d + cy.
/// Points with Z <= 0 or beyond the radius where the radial polynomial stops being monotonic are rejected.
class PinholeRadtan : public CameraModel {
 public:
  /// Use makeCamera() (camera_loader.h) for validated construction from untrusted values.
  PinholeRadtan(int width, int height, double fx, double fy, double cx, double cy, double k1 = 0.0,
                double k2 = 0.0, double p1 = 0.0, double p2 = 0.0, double k3 = 0.0);

  std::string modelName() const override { return "pinhole-radtan"; }
  CameraKind kind() const override { return CameraKind::kPinhole; }
  std::string distortionModel() const override { return "radial-tangential"; }
  bool project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
               Eigen::Matrix<double, 2, 3>* J = nullptr) const override;
  /// Gauss-Newton on the normalized coordinates (x, y) starting from the distorted ones.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const override;
  /// fx fy cx cy k1 k2 p1 p2 (8 values), plus k3 as a 9th value only when k3 != 0.
  std::vector<double> parameters() const override;
  double focal() const override { return 0.5 * (fx_ + fy_); }

  /// Distortion in normalized coordinates; J (optional) = d(x_d, y_d)/d(x, y).
  Eigen::Vector2d distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J = nullptr) const;
  /// Inverse of distort() (Gauss-Newton); false when it does not converge.
  bool undistortNormalized(const Eigen::Vector2d& xy_d, Eigen::Vector2d* xy) const;

  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  double k1() const { return k1_; }
  double k2() const { return k2_; }
  double p1() const { return p1_; }
  double p2() const { return p2_; }
  double k3() const { return k3_; }
  /// Largest r^2 = x^2 + y^2 accepted by project() (radial polynomial monotonic below it).
  double maxRadiusSquared() const { return r2_max_; }

 private:
  double fx_, fy_, cx_, cy_, k1_, k2_, p1_, p2_, k3_;
  double r2_max_;
};

}  // namespace iraf_vo
