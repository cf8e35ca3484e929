// Fast projection paths against the plain formulation they replace: PinholeRadtan::project with the distortion
// and its Jacobian inlined must give exactly (==, every bit but the sign of zero) what distort() followed by the
// dense chain diag(fx, fy) * Jd * d(xy)/d(p) gives. Projection without a Jacobian gives the same pixel.
#include <gtest/gtest.h>

#include <random>

#include "iraf_vo/camera/kannala_brandt.h"
#include "iraf_vo/camera/pinhole_radtan.h"

using namespace iraf_vo;

namespace {

// The plain projection: distort() and the Jacobian as a product of dense matrices.
bool plainProject(const PinholeRadtan& cam, const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
                  Eigen::Matrix<double, 2, 3>* J) {
  const double z = p_c.z();
  if (!(z > 1e-12) || !p_c.allFinite()) return false;
  const double inv_z = 1.0 / z;
  const Eigen::Vector2d xy(p_c.x() * inv_z, p_c.y() * inv_z);
  if (xy.squaredNorm() > cam.maxRadiusSquared()) return false;
  Eigen::Matrix2d Jd;
  const Eigen::Vector2d d = cam.distort(xy, &Jd);
  *uv = Eigen::Vector2d(cam.fx() * d.x() + cam.cx(), cam.fy() * d.y() + cam.cy());
  Eigen::Matrix<double, 2, 3> Jp;
  Jp << inv_z, 0.0, -xy.x() * inv_z, 0.0, inv_z, -xy.y() * inv_z;
  Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
  F(0, 0) = cam.fx();
  F(1, 1) = cam.fy();
  *J = F * Jd * Jp;
  return true;
}

// Random points in front of the camera spread over (and past) the valid domain.
std::vector<Eigen::Vector3d> randomPoints(std::mt19937* rng, int n) {
  std::uniform_real_distribution<double> lateral(-1.5, 1.5), depth(0.05, 20.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    const double z = depth(*rng);
    pts.emplace_back(lateral(*rng) * z, lateral(*rng) * z, z);
  }
  pts.emplace_back(0.0, 0.0, 1.0);   // optical axis
  pts.emplace_back(0.3, 0.0, 2.0);   // on an image axis
  pts.emplace_back(0.0, -0.4, 1.5);
  pts.emplace_back(0.1, 0.1, -1.0);  // behind
  return pts;
}

void expectSameAsPlain(const PinholeRadtan& cam, const std::vector<Eigen::Vector3d>& pts, int* n_projected) {
  for (const Eigen::Vector3d& p : pts) {
    Eigen::Vector2d uv_plain(-1, -1), uv_fast(-2, -2), uv_nojac(-3, -3);
    Eigen::Matrix<double, 2, 3> J_plain, J_fast;
    const bool ok_plain = plainProject(cam, p, &uv_plain, &J_plain);
    const bool ok_fast = cam.project(p, &uv_fast, &J_fast);
    const bool ok_nojac = cam.project(p, &uv_nojac);
    ASSERT_EQ(ok_plain, ok_fast) << p.transpose();
    ASSERT_EQ(ok_plain, ok_nojac) << p.transpose();
    if (!ok_plain) continue;
    ++*n_projected;
    for (int k = 0; k < 2; ++k) {
      ASSERT_EQ(uv_plain[k], uv_fast[k]) << p.transpose();
      ASSERT_EQ(uv_plain[k], uv_nojac[k]) << p.transpose();
    }
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(J_plain(r, c), J_fast(r, c)) << p.transpose() << " J(" << r << "," << c << ")";
  }
}

}  // namespace

TEST(CameraProjection, PinholeRadtanProjectMatchesPlainDistortChainExactly) {
  std::mt19937 rng(7);
  int n_projected = 0;
  // EuRoC cam0, no distortion, and random coefficient sets (with and without k3).
  std::vector<PinholeRadtan> cams{
      PinholeRadtan(752, 480, 458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05),
      PinholeRadtan(640, 480, 500.0, 500.0, 320.0, 240.0)};
  std::uniform_real_distribution<double> k(-0.3, 0.3), p(-0.01, 0.01), f(100.0, 1500.0);
  for (int c = 0; c < 20; ++c)
    cams.emplace_back(640, 480, f(rng), f(rng), 320.5, 239.5, k(rng), 0.3 * k(rng), p(rng), p(rng),
                      c % 2 ? 0.1 * k(rng) : 0.0);
  for (const PinholeRadtan& cam : cams) expectSameAsPlain(cam, randomPoints(&rng, 5000), &n_projected);
  EXPECT_GT(n_projected, 50000);
}

TEST(CameraProjection, KannalaBrandtPixelIndependentOfJacobianRequest) {
  const KannalaBrandt cam(512, 512, 190.978477, 190.973307, 254.931706, 256.897442, 0.0034823894022493434,
                          0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int n_projected = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    Eigen::Vector2d a(-1, -1), b(-2, -2);
    Eigen::Matrix<double, 2, 3> J;
    const bool ok_a = cam.project(p, &a, &J), ok_b = cam.project(p, &b);
    ASSERT_EQ(ok_a, ok_b);
    if (!ok_a) continue;
    ++n_projected;
    ASSERT_EQ(a.x(), b.x());
    ASSERT_EQ(a.y(), b.y());
  }
  EXPECT_GT(n_projected, 10000);
}
