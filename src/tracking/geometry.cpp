#include <iraf_vo/tracking/geometry.h>

#include <ceres/ceres.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <deque>
#include <limits>
#include <memory>

namespace iraf_vo {

namespace {

// Pose block layout: [tx ty tz qx qy qz qw] of T_c_w. Tangent: [dt, dtheta] with the left perturbation
// t' = t + dt, R' = Exp(dtheta) R. The cost functions fill the first 6 columns of their 2x7 pose Jacobian
// with the tangent Jacobian, so PlusJacobian = [I6; 0].
class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    Eigen::Map<const Eigen::Vector3d> t(x);
    Eigen::Map<const Eigen::Quaterniond> q(x + 3);
    Eigen::Map<const Eigen::Vector3d> dt(delta);
    Eigen::Map<const Eigen::Vector3d> dth(delta + 3);
    Eigen::Map<Eigen::Vector3d> t_out(x_plus_delta);
    Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
    const double angle = dth.norm();
    Eigen::Quaterniond dq = angle > 1e-12 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, dth / angle))
                                          : Eigen::Quaterniond(1.0, 0.5 * dth.x(), 0.5 * dth.y(), 0.5 * dth.z());
    q_out = (dq * q).normalized();
    t_out = t + dt;
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Map<const Eigen::Vector3d> ty(y), tx(x);
    Eigen::Map<const Eigen::Quaterniond> qy(y + 3), qx(x + 3);
    Eigen::Map<Eigen::Vector3d> dt(y_minus_x), dth(y_minus_x + 3);
    dt = ty - tx;
    Eigen::AngleAxisd aa(qy * qx.conjugate());
    dth = aa.angle() * aa.axis();
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
};

void poseToBlock(const Eigen::Isometry3d& T, double* b) {
  (Eigen::Map<Eigen::Vector3d>(b)) = T.translation();
  Eigen::Quaterniond q(T.rotation());
  q.normalize();
  b[3] = q.x(); b[4] = q.y(); b[5] = q.z(); b[6] = q.w();
}

Eigen::Isometry3d blockToPose(const double* b) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(b[6], b[3], b[4], b[5]);
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(b[0], b[1], b[2]);
  return T;
}

// r = (pi(R p_w + t) - uv) / sigma
class ReprojectionCost final : public ceres::SizedCostFunction<2, 7, 3> {
 public:
  ReprojectionCost(const CameraModel* cam, const Eigen::Vector2d& uv, double sigma)
      : cam_(cam), uv_(uv), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    Eigen::Map<const Eigen::Vector3d> t(params[0]);
    Eigen::Map<const Eigen::Quaterniond> q(params[0] + 3);
    Eigen::Map<const Eigen::Vector3d> p_w(params[1]);
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const Eigen::Vector3d Rp = R * p_w;
    const Eigen::Vector3d p_c = Rp + t;
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    // Cost-only evaluations (trial steps) pass no Jacobians: the projection's Jacobian is not formed then.
    if (p_c.z() <= 1e-6 || !cam_->project(p_c, &uv, jacobians ? &J : nullptr)) return false;
    (Eigen::Map<Eigen::Vector2d>(residuals)) = (uv - uv_) * inv_sigma_;
    if (jacobians) {
      J *= inv_sigma_;
      if (jacobians[0]) {
        Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> Jp(jacobians[0]);
        Jp.leftCols<3>() = J;
        Jp.block<2, 3>(0, 3) = -J * skew(Rp);
        Jp.col(6).setZero();
      }
      if (jacobians[1]) {
        Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jx(jacobians[1]);
        Jx = J * R;
      }
    }
    return true;
  }

 private:
  const CameraModel* cam_;
  Eigen::Vector2d uv_;
  double inv_sigma_;
};

class PoseOnlyCost final : public ceres::SizedCostFunction<2, 7> {
 public:
  PoseOnlyCost(const CameraModel* cam, const Eigen::Vector3d& p_w, const Eigen::Vector2d& uv, double sigma)
      : cam_(cam), p_w_(p_w), uv_(uv), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    Eigen::Map<const Eigen::Vector3d> t(params[0]);
    Eigen::Map<const Eigen::Quaterniond> q(params[0] + 3);
    const Eigen::Vector3d Rp = q.toRotationMatrix() * p_w_;
    const Eigen::Vector3d p_c = Rp + t;
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    const bool want_jacobian = jacobians && jacobians[0];
    if (p_c.z() <= 1e-6 || !cam_->project(p_c, &uv, want_jacobian ? &J : nullptr)) return false;
    (Eigen::Map<Eigen::Vector2d>(residuals)) = (uv - uv_) * inv_sigma_;
    if (want_jacobian) {
      J *= inv_sigma_;
      Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> Jp(jacobians[0]);
      Jp.leftCols<3>() = J;
      Jp.block<2, 3>(0, 3) = -J * skew(Rp);
      Jp.col(6).setZero();
    }
    return true;
  }

 private:
  const CameraModel* cam_;
  Eigen::Vector3d p_w_;
  Eigen::Vector2d uv_;
  double inv_sigma_;
};

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Stops the solver between iterations when the abort flag is set or the calling thread used max_cpu_seconds of
// CPU time since construction (a load-independent budget: the wall clock grows with the machine's load).
class AbortCallback final : public ceres::IterationCallback {
 public:
  AbortCallback(const std::atomic<bool>* flag, double max_cpu_seconds)
      : flag_(flag), max_cpu_(max_cpu_seconds), cpu0_(threadCpuSeconds()) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    if (flag_ && flag_->load()) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    if (max_cpu_ > 0.0 && threadCpuSeconds() - cpu0_ > max_cpu_) {
      cpu_budget_hit = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }
  bool cpu_budget_hit = false;

 private:
  const std::atomic<bool>* flag_;
  double max_cpu_;
  double cpu0_;
};

}  // namespace

namespace {

// One observation's term of the pose cost: Huber(|r|^2) (or |r|^2), r = pixel error / sigma, e2 = |pixel error|^2.
double huberTerm(double e2, double sigma, double delta, bool robust) {
  const double s2 = e2 / (sigma * sigma);
  return (!robust || s2 <= delta * delta) ? s2 : 2.0 * delta * std::sqrt(s2) - delta * delta;
}

// Robust cost of the current pose over the used observations: sum of Huber(|r|^2), r sigma-normalized.
double poseCost(const CameraModel& cam, const Eigen::Isometry3d& T, const std::vector<Eigen::Vector3d>& p_w,
                const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& sigma, const std::vector<char>& use,
                double delta, bool robust) {
  double c = 0.0;
  for (size_t i = 0; i < p_w.size(); ++i) {
    if (!use[i]) continue;
    const double e2 = reprojectionError2(cam, T, p_w[i], uv[i]);
    if (e2 < 0) return std::numeric_limits<double>::infinity();
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
void solvePoseLM(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, const std::vector<char>& use, double delta, bool robust,
                 int max_iterations, double initial_cost, Eigen::Isometry3d* T) {
  double lambda = 1e-4;
  double cost = initial_cost;
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
      H.noalias() += w * Jp.transpose() * Jp;
      g.noalias() += w * Jp.transpose() * r;
    }
    bool improved = false;
    for (int tries = 0; tries < 6 && !improved; ++tries) {
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
      const double cn = poseCost(cam, Tn, p_w, uv, sigma, use, delta, robust);
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
    if (!improved) return;
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

namespace {

// Squared pixel error of every observation, -1 where the point does not project (reprojectionError2).
std::vector<double> observationErrors2(const CameraModel& cam, const std::vector<BAKeyframe>& kfs,
                                       const std::vector<BAPoint>& pts, const std::vector<BAObservation>& obs) {
  std::vector<double> e2(obs.size());
  for (size_t j = 0; j < obs.size(); ++j)
    e2[j] = reprojectionError2(cam, kfs[obs[j].keyframe].T_c_w, pts[obs[j].point].p_w, obs[j].uv);
  return e2;
}

// RMSE over observationErrors2(); an observation that does not project counts as 1000 px.
double rmseOfErrors2(const std::vector<double>& e2) {
  if (e2.empty()) return 0.0;
  double s = 0.0;
  for (const double e : e2) s += e < 0 ? 1e6 : e;
  return std::sqrt(s / e2.size());
}

}  // namespace

double reprojectionRmse(const CameraModel& cam, const std::vector<BAKeyframe>& kfs, const std::vector<BAPoint>& pts,
                        const std::vector<BAObservation>& obs) {
  return rmseOfErrors2(observationErrors2(cam, kfs, pts, obs));
}

bool bundleAdjust(const CameraModel& cam, std::vector<BAKeyframe>* kfs, std::vector<BAPoint>* pts,
                  const std::vector<BAObservation>& obs, const BAOptions& options, BASummary* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  BASummary local;
  BASummary& sum = summary ? *summary : local;
  sum = BASummary();
  sum.outlier.assign(obs.size(), 0);
  if (obs.empty() || kfs->empty() || pts->empty()) return false;
  std::vector<double> poses(7 * kfs->size());
  for (size_t k = 0; k < kfs->size(); ++k) poseToBlock((*kfs)[k].T_c_w, &poses[7 * k]);
  std::vector<double> points(3 * pts->size());
  for (size_t i = 0; i < pts->size(); ++i) (Eigen::Map<Eigen::Vector3d>(&points[3 * i])) = (*pts)[i].p_w;

  // Declared before the problem so they outlive it (shared by all residuals, not owned by the problem).
  // The cost functions live in one container (no per-residual delete, no ownership bookkeeping in the problem).
  PoseManifold manifold;
  std::unique_ptr<ceres::HuberLoss> huber(new ceres::HuberLoss(options.huber_delta));
  ceres::HuberLoss* loss = huber.get();
  std::deque<ReprojectionCost> costs;
  ceres::Problem::Options popts;
  popts.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popts.disable_all_safety_checks = true;  // each residual has one pose and one distinct point block
  ceres::Problem problem(popts);
  std::vector<char> pose_added(kfs->size(), 0);
  // Errors before the solve: which observations project, and the initial RMSE (the same values).
  const std::vector<double> e2_initial = observationErrors2(cam, *kfs, *pts, obs);
  int n_res = 0;
  for (size_t j = 0; j < obs.size(); ++j) {
    const auto& o = obs[j];
    if (e2_initial[j] < 0) {
      sum.outlier[j] = 1;
      continue;
    }
    double* pb = &poses[7 * o.keyframe];
    if (!pose_added[o.keyframe]) {
      problem.AddParameterBlock(pb, 7, &manifold);
      if ((*kfs)[o.keyframe].fixed) problem.SetParameterBlockConstant(pb);
      pose_added[o.keyframe] = 1;
    }
    costs.emplace_back(&cam, o.uv, o.sigma);
    problem.AddResidualBlock(&costs.back(), loss, pb, &points[3 * o.point]);
    ++n_res;
  }
  bool ok = false;
  if (n_res > 0) {
    sum.initial_rmse_px = rmseOfErrors2(e2_initial);
    ceres::Solver::Options so;
    so.linear_solver_type = options.dense_schur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
    // Explicit Schur ordering (points eliminated first) saves Ceres' independent-set search.
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (size_t i = 0; i < pts->size(); ++i)
      if (problem.HasParameterBlock(&points[3 * i])) ordering->AddElementToGroup(&points[3 * i], 0);
    for (size_t k = 0; k < kfs->size(); ++k)
      if (pose_added[k]) ordering->AddElementToGroup(&poses[7 * k], 1);
    so.linear_solver_ordering = ordering;
    so.max_num_iterations = options.max_num_iterations;
    so.max_solver_time_in_seconds = options.max_solver_time_in_seconds;
    so.num_threads = std::max(1, options.num_threads);
    so.logging_type = ceres::SILENT;
    AbortCallback cb(options.abort, options.max_cpu_seconds);
    if (options.abort || options.max_cpu_seconds > 0.0) so.callbacks.push_back(&cb);
    ceres::Solver::Summary s;
    ceres::Solve(so, &problem, &s);
    ok = s.IsSolutionUsable();
    sum.iterations = static_cast<int>(s.iterations.size());
    sum.cpu_budget_hit = cb.cpu_budget_hit;
    sum.time_limit_hit = s.termination_type == ceres::NO_CONVERGENCE && s.message.find("time") != std::string::npos;
    if (ok) {
      for (size_t k = 0; k < kfs->size(); ++k)
        if (!(*kfs)[k].fixed) (*kfs)[k].T_c_w = blockToPose(&poses[7 * k]);
      for (size_t i = 0; i < pts->size(); ++i) (*pts)[i].p_w = Eigen::Map<Eigen::Vector3d>(&points[3 * i]);
    }
    const std::vector<double> e2_final = observationErrors2(cam, *kfs, *pts, obs);
    for (size_t j = 0; j < obs.size(); ++j) {
      const double e2 = e2_final[j], sigma = obs[j].sigma;
      sum.outlier[j] = e2 < 0 || e2 / (sigma * sigma) > options.chi2_threshold;
    }
    sum.final_rmse_px = rmseOfErrors2(e2_final);
    sum.ran = true;
  }
  sum.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return ok;
}

}  // namespace iraf_vo
