// Pose-only refinement (pose_optimization.h): Levenberg-Marquardt on 6x6 normal equations with Huber IRLS
// weights, or ceres::Solve on the same model. ROS-free.
#include "iraf_vo/tracking/pose_optimization.h"

#include "ceres_blocks.h"
#include "iraf_vo/tracking/geometry.h"
#include "iraf_vo/tracking/multiview.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace iraf_vo {

using ceres_blocks::blockToPose;
using ceres_blocks::PoseManifold;
using ceres_blocks::PoseOnlyCost;
using ceres_blocks::poseToBlock;

namespace {

// One observation's term of the pose cost: Huber(|r|^2) (or |r|^2), r = pixel error / sigma, e2 = |pixel error|^2.
double huberTerm(double e2, double sigma, double delta, bool robust) {
  const double s2 = e2 / (sigma * sigma);
  return (!robust || s2 <= delta * delta) ? s2 : 2.0 * delta * std::sqrt(s2) - delta * delta;
}

// Robust cost of the current pose over the used observations: sum of Huber(|r|^2), r sigma-normalized. An
// observation that does not project at T is listed in *behind and left out of the sum.
double poseCost(const CameraModel& cam, const Eigen::Isometry3d& T, const std::vector<Eigen::Vector3d>& p_w,
                const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& sigma, const std::vector<char>& use,
                double delta, bool robust, std::vector<size_t>* behind) {
  double c = 0.0;
  for (size_t i = 0; i < p_w.size(); ++i) {
    if (!use[i]) continue;
    const double e2 = reprojectionError2(cam, T, p_w[i], uv[i]);
    if (e2 < 0) {
      behind->push_back(i);
      continue;
    }
    c += huberTerm(e2, sigma[i], delta, robust);
  }
  return c;
}

// poseCost() from squared errors already computed at the pose (e2[i] >= 0 for every used i).
double poseCostOfErrors2(const std::vector<double>& e2, const std::vector<double>& sigma, const std::vector<char>& use,
                         double delta, bool robust) {
  double c = 0.0;
  for (size_t i = 0; i < e2.size(); ++i)
    if (use[i]) c += huberTerm(e2[i], sigma[i], delta, robust);
  return c;
}

// Levenberg-Marquardt on the 6-dof left perturbation (t' = t + dt, R' = Exp(dtheta) R) with Huber IRLS weights:
// the same model and Jacobian as PoseOnlyCost, solved on 6x6 normal equations (no per-residual allocation).
// initial_cost: poseCost() at *T.
// A trial pose at which an observation does not project (behind the camera, outside a fisheye's field of view) drops
// that observation from this solve and the iteration starts again from the current pose (the round's chi2
// classification then decides on it); rejecting the trial instead cost fisheye sequences ~5 % of all trials.
void solvePoseLM(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, std::vector<char> use, double delta, bool robust,
                 int max_iterations, double initial_cost, Eigen::Isometry3d* T) {
  double lambda = 1e-4;
  double cost = initial_cost;
  std::vector<size_t> behind;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    const Eigen::Matrix3d R = T->rotation();
    for (size_t i = 0; i < p_w.size(); ++i) {
      if (!use[i]) continue;
      const Eigen::Vector3d Rp = R * p_w[i];
      const Eigen::Vector3d pc = Rp + T->translation();
      Eigen::Vector2d pr;
      Eigen::Matrix<double, 2, 3> J;
      if (pc.z() <= 1e-6 || !cam.project(pc, &pr, &J)) continue;
      const double is = 1.0 / sigma[i];
      const Eigen::Vector2d r = (pr - uv[i]) * is;
      Eigen::Matrix<double, 2, 6> Jp;
      Jp.leftCols<3>() = J * is;
      Jp.rightCols<3>() = -Jp.leftCols<3>() * skew(Rp);
      const double e = r.norm();
      const double w = (!robust || e <= delta) ? 1.0 : delta / e;  // Huber IRLS weight
      addWeightedNormalEquations(Jp, r, w, &H, &g);
    }
    // Only the lower triangle is summed (LDLT reads no other); the upper one mirrors it.
    copyLowerToUpper(&H);
    bool improved = false, dropped = false;
    for (int tries = 0; tries < 6 && !improved && !dropped; ++tries) {
      Eigen::Matrix<double, 6, 6> A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-9);
      const Eigen::Matrix<double, 6, 1> dx = A.ldlt().solve(-g);
      if (!dx.allFinite()) break;
      Eigen::Isometry3d Tn = *T;
      const double ang = dx.tail<3>().norm();
      const Eigen::Matrix3d dR =
          ang > 1e-12 ? Eigen::AngleAxisd(ang, dx.tail<3>() / ang).toRotationMatrix() : Eigen::Matrix3d::Identity();
      // Re-orthonormalize through a unit quaternion: Isometry3d::inverse() assumes R^T = R^-1, and products of
      // slightly non-orthogonal matrices blow up through the constant-velocity model.
      Tn.linear() = Eigen::Quaterniond(dR * R).normalized().toRotationMatrix();
      Tn.translation() = T->translation() + dx.head<3>();
      behind.clear();
      const double cn = poseCost(cam, Tn, p_w, uv, sigma, use, delta, robust, &behind);
      if (!behind.empty()) {
        for (size_t i : behind) use[i] = 0;
        behind.clear();
        cost = poseCost(cam, *T, p_w, uv, sigma, use, delta, robust, &behind);  // all project at *T
        dropped = true;
        continue;
      }
      if (cn < cost) {
        *T = Tn;
        improved = true;
        const bool converged = (cost - cn) < 1e-10 * cost || dx.norm() < 1e-10;
        cost = cn;
        lambda = std::max(1e-7, lambda * 0.3);
        if (converged) return;
      } else {
        lambda *= 10.0;
      }
    }
    if (!improved && !dropped) return;
  }
}

}  // namespace

int optimizePose(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, const PoseOptimizationOptions& options, Eigen::Isometry3d* T_c_w,
                 std::vector<char>* inlier) {
  const size_t n = p_w.size();
  if (inlier->size() != n) inlier->assign(n, 1);
  int n_inliers = 0;
  // Squared pixel error of each observation at *T_c_w (valid for the inliers): computed here for the first
  // round, then by each round's classification (its inliers all project, so no observation is dropped again).
  std::vector<double> e2(n, -1.0);
  for (size_t i = 0; i < n; ++i)
    if ((*inlier)[i]) e2[i] = reprojectionError2(cam, *T_c_w, p_w[i], uv[i]);
  for (int round = 0; round < std::max(1, options.rounds); ++round) {
    // Huber only in the first rounds (ORB-SLAM drops the robust kernel in the last one).
    const bool robust = round + 1 < options.rounds;
    int used = 0;
    for (size_t i = 0; i < n; ++i) {
      if ((*inlier)[i] && e2[i] < 0) (*inlier)[i] = 0;
      used += (*inlier)[i];
    }
    if (used < 4) return 0;
    if (!options.use_ceres) {
      const double cost = poseCostOfErrors2(e2, sigma, *inlier, options.huber_delta, robust);
      solvePoseLM(cam, p_w, uv, sigma, *inlier, options.huber_delta, robust, options.max_num_iterations, cost, T_c_w);
    } else {
      double pose[7];
      poseToBlock(*T_c_w, pose);
      ceres::Problem::Options popts;
      popts.manifold_ownership = ceres::TAKE_OWNERSHIP;
      popts.loss_function_ownership = ceres::TAKE_OWNERSHIP;
      popts.cost_function_ownership = ceres::TAKE_OWNERSHIP;
      ceres::Problem problem(popts);
      problem.AddParameterBlock(pose, 7, new PoseManifold);
      for (size_t i = 0; i < n; ++i) {
        if (!(*inlier)[i]) continue;
        ceres::LossFunction* loss = robust ? new ceres::HuberLoss(options.huber_delta) : nullptr;
        problem.AddResidualBlock(new PoseOnlyCost(&cam, p_w[i], uv[i], sigma[i]), loss, pose);
      }
      ceres::Solver::Options so;
      so.linear_solver_type = ceres::DENSE_QR;
      so.max_num_iterations = options.max_num_iterations;
      so.num_threads = 1;
      so.logging_type = ceres::SILENT;
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
      *T_c_w = blockToPose(pose);
    }
    // chi2 classification over all observations (outliers may come back).
    n_inliers = 0;
    for (size_t i = 0; i < n; ++i) {
      e2[i] = reprojectionError2(cam, *T_c_w, p_w[i], uv[i]);
      const bool ok = e2[i] >= 0 && e2[i] / (sigma[i] * sigma[i]) <= options.chi2_threshold;
      (*inlier)[i] = ok;
      n_inliers += ok;
    }
    if (n_inliers < 4) return n_inliers;
  }
  return n_inliers;
}

}  // namespace iraf_vo
