// Levenberg-Marquardt bundle adjustment on the Schur complement (schur_lm.h). ROS-free.
//
// Normal equations of the robustified problem (Huber: the residual and its Jacobian weighted by sqrt(rho'), as
// Ceres' corrector does for rho'' <= 0), free poses c (6-dof tangent, left perturbation as PoseManifold) and
// points p:   [U  W; W^T V] [dc; dp] = -[gc; gp],  damped by D / radius on the diagonal.
// Points are eliminated: (U + Dc - W (V + Dp)^-1 W^T) dc = -gc + W (V + Dp)^-1 gp, a dense 6n x 6n Cholesky, then
// dp = (V + Dp)^-1 (-gp - W^T dc). The trust-region logic follows Ceres' TrustRegionMinimizer /
// LevenbergMarquardtStrategy: D = the Jacobian's squared column norms clamped below by 1e-6 in the Jacobi-scaled
// variables (scale 1 / (1 + column norm at the start)), radius 1e4, rho > 1e-3 accepts, accepted:
// radius /= max(1/3, 1 - (2 rho - 1)^3), rejected: radius /= 2, 4, 8, ...; the function and parameter tolerances
// end the solve without taking the step that met them.
#include "schur_lm.h"

#include "ceres_blocks.h"
#include "iraf_vo/tracking/geometry.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace iraf_vo {
namespace schur_lm {

namespace {

using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

class Solver {
 public:
  Solver(const CameraModel& cam, const std::vector<char>& fixed, const std::vector<Residual>& res, size_t num_points,
         const Options& options)
      : cam_(cam), o_(options), res_(res), b_(options.huber_delta) {
    const int np = static_cast<int>(fixed.size());
    free_index_.assign(np, -1);
    for (int k = 0; k < np; ++k)
      if (!fixed[k]) free_index_[k] = nf_++;
    // Residuals grouped by point (CSR, residual order kept inside a point).
    first_.assign(num_points + 1, 0);
    for (const Residual& r : res) ++first_[r.point + 1];
    for (size_t i = 0; i < num_points; ++i) first_[i + 1] += first_[i];
    order_.resize(res.size());
    std::vector<int> fill(first_.begin(), first_.end() - 1);
    for (size_t j = 0; j < res.size(); ++j) order_[fill[res[j].point]++] = static_cast<int>(j);
    // The point-pose blocks of free poses (the reduced system's terms), with their pose's free index: a
    // stereo keyframe's left and right residuals of a point share one block W = sum of their J_c^T J_p, so the
    // Schur complement pairs keyframes, not residuals.
    free_first_.assign(num_points + 1, 0);
    block_of_.assign(res.size(), -1);
    block_first_.assign(res.size(), 0);
    for (size_t i = 0; i < num_points; ++i) {
      free_first_[i + 1] = free_first_[i];
      for (int n = first_[i]; n < first_[i + 1]; ++n) {
        const int j = order_[n];
        const int c = free_index_[res[j].pose];
        if (c < 0) continue;
        int b = free_first_[i];
        while (b < free_first_[i + 1] && free_cam_[b] != c) ++b;
        block_of_[j] = b;
        if (b < free_first_[i + 1]) continue;
        block_first_[j] = 1;
        free_cam_.push_back(c);
        ++free_first_[i + 1];
      }
    }
    U_.resize(nf_);
    gc_.resize(nf_);
    Dc_.resize(nf_);
    minDc_.resize(nf_);
    V_.resize(num_points);
    gp_.resize(num_points);
    Dp_.resize(num_points);
    minDp_.resize(num_points);
    Vinv_.resize(num_points);
    excluded_.assign(num_points, 0);
    W_.resize(free_cam_.size());
    T_.resize(free_cam_.size());
    R_.resize(np);
  }

  int numFree() const { return nf_; }
  bool pointUsed(size_t i) const { return first_[i + 1] > first_[i] && !excluded_[i]; }
  /// Takes point i and its residuals out of the problem (its parameters are no longer changed).
  void excludePoint(int i) { excluded_[static_cast<size_t>(i)] = 1; }
  bool poseFree(size_t k) const { return free_index_[k] >= 0; }

  // Cost 0.5 sum Huber(|r|^2); with `linearize` also the normal equations. False if a residual does not project;
  // with `failed` (not when linearizing) every point with such a residual is listed there and the cost is that of
  // the other points.
  bool evaluate(const double* poses, const double* points, bool linearize, double* cost,
                std::vector<int>* failed = nullptr) {
    for (size_t k = 0; k < R_.size(); ++k) R_[k] = Eigen::Map<const Eigen::Quaterniond>(poses + 7 * k + 3).toRotationMatrix();
    if (linearize) {
      for (int c = 0; c < nf_; ++c) {
        U_[c].setZero();
        gc_[c].setZero();
      }
    }
    const double b2 = b_ * b_;
    double total = 0.0;
    const size_t npts = V_.size();
    for (size_t i = 0; i < npts; ++i) {
      if (!pointUsed(i)) continue;
      const Eigen::Vector3d p = Eigen::Map<const Eigen::Vector3d>(points + 3 * i);
      Eigen::Matrix3d V = Eigen::Matrix3d::Zero();
      Eigen::Vector3d gp = Eigen::Vector3d::Zero();
      for (int n = first_[i]; n < first_[i + 1]; ++n) {
        const int j = order_[n];
        const Residual& r = res_[j];
        const Eigen::Matrix3d& R = R_[r.pose];
        const Eigen::Vector3d Rp = R * p;
        Eigen::Vector3d pc = Rp + Eigen::Map<const Eigen::Vector3d>(poses + 7 * r.pose);
        Eigen::Vector2d uv;
        Eigen::Matrix<double, 2, 3> J;
        const CameraModel& cam = r.right ? *o_.right_camera : cam_;
        if (r.right) pc = o_.R_rl * pc + o_.t_rl;
        if (pc.z() <= 1e-6 || !cam.project(pc, &uv, linearize ? &J : nullptr)) {
          if (!failed || linearize) return false;
          failed->push_back(static_cast<int>(i));
          break;
        }
        if (r.right && linearize) J = J * o_.R_rl;  // d pi_r / d (the left camera's point)
        const Eigen::Vector2d e = (uv - r.uv) * r.inv_sigma;
        const double s = e.squaredNorm();
        double w = 1.0;
        if (s > b2) {
          const double norm = std::sqrt(s);
          total += 2.0 * b_ * norm - b2;
          w = b_ / norm;
        } else {
          total += s;
        }
        if (!linearize) continue;
        J *= r.inv_sigma;
        const Eigen::Matrix<double, 2, 3> Jp = J * R;
        const Eigen::Matrix<double, 3, 2> wJpT = w * Jp.transpose();
        V.noalias() += wJpT * Jp;
        gp.noalias() += wJpT * e;
        const int c = free_index_[r.pose];
        if (c < 0) continue;
        Eigen::Matrix<double, 2, 6> Jc;
        Jc.leftCols<3>() = J;
        Jc.rightCols<3>().noalias() = -J * skew(Rp);
        const Eigen::Matrix<double, 6, 2> wJcT = w * Jc.transpose();
        U_[c].noalias() += wJcT * Jc;
        gc_[c].noalias() += wJcT * e;
        if (block_first_[j]) W_[block_of_[j]].noalias() = wJcT * Jp;
        else W_[block_of_[j]].noalias() += wJcT * Jp;
      }
      if (linearize) {
        V_[i] = V;
        gp_[i] = gp;
      }
    }
    *cost = 0.5 * total;
    return !failed || failed->empty();
  }

  // Jacobi scaling of the first linearization: the damping's lower clamp 1e-6 in the scaled variables.
  void setScaling() {
    for (int c = 0; c < nf_; ++c)
      for (int a = 0; a < 6; ++a) minDc_[c][a] = 1e-6 * std::pow(1.0 + std::sqrt(U_[c](a, a)), 2);
    for (size_t i = 0; i < V_.size(); ++i)
      for (int a = 0; a < 3; ++a) minDp_[i][a] = 1e-6 * std::pow(1.0 + std::sqrt(V_[i](a, a)), 2);
  }

  double gradientMaxNorm() const {
    double m = 0.0;
    for (const Vec6& g : gc_) m = std::max(m, g.cwiseAbs().maxCoeff());
    for (size_t i = 0; i < gp_.size(); ++i)
      if (pointUsed(i)) m = std::max(m, gp_[i].cwiseAbs().maxCoeff());
    return m;
  }

  // The damped step; false when the reduced system is not positive definite. *model = predicted cost decrease.
  bool step(double radius, std::vector<Vec6>* dc, std::vector<Eigen::Vector3d>* dp, double* model) {
    const int n = 6 * nf_;
    S_.setZero(n, n);
    bc_.setZero(n);
    for (int c = 0; c < nf_; ++c) {
      Dc_[c] = U_[c].diagonal().cwiseMax(minDc_[c]) / radius;
      S_.block<6, 6>(6 * c, 6 * c) = U_[c];
      S_.block<6, 6>(6 * c, 6 * c).diagonal() += Dc_[c];
      bc_.segment<6>(6 * c) = -gc_[c];
    }
    for (size_t i = 0; i < V_.size(); ++i) {
      if (!pointUsed(i)) continue;
      Dp_[i] = V_[i].diagonal().cwiseMax(minDp_[i]) / radius;
      Eigen::Matrix3d Vd = V_[i];
      Vd.diagonal() += Dp_[i];
      double det;
      bool invertible;
      Vd.computeInverseAndDetWithCheck(Vinv_[i], det, invertible, 0.0);
      if (!invertible || !(det > 0.0)) return false;
      // Upper block triangle of the reduced system: pair (a, b) adds T_a W_b^T to block (pose a, pose b).
      for (int a = free_first_[i]; a < free_first_[i + 1]; ++a) {
        const int ca = free_cam_[a];
        T_[a].noalias() = W_[a] * Vinv_[i];
        bc_.segment<6>(6 * ca).noalias() += T_[a] * gp_[i];
        for (int b = free_first_[i]; b <= a; ++b) {
          const int cb = free_cam_[b];
          // T_b exists (b <= a): T_a W_b^T = W_a Vinv W_b^T = (T_b W_a^T)^T.
          if (ca < cb) {
            S_.block<6, 6>(6 * ca, 6 * cb).noalias() -= T_[a] * W_[b].transpose();
          } else if (cb < ca) {
            S_.block<6, 6>(6 * cb, 6 * ca).noalias() -= T_[b] * W_[a].transpose();
          } else {  // a == b: one block per pose and point
            const Mat6 B = T_[a] * W_[a].transpose();
            S_.block<6, 6>(6 * ca, 6 * ca) -= B;
          }
        }
      }
    }
    Eigen::VectorXd x;
    if (n > 0) {
      Eigen::LLT<Eigen::MatrixXd, Eigen::Upper> llt(S_);
      if (llt.info() != Eigen::Success) return false;
      x = llt.solve(bc_);
      if (!x.allFinite()) return false;
    }
    double g_dx = 0.0, dDd = 0.0;
    dc->resize(nf_);
    for (int c = 0; c < nf_; ++c) {
      (*dc)[c] = x.segment<6>(6 * c);
      g_dx += gc_[c].dot((*dc)[c]);
      dDd += (*dc)[c].cwiseAbs2().dot(Dc_[c]);
    }
    dp->resize(V_.size());
    for (size_t i = 0; i < V_.size(); ++i) {
      if (!pointUsed(i)) continue;
      Eigen::Vector3d rhs = -gp_[i];
      for (int b = free_first_[i]; b < free_first_[i + 1]; ++b) rhs.noalias() -= W_[b].transpose() * (*dc)[free_cam_[b]];
      (*dp)[i] = Vinv_[i] * rhs;
      g_dx += gp_[i].dot((*dp)[i]);
      dDd += (*dp)[i].cwiseAbs2().dot(Dp_[i]);
    }
    // (H + D) dx = -g  =>  model decrease -g.dx - dx.H.dx / 2 = (-g.dx + dx.D.dx) / 2.
    *model = 0.5 * (-g_dx + dDd);
    return std::isfinite(*model);
  }

 private:
  const CameraModel& cam_;
  const Options& o_;
  const std::vector<Residual>& res_;
  double b_;
  int nf_ = 0;
  std::vector<int> free_index_, first_, order_;
  std::vector<int> free_first_, free_cam_;  // point i's blocks: [free_first_[i], free_first_[i + 1])
  std::vector<int> block_of_;               // residual -> its block (-1: fixed pose)
  std::vector<char> block_first_;           // the residual sets its block's W (the others add to it)
  std::vector<Mat6> U_;
  std::vector<Vec6> gc_, Dc_, minDc_;
  std::vector<Eigen::Matrix3d> V_, Vinv_, R_;
  std::vector<Eigen::Vector3d> gp_, Dp_, minDp_;
  std::vector<Mat63> W_, T_;
  std::vector<char> excluded_;
  Eigen::MatrixXd S_;
  Eigen::VectorXd bc_;
};

}  // namespace

bool solve(const CameraModel& cam, std::vector<double>* poses, const std::vector<char>& fixed,
           std::vector<double>* points, const std::vector<Residual>& residuals, const Options& o, Summary* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  Summary& sum = *summary;
  sum = Summary();
  const size_t num_points = points->size() / 3;
  Solver solver(cam, fixed, residuals, num_points, o);
  double cost;
  if (!solver.evaluate(poses->data(), points->data(), true, &cost)) return false;
  solver.setScaling();
  sum.initial_cost = sum.final_cost = cost;
  sum.iterations = 1;
  // |x| over the free parameters (ambient), as Ceres' reduced program.
  auto freeNorm2 = [&](const std::vector<double>& ps, const std::vector<double>& xs) {
    double s = 0.0;
    for (size_t k = 0; k < fixed.size(); ++k)
      if (solver.poseFree(k)) s += Eigen::Map<const Eigen::Matrix<double, 7, 1>>(&ps[7 * k]).squaredNorm();
    for (size_t i = 0; i < num_points; ++i)
      if (solver.pointUsed(i)) s += Eigen::Map<const Eigen::Vector3d>(&xs[3 * i]).squaredNorm();
    return s;
  };
  double x_norm = std::sqrt(freeNorm2(*poses, *points));
  double radius = o.initial_trust_region_radius, decrease_factor = 2.0;
  int invalid_steps = 0;
  const ceres_blocks::PoseManifold manifold;
  std::vector<Vec6> dc;
  std::vector<Eigen::Vector3d> dp;
  std::vector<double> cand_poses(*poses), cand_points(*points);
  for (;;) {
    // After every iteration (Ceres' order): callbacks, time, iterations, gradient, radius.
    if (o.stop && o.stop()) {
      sum.termination = Termination::kStopped;
      break;
    }
    if (o.max_wall_seconds > 0.0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > o.max_wall_seconds) {
      sum.termination = Termination::kTimeLimit;
      break;
    }
    if (sum.iterations - 1 >= o.max_num_iterations) {
      sum.termination = Termination::kMaxIterations;
      break;
    }
    if (solver.gradientMaxNorm() <= o.gradient_tolerance || radius <= 1e-32) {
      sum.termination = Termination::kConvergence;
      break;
    }
    ++sum.iterations;
    double model = 0.0;
    if (!solver.step(radius, &dc, &dp, &model) || !(model > 0.0)) {
      if (++invalid_steps >= 5) {
        sum.termination = Termination::kFailure;
        break;
      }
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      continue;
    }
    invalid_steps = 0;
    double step2 = 0.0;
    {
      int c = 0;
      for (size_t k = 0; k < fixed.size(); ++k) {
        if (!solver.poseFree(k)) continue;
        manifold.Plus(&(*poses)[7 * k], dc[c++].data(), &cand_poses[7 * k]);
        step2 += (Eigen::Map<const Eigen::Matrix<double, 7, 1>>(&cand_poses[7 * k]) -
                  Eigen::Map<const Eigen::Matrix<double, 7, 1>>(&(*poses)[7 * k]))
                     .squaredNorm();
      }
      for (size_t i = 0; i < num_points; ++i) {
        if (!solver.pointUsed(i)) continue;
        (Eigen::Map<Eigen::Vector3d>(&cand_points[3 * i])) = Eigen::Map<const Eigen::Vector3d>(&(*points)[3 * i]) + dp[i];
        step2 += dp[i].squaredNorm();
      }
    }
    double cand_cost;
    std::vector<int> behind;
    const bool valid =
        solver.evaluate(cand_poses.data(), cand_points.data(), false, &cand_cost, o.drop_points_behind ? &behind : nullptr);
    if (!valid && !behind.empty()) {
      // The step moved points behind a camera (or out of its field of view): as ORB-SLAM's local BA drops edges of
      // negative depth, those points leave the problem where they are (their last valid position; the outlier flags
      // after the solve follow the chi2 test as for every point) and the iteration continues from the current
      // parameters and trust region with the rest. (Ceres' rule, the whole step invalid and the radius halved, let
      // one such point - far away, its depth ill-defined - spend the iterations of a fisheye window: 52 of 89 local
      // BAs of sim_clean_fisheye ended at the iteration limit, 7 of 92 on EuRoC.)
      for (int i : behind) solver.excludePoint(i);
      sum.excluded_points += static_cast<int>(behind.size());
      cand_poses = *poses;
      cand_points = *points;
      if (!solver.evaluate(poses->data(), points->data(), true, &cost)) {
        sum.termination = Termination::kFailure;
        break;
      }
      x_norm = std::sqrt(freeNorm2(*poses, *points));
      continue;
    }
    if (!valid) cand_cost = std::numeric_limits<double>::max();
    if (std::sqrt(step2) <= o.parameter_tolerance * (x_norm + o.parameter_tolerance) ||
        std::abs(cost - cand_cost) <= o.function_tolerance * cost) {
      --sum.iterations;  // as Ceres: the step that met a tolerance is neither taken nor counted
      sum.termination = Termination::kConvergence;
      break;
    }
    const double rho = (cost - cand_cost) / model;
    if (rho > 1e-3) {
      poses->swap(cand_poses);
      points->swap(cand_points);
      cand_poses = *poses;
      cand_points = *points;
      cost = cand_cost;
      x_norm = std::sqrt(freeNorm2(*poses, *points));
      ++sum.successful_steps;
      double c2;
      if (!solver.evaluate(poses->data(), points->data(), true, &c2)) {
        sum.termination = Termination::kFailure;
        break;
      }
      radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
      decrease_factor = 2.0;
    } else {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
    }
  }
  sum.final_cost = cost;
  return sum.usable();
}

}  // namespace schur_lm
}  // namespace iraf_vo
