#include "iraf_vo/tracking/two_view_ambiguity.h"

#include <Eigen/SVD>

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace iraf_vo {

namespace {

// Sampson error of one match under E = [t]x R, in units of the noise: (x2' E x1) / sqrt(|(E x1)_12|^2 +
// |(E' x2)_12|^2) * focal / sigma (first-order geometric error summed over both images).
struct SampsonResidual {
  SampsonResidual(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double scale) : x1(a), x2(b), s(scale) {}
  template <typename T>
  bool operator()(const T* q, const T* t, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q(q);
    const Eigen::Matrix<T, 3, 1> tt(t[0], t[1], t[2]);
    Eigen::Matrix<T, 3, 3> tx;
    tx << T(0), -tt.z(), tt.y(), tt.z(), T(0), -tt.x(), -tt.y(), tt.x(), T(0);
    const Eigen::Matrix<T, 3, 3> E = tx * Q.toRotationMatrix();
    const Eigen::Matrix<T, 3, 1> X1(T(x1.x()), T(x1.y()), T(1)), X2(T(x2.x()), T(x2.y()), T(1));
    const Eigen::Matrix<T, 3, 1> l2 = E * X1, l1 = E.transpose() * X2;
    const T den = l2(0) * l2(0) + l2(1) * l2(1) + l1(0) * l1(0) + l1(1) * l1(1);
    r[0] = X2.dot(l2) / sqrt(den + T(1e-30)) * T(s);
    return true;
  }
  Eigen::Vector2d x1, x2;
  double s;
};

struct Motion {
  Eigen::Quaterniond q;
  Eigen::Vector3d t;
  double chi2 = std::numeric_limits<double>::infinity();
};

// Local refinement of (R, t), |t| = 1 (or R alone for a fixed t), on the robust chi2 of the Sampson errors;
// fixed iterations, one thread (the result does not depend on the machine).
Motion refineMotion(const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2, Motion m,
                    double focal, double sigma_px, bool fix_t = false) {
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  // In sigma units. Bounded (Tukey's biweight): gross outliers cost a constant whatever the motion, so they
  // cannot pull the profile (Huber's linear tails let 10 % swapped matches prefer a translation 60 deg off).
  ceres::TukeyLoss loss(4.685);
  ceres::EigenQuaternionManifold q_manifold;
  ceres::SphereManifold<3> t_manifold;
  m.q.normalize();
  m.t.normalize();
  double* q = m.q.coeffs().data();
  double* t = m.t.data();
  problem.AddParameterBlock(q, 4, &q_manifold);
  problem.AddParameterBlock(t, 3, &t_manifold);
  for (size_t i = 0; i < p1.size(); ++i)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonResidual, 1, 4, 3>(
                                 new SampsonResidual(p1[i], p2[i], focal / sigma_px)),
                             &loss, q, t);
  if (fix_t) problem.SetParameterBlockConstant(t);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 20;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  m.chi2 = summary.IsSolutionUsable() ? 2.0 * summary.final_cost : std::numeric_limits<double>::infinity();
  return m;
}

// Angle between the lines of two translations (E fixes t up to sign), degrees.
double lineAngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180.0 / M_PI;
}

}  // namespace

MotionAmbiguity findTranslationAmbiguity(const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2,
                                         const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double focal,
                                         const MotionAmbiguityParams& params) {
  MotionAmbiguity out;
  if (p1.size() != p2.size() || p1.size() < 8 || !(t.norm() > 1e-12)) return out;
  const double sigma = params.sigma_px;
  const Motion best = refineMotion(p1, p2, Motion{Eigen::Quaterniond(R), t.normalized()}, focal, sigma);
  // The chosen motion must be (near) a minimum of the robust epipolar cost of all matches: refined, its
  // translation moving by min_angle_deg or more means the matches do not pin it down (seen: RANSAC's motion 56 deg
  // off the truth, the refined one 20 deg off, at 1 deg parallax and 2 px noise). The refined motion is then the
  // other motion (at profile chi2 0: it explains the matches better), and the search below is not needed.
  out.refined_shift_deg = lineAngleDeg(best.t, t);
  if (params.max_delta_chi2 > 0.0 && out.refined_shift_deg >= params.min_angle_deg) {
    out.ambiguous = true;
    out.angle_deg = out.refined_shift_deg;
    out.R_other = best.q.toRotationMatrix();
    out.t_other = best.t;
    return out;
  }
  const double s2 = std::max(1e-12, best.chi2 / std::max<double>(1, p1.size() - 5));
  out.sigma_est_px = std::sqrt(s2) * sigma;
  const Eigen::Vector3d a = best.t.unitOrthogonal(), b = best.t.cross(a);
  auto tilted = [&](const Eigen::Vector3d& dir, double deg) {
    return Eigen::Vector3d(Eigen::AngleAxisd(deg * M_PI / 180.0, best.t.cross(dir).normalized()) * best.t);
  };
  // Profile chi2 of the translation direction (rotation re-optimized), in units of the estimated noise.
  auto profile = [&](const Eigen::Quaterniond& q0, const Eigen::Vector3d& t_fixed, Motion* m) {
    *m = refineMotion(p1, p2, Motion{q0, t_fixed}, focal, sigma, true);
    return (m->chi2 - best.chi2) / s2;
  };
  // Its curvature from 4 tilts of h deg (P(phi) = P(phi + 180 deg)): P(phi) ~ h^2 (c11 cos^2 + 2 c12 cos sin +
  // c22 sin^2); the weakest direction is the eigenvector of the smallest eigenvalue.
  const double h = 5.0;
  Eigen::Matrix<double, 4, 3> A;
  Eigen::Matrix<double, 4, 1> y;
  for (int k = 0; k < 4; ++k) {
    const double phi = k * M_PI / 4.0, c = std::cos(phi), sn = std::sin(phi);
    Motion m;
    y(k) = profile(best.q, tilted(c * a + sn * b, h), &m);
    A.row(k) << c * c, 2 * c * sn, sn * sn;
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(y);
  Eigen::Matrix2d C;
  C << c(0), c(1), c(1), c(2);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
  const Eigen::Vector2d w = eig.eigenvectors().col(0);
  const Eigen::Vector3d weak = w(0) * a + w(1) * b;
  out.profile_chi2 = std::numeric_limits<double>::infinity();
  auto consider = [&](double p, double angle_deg, const Motion& m) {  // keeps the best other motion
    if (angle_deg < params.min_angle_deg || !(p < out.profile_chi2)) return;
    out.profile_chi2 = p;
    out.angle_deg = angle_deg;
    out.R_other = m.q.toRotationMatrix();
    out.t_other = m.t;
  };
  // Along the weakest direction, both ways, following the valley (each step starts from the previous rotation).
  for (double sign : {1.0, -1.0}) {
    Eigen::Quaterniond q = best.q;
    for (double deg : {params.min_angle_deg, 45.0, 90.0}) {
      Motion m;
      const double p = profile(q, tilted(sign * weak, deg), &m);
      q = m.q;
      consider(p, deg, m);
    }
  }
  // A second minimum off the valley: free refinements from 8 restarts (4 directions, tilted 45 and 90 deg).
  for (int k = 0; k < 4; ++k)
    for (double deg : {45.0, 90.0}) {
      const double phi = k * M_PI / 2.0;
      const Motion m = refineMotion(p1, p2, Motion{best.q, tilted(std::cos(phi) * a + std::sin(phi) * b, deg)}, focal,
                                    sigma);
      consider((m.chi2 - best.chi2) / s2, lineAngleDeg(m.t, best.t), m);
    }
  out.ambiguous = params.max_delta_chi2 > 0.0 && out.profile_chi2 < params.max_delta_chi2;
  return out;
}

int inliersOfPureRotation(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                          const std::vector<char>& inliers, double focal, double threshold_px) {
  std::vector<char> use = inliers;
  int n = 0;
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < b1.size(); ++i)
      if (use[i]) M += b2[i].normalized() * b1[i].normalized().transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();  // b2 ~ R b1 (Kabsch)
    n = 0;
    for (size_t i = 0; i < b1.size(); ++i) {
      const double e = std::acos(std::clamp((R * b1[i].normalized()).dot(b2[i].normalized()), -1.0, 1.0)) * focal;
      use[i] = inliers[i] && e < 2.0 * threshold_px;
      n += use[i];
    }
    if (n < 3) break;
  }
  return n;
}

}  // namespace iraf_vo
