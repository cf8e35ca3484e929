#include "iraf_vo/camera/kannala_brandt.h"

#include <cmath>

namespace iraf_vo {

KannalaBrandt::KannalaBrandt(int width, int height, double fx, double fy, double cx, double cy, double k1,
                             double k2, double k3, double k4)
    : fx_(fx), fy_(fy), cx_(cx), cy_(cy), k1_(k1), k2_(k2), k3_(k3), k4_(k4) {
  width_ = width;
  height_ = height;
  // Valid domain: theta_d(theta) increasing, capped at pi (the ray straight backwards).
  theta_max_ = M_PI;
  const double dt = 1e-4;
  for (double t = dt; t <= M_PI; t += dt) {
    double d = 0.0;
    thetaD(t, &d);
    if (d <= 0.0) {
      theta_max_ = t - dt;
      break;
    }
  }
}

double KannalaBrandt::thetaD(double theta, double* dtheta_d) const {
  // theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
  const double t2 = theta * theta;
  const double poly = 1.0 + t2 * (k1_ + t2 * (k2_ + t2 * (k3_ + t2 * k4_)));
  if (dtheta_d) *dtheta_d = 1.0 + t2 * (3.0 * k1_ + t2 * (5.0 * k2_ + t2 * (7.0 * k3_ + t2 * 9.0 * k4_)));
  return theta * poly;
}

bool KannalaBrandt::project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J) const {
  if (!p_c.allFinite()) return false;
  const double X = p_c.x(), Y = p_c.y(), Z = p_c.z();
  const double r2 = X * X + Y * Y;
  const double r = std::sqrt(r2);
  const double n = std::sqrt(r2 + Z * Z);
  if (!(n > 1e-12)) return false;
  if (r < 1e-9 * n) {
    // On the optical axis: limit theta_d / r -> 1 / Z (only in front of the camera).
    if (Z <= 0.0) return false;
    *uv = Eigen::Vector2d(fx_ * X / Z + cx_, fy_ * Y / Z + cy_);
    if (J) *J << fx_ / Z, 0.0, -fx_ * X / (Z * Z), 0.0, fy_ / Z, -fy_ * Y / (Z * Z);
    return true;
  }
  const double theta = std::atan2(r, Z);
  if (theta > theta_max_) return false;
  double dtd = 0.0;  // dtheta_d/dtheta, for the Jacobian only
  const double td = thetaD(theta, J ? &dtd : nullptr);
  const double s = td / r;
  *uv = Eigen::Vector2d(fx_ * s * X + cx_, fy_ * s * Y + cy_);
  if (J) {
    // s = theta_d / r;  ds/dp = dtheta_d/dtheta * dtheta/dp / r - theta_d / r^2 * dr/dp
    // dtheta/dp = (Z X / (r n^2), Z Y / (r n^2), -r / n^2),  dr/dp = (X/r, Y/r, 0).
    const double n2 = n * n;
    const Eigen::RowVector3d dtheta(Z * X / (r * n2), Z * Y / (r * n2), -r / n2);
    const Eigen::RowVector3d dr(X / r, Y / r, 0.0);
    const Eigen::RowVector3d dsdp = (dtd / r) * dtheta - (td / r2) * dr;
    J->row(0) = fx_ * (X * dsdp + Eigen::RowVector3d(s, 0.0, 0.0));
    J->row(1) = fy_ * (Y * dsdp + Eigen::RowVector3d(0.0, s, 0.0));
  }
  return true;
}

bool KannalaBrandt::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const {
  if (!uv.allFinite()) return false;
  const double mx = (uv.x() - cx_) / fx_, my = (uv.y() - cy_) / fy_;
  const double td = std::sqrt(mx * mx + my * my);
  if (td < 1e-15) {
    *bearing = Eigen::Vector3d(mx, my, 1.0).normalized();
    return true;
  }
  const double td_max = thetaD(theta_max_);
  if (td > td_max) return false;
  // Newton on theta: f(theta) = theta_d(theta) - |m| = 0, starting at theta = |m|.
  double theta = std::min(td, theta_max_);
  for (int it = 0; it < 50; ++it) {
    double d = 0.0;
    const double f = thetaD(theta, &d) - td;
    if (std::abs(f) < 1e-16) break;
    if (!(d > 1e-12)) return false;
    double next = theta - f / d;
    if (next < 0.0) next = 0.5 * theta;
    if (next > theta_max_) next = 0.5 * (theta + theta_max_);
    const bool done = std::abs(next - theta) < 1e-16;
    theta = next;
    if (done) break;
  }
  if (!(std::abs(thetaD(theta) - td) * std::max(fx_, fy_) < 1e-8)) return false;
  const double st = std::sin(theta);
  *bearing = Eigen::Vector3d(st * mx / td, st * my / td, std::cos(theta));
  return true;
}

std::vector<double> KannalaBrandt::parameters() const { return {fx_, fy_, cx_, cy_, k1_, k2_, k3_, k4_}; }

}  // namespace iraf_vo
