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

// The observations of one pose problem: left pixels, and the right ones of a stereo frame (right == nullptr: none).
struct PoseObservations {
  const CameraModel& cam;
  const std::vector<Eigen::Vector3d>& p_w;
  const std::vector<Eigen::Vector2d>& uv;
  const std::vector<double>& sigma;
  const RightObservations* right;
};

// Squared right-image pixel error of observation i at T (-1: does not project into the right camera).
double rightError2(const PoseObservations& o, const Eigen::Isometry3d& T, size_t i) {
  return reprojectionError2(*o.right->camera, o.right->T_r_l * T, o.p_w[i], o.right->uv[i]);
}

// Robust cost of the current pose over the used observations: sum of Huber(|r|^2), r sigma-normalized, the right
// residuals in use (right_use) next to their left ones. An observation that does not project at T is listed in
// *behind (a right one in *right_behind) and left out of the sum.
double poseCost(const PoseObservations& o, const Eigen::Isometry3d& T, const std::vector<char>& use,
                const std::vector<char>& right_use, double delta, bool robust, std::vector<size_t>* behind,
                std::vector<size_t>* right_behind) {
  double c = 0.0;
  for (size_t i = 0; i < o.p_w.size(); ++i) {
    if (!use[i]) continue;
    const double e2 = reprojectionError2(o.cam, T, o.p_w[i], o.uv[i]);
    if (e2 < 0) {
      behind->push_back(i);
      continue;
    }
    c += huberTerm(e2, o.sigma[i], delta, robust);
    if (!o.right || !right_use[i]) continue;
    const double e2r = rightError2(o, T, i);
    if (e2r < 0) right_behind->push_back(i);
    else c += huberTerm(e2r, o.right->sigma[i], delta, robust);
  }
  return c;
}

// poseCost() from squared errors already computed at the pose (e2[i] >= 0 for every used i, e2r[i] >= 0 for every
// right one in use).
double poseCostOfErrors2(const PoseObservations& o, const std::vector<double>& e2, const std::vector<double>& e2r,
                         const std::vector<char>& use, const std::vector<char>& right_use, double delta, bool robust) {
  double c = 0.0;
  for (size_t i = 0; i < e2.size(); ++i) {
    if (!use[i]) continue;
    c += huberTerm(e2[i], o.sigma[i], delta, robust);
    if (o.right && right_use[i]) c += huberTerm(e2r[i], o.right->sigma[i], delta, robust);
  }
  return c;
}

// One residual's Gauss-Newton terms: r = (pr - uv) / sigma with d(pr)/d(point in the camera) = J, the point
// p_c = R p + t moving with the left perturbation as d(p_c) = A [dt, dtheta], A = [I, -skew(Rp)] (left camera) or
// R_rl [I, -skew(Rp)] (right camera: M = R_rl).
void addResidual(const Eigen::Matrix<double, 2, 3>& J, const Eigen::Vector2d& pr, const Eigen::Vector2d& uv,
                 double sigma, const Eigen::Matrix3d* M, const Eigen::Vector3d& Rp, double delta, bool robust,
                 Eigen::Matrix<double, 6, 6>* H, Eigen::Matrix<double, 6, 1>* g) {
  const double is = 1.0 / sigma;
  const Eigen::Vector2d r = (pr - uv) * is;
  Eigen::Matrix<double, 2, 6> Jp;
  if (M) Jp.leftCols<3>() = J * (*M) * is;
  else Jp.leftCols<3>() = J * is;
  Jp.rightCols<3>() = -Jp.leftCols<3>() * skew(Rp);
  const double e = r.norm();
  const double w = (!robust || e <= delta) ? 1.0 : delta / e;  // Huber IRLS weight
  addWeightedNormalEquations(Jp, r, w, H, g);
}

// Levenberg-Marquardt on the 6-dof left perturbation (t' = t + dt, R' = Exp(dtheta) R) with Huber IRLS weights:
// the same model and Jacobian as PoseOnlyCost, solved on 6x6 normal equations (no per-residual allocation).
// initial_cost: poseCost() at *T.
// A trial pose at which an observation does not project (behind the camera, outside a fisheye's field of view) drops
// that observation from this solve and the iteration starts again from the current pose (the round's chi2
// classification then decides on it); rejecting the trial instead cost fisheye sequences ~5 % of all trials.
void solvePoseLM(const PoseObservations& o, std::vector<char> use, std::vector<char> right_use, double delta,
                 bool robust, int max_iterations, double initial_cost, Eigen::Isometry3d* T) {
  double lambda = 1e-4;
  double cost = initial_cost;
  std::vector<size_t> behind, right_behind;
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    const Eigen::Matrix3d R = T->rotation();
    for (size_t i = 0; i < o.p_w.size(); ++i) {
      if (!use[i]) continue;
      const Eigen::Vector3d Rp = R * o.p_w[i];
      const Eigen::Vector3d pc = Rp + T->translation();
      Eigen::Vector2d pr;
      Eigen::Matrix<double, 2, 3> J;
      if (pc.z() <= 1e-6 || !o.cam.project(pc, &pr, &J)) continue;
      addResidual(J, pr, o.uv[i], o.sigma[i], nullptr, Rp, delta, robust, &H, &g);
      if (!o.right || !right_use[i]) continue;
      const Eigen::Vector3d prc = o.right->T_r_l * pc;
      if (prc.z() <= 1e-6 || !o.right->camera->project(prc, &pr, &J)) continue;
      const Eigen::Matrix3d R_rl = o.right->T_r_l.linear();
      addResidual(J, pr, o.right->uv[i], o.right->sigma[i], &R_rl, Rp, delta, robust, &H, &g);
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
      right_behind.clear();
      const double cn = poseCost(o, Tn, use, right_use, delta, robust, &behind, &right_behind);
      if (!behind.empty() || !right_behind.empty()) {
        for (size_t i : behind) use[i] = 0;
        for (size_t i : right_behind) right_use[i] = 0;
        behind.clear();
        right_behind.clear();
        cost = poseCost(o, *T, use, right_use, delta, robust, &behind, &right_behind);  // all project at *T
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

int RightObservations::count() const {
  if (!camera) return 0;
  return static_cast<int>(std::count_if(sigma.begin(), sigma.end(), [](double s) { return s > 0.0; }));
}

int optimizePose(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, const PoseOptimizationOptions& options, Eigen::Isometry3d* T_c_w,
                 std::vector<char>* inlier, const RightObservations* right, int* right_inliers) {
  const size_t n = p_w.size();
  if (inlier->size() != n) inlier->assign(n, 1);
  if (right_inliers) *right_inliers = 0;
  if (right && (right->count() == 0 || right->uv.size() != n || right->sigma.size() != n)) right = nullptr;
  const PoseObservations obs{cam, p_w, uv, sigma, right};
  int n_inliers = 0;
  // Squared pixel error of each observation at *T_c_w (valid for the inliers): computed here for the first
  // round, then by each round's classification (its inliers all project, so no observation is dropped again).
  // The right residuals (e2r, right_use) join from the second round on, where the first round's classification
  // passed both errors: in the first round a wrong match would count twice against the Huber kernel (on EuRoC
  // that pulled a frame 20 mm off, with half of its inliers lost).
  std::vector<double> e2(n, -1.0), e2r;
  std::vector<char> right_use;
  for (size_t i = 0; i < n; ++i)
    if ((*inlier)[i]) e2[i] = reprojectionError2(cam, *T_c_w, p_w[i], uv[i]);
  if (right) {
    e2r.assign(n, -1.0);
    right_use.assign(n, 0);
  }
  for (int round = 0; round < std::max(1, options.rounds); ++round) {
    // Huber only in the first rounds (ORB-SLAM drops the robust kernel in the last one).
    const bool robust = round + 1 < options.rounds;
    int used = 0;
    for (size_t i = 0; i < n; ++i) {
      if ((*inlier)[i] && e2[i] < 0) (*inlier)[i] = 0;
      if (right && !(*inlier)[i]) right_use[i] = 0;
      used += (*inlier)[i];
    }
    if (used < 4) return 0;
    if (!options.use_ceres || right) {
      const double cost = poseCostOfErrors2(obs, e2, e2r, *inlier, right_use, options.huber_delta, robust);
      solvePoseLM(obs, *inlier, right_use, options.huber_delta, robust, options.max_num_iterations, cost, T_c_w);
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
    // chi2 classification over all observations (outliers may come back); a right residual is used while both
    // its left and its right error pass.
    n_inliers = 0;
    int n_right = 0;
    for (size_t i = 0; i < n; ++i) {
      e2[i] = reprojectionError2(cam, *T_c_w, p_w[i], uv[i]);
      const bool ok = e2[i] >= 0 && e2[i] / (sigma[i] * sigma[i]) <= options.chi2_threshold;
      (*inlier)[i] = ok;
      n_inliers += ok;
      if (!right) continue;
      const double sr = right->sigma[i];
      e2r[i] = ok && sr > 0.0 ? rightError2(obs, *T_c_w, i) : -1.0;
      right_use[i] = e2r[i] >= 0 && e2r[i] / (sr * sr) <= options.chi2_threshold;
      n_right += right_use[i];
    }
    if (right_inliers) *right_inliers = n_right;
    if (n_inliers < 4) return n_inliers;
  }
  return n_inliers;
}

}  // namespace iraf_vo
