#include "iraf_vo/camera/pinhole_radtan.h"

#include <Eigen/LU>
#include <cmath>
#include <limits>

namespace iraf_vo {

PinholeRadtan::PinholeRadtan(int width, int height, double fx, double fy, double cx, double cy, double k1,
                             double k2, double p1, double p2, double k3)
    : fx_(fx), fy_(fy), cx_(cx), cy_(cy), k1_(k1), k2_(k2), p1_(p1), p2_(p2), k3_(k3) {
  width_ = width;
  height_ = height;
  // Valid domain: the radial map r -> r (1 + k1 r^2 + k2 r^4 + k3 r^6) must be increasing, i.e.
  // d/dr = 1 + 3 k1 s + 5 k2 s^2 + 7 k3 s^3 > 0 with s = r^2. Take the first sign change for s in (0, 100].
  r2_max_ = std::numeric_limits<double>::infinity();
  const double ds = 1e-3;
  for (double s = ds; s <= 100.0; s += ds) {
    if (1.0 + s * (3.0 * k1_ + s * (5.0 * k2_ + s * 7.0 * k3_)) <= 0.0) {
      r2_max_ = s - ds;
      break;
    }
  }
}

Eigen::Vector2d PinholeRadtan::distort(const Eigen::Vector2d& xy, Eigen::Matrix2d* J) const {
  const double x = xy.x(), y = xy.y();
  const double x2 = x * x, y2 = y * y, xy_ = x * y, r2 = x2 + y2;
  const double radial = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
  const Eigen::Vector2d d(x * radial + 2.0 * p1_ * xy_ + p2_ * (r2 + 2.0 * x2),
                          y * radial + p1_ * (r2 + 2.0 * y2) + 2.0 * p2_ * xy_);
  if (J) {
    // d(radial)/d(r2) = k1 + 2 k2 r2 + 3 k3 r2^2;  d(r2)/dx = 2x, d(r2)/dy = 2y.
    const double dr = k1_ + r2 * (2.0 * k2_ + 3.0 * k3_ * r2);
    (*J)(0, 0) = radial + 2.0 * x2 * dr + 2.0 * p1_ * y + 6.0 * p2_ * x;
    (*J)(0, 1) = 2.0 * xy_ * dr + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J)(1, 0) = 2.0 * xy_ * dr + 2.0 * p1_ * x + 2.0 * p2_ * y;
    (*J)(1, 1) = radial + 2.0 * y2 * dr + 6.0 * p1_ * y + 2.0 * p2_ * x;
  }
  return d;
}

bool PinholeRadtan::project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J) const {
  const double z = p_c.z();
  if (!(z > 1e-12) || !p_c.allFinite()) return false;
  const double inv_z = 1.0 / z;
  const double x = p_c.x() * inv_z, y = p_c.y() * inv_z;
  // distort() inlined (same expressions, same rounding): the Jacobian terms are formed only when asked for.
  const double x2 = x * x, y2 = y * y, xy = x * y, r2 = x2 + y2;
  if (r2 > r2_max_) return false;
  const double radial = 1.0 + r2 * (k1_ + r2 * (k2_ + r2 * k3_));
  const double xd = x * radial + 2.0 * p1_ * xy + p2_ * (r2 + 2.0 * x2);
  const double yd = y * radial + p1_ * (r2 + 2.0 * y2) + 2.0 * p2_ * xy;
  *uv = Eigen::Vector2d(fx_ * xd + cx_, fy_ * yd + cy_);
  if (J) {
    // d(uv)/d(p) = diag(fx, fy) * Jd * [1/z 0 -x/z; 0 1/z -y/z] with Jd = d(xd, yd)/d(x, y) as in distort(),
    // multiplied out without the zero entries (each product and sum as in the dense 2x2 * 2x2 * 2x3 chain).
    const double dr = k1_ + r2 * (2.0 * k2_ + 3.0 * k3_ * r2);
    const double cross = 2.0 * xy * dr + 2.0 * p1_ * x + 2.0 * p2_ * y;
    const double a = fx_ * (radial + 2.0 * x2 * dr + 2.0 * p1_ * y + 6.0 * p2_ * x);
    const double b = fx_ * cross;
    const double c = fy_ * cross;
    const double d = fy_ * (radial + 2.0 * y2 * dr + 6.0 * p1_ * y + 2.0 * p2_ * x);
    const double dx_dz = -x * inv_z, dy_dz = -y * inv_z;
    *J << a * inv_z, b * inv_z, a * dx_dz + b * dy_dz,  //
        c * inv_z, d * inv_z, c * dx_dz + d * dy_dz;
  }
  return true;
}

bool PinholeRadtan::undistortNormalized(const Eigen::Vector2d& xy_d, Eigen::Vector2d* xy_out) const {
  if (!xy_d.allFinite()) return false;
  // Gauss-Newton on min |distort(xy) - xy_d|^2 starting at xy = xy_d (square system, so a Newton step).
  Eigen::Vector2d xy = xy_d;
  Eigen::Matrix2d J;
  Eigen::Vector2d f = distort(xy, &J) - xy_d;
  for (int it = 0; it < 50 && f.squaredNorm() > 1e-30; ++it) {
    const double det = J.determinant();
    if (!(std::abs(det) > 1e-15)) return false;
    Eigen::Vector2d step = -J.inverse() * f;
    // Step halving keeps the iteration inside the basin when the first guess is far off (image corners).
    double alpha = 1.0;
    Eigen::Vector2d xy_new, f_new;
    Eigen::Matrix2d J_new;
    for (int ls = 0; ls < 20; ++ls) {
      xy_new = xy + alpha * step;
      f_new = distort(xy_new, &J_new) - xy_d;
      if (f_new.squaredNorm() < f.squaredNorm()) break;
      alpha *= 0.5;
    }
    if (!(f_new.squaredNorm() <= f.squaredNorm())) break;
    xy = xy_new;
    f = f_new;
    J = J_new;
    if ((alpha * step).squaredNorm() < 1e-32) break;
  }
  // Converged to better than 1e-10 px (normalized residual times focal length).
  if (!(f.norm() * std::max(fx_, fy_) < 1e-8)) return false;
  if (xy.squaredNorm() > r2_max_) return false;
  *xy_out = xy;
  return true;
}

bool PinholeRadtan::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const {
  const Eigen::Vector2d xy_d((uv.x() - cx_) / fx_, (uv.y() - cy_) / fy_);
  Eigen::Vector2d xy;
  if (!undistortNormalized(xy_d, &xy)) return false;
  *bearing = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

std::vector<double> PinholeRadtan::parameters() const {
  std::vector<double> p{fx_, fy_, cx_, cy_, k1_, k2_, p1_, p2_};
  if (k3_ != 0.0) p.push_back(k3_);
  return p;
}

}  // namespace iraf_vo
