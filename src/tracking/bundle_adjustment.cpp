// Bundle adjustment (bundle_adjustment.h): the Schur-complement LM (schur_lm.h) or ceres::Solve. ROS-free.
#include "iraf_vo/tracking/bundle_adjustment.h"

#include "ceres_blocks.h"
#include "iraf_vo/tracking/multiview.h"
#include "schur_lm.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <deque>
#include <memory>

namespace iraf_vo {

using ceres_blocks::blockToPose;
using ceres_blocks::PoseManifold;
using ceres_blocks::poseToBlock;
using ceres_blocks::ReprojectionCost;

namespace {

// Sanitizer builds (ASan, TSan; GCC's macros, clang's __has_feature) run the solver several times slower than the
// code they check. The time budgets grow by as much, so that they stop a solve where the uninstrumented build does
// (BA's 0.1 s budget was hit in one of two identical runs under ASan on a slow machine, and their poses differed).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define IRAF_VO_INSTRUMENTED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define IRAF_VO_INSTRUMENTED 1
#endif
#endif
#ifdef IRAF_VO_INSTRUMENTED
constexpr double kInstrumentedSlowdown = 10.0;
#else
constexpr double kInstrumentedSlowdown = 1.0;
#endif

// The options a solver runs with: the time budgets scaled by kInstrumentedSlowdown.
BAOptions withInstrumentedBudgets(BAOptions options) {
  options.max_cpu_seconds *= kInstrumentedSlowdown;
  options.max_solver_time_in_seconds *= kInstrumentedSlowdown;
  return options;
}

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

// Squared pixel error of every observation, -1 where the point does not project (reprojectionError2).
std::vector<double> observationErrors2(const CameraModel& cam, const std::vector<BAKeyframe>& kfs,
                                       const std::vector<BAPoint>& pts, const std::vector<BAObservation>& obs,
                                       const BAOptions* stereo = nullptr) {
  std::vector<double> e2(obs.size());
  for (size_t j = 0; j < obs.size(); ++j) {
    if (obs[j].right) {  // a right observation without a right camera does not project
      e2[j] = stereo && stereo->right_camera
                  ? reprojectionError2(*stereo->right_camera, stereo->T_r_l * kfs[obs[j].keyframe].T_c_w,
                                       pts[obs[j].point].p_w, obs[j].uv)
                  : -1.0;
      continue;
    }
    e2[j] = reprojectionError2(cam, kfs[obs[j].keyframe].T_c_w, pts[obs[j].point].p_w, obs[j].uv);
  }
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

namespace {

// The Ceres path (BAOptions::use_ceres): TRUST_REGION / LEVENBERG_MARQUARDT / DENSE_SCHUR, explicit Schur ordering.
// valid[j]: observation j enters the problem. Returns Summary::IsSolutionUsable().
bool solveWithCeres(const CameraModel& cam, const std::vector<BAKeyframe>& kfs, size_t num_points,
                    const std::vector<BAObservation>& obs, const std::vector<char>& valid, const BAOptions& options,
                    std::vector<double>* poses, std::vector<double>* points, BASummary* sum) {
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
  std::vector<char> pose_added(kfs.size(), 0);
  for (size_t j = 0; j < obs.size(); ++j) {
    if (!valid[j]) continue;
    const auto& o = obs[j];
    double* pb = &(*poses)[7 * o.keyframe];
    if (!pose_added[o.keyframe]) {
      problem.AddParameterBlock(pb, 7, &manifold);
      if (kfs[o.keyframe].fixed) problem.SetParameterBlockConstant(pb);
      pose_added[o.keyframe] = 1;
    }
    costs.emplace_back(&cam, o.uv, o.sigma);
    problem.AddResidualBlock(&costs.back(), loss, pb, &(*points)[3 * o.point]);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = options.dense_schur ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  // Explicit Schur ordering (points eliminated first) saves Ceres' independent-set search.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (size_t i = 0; i < num_points; ++i)
    if (problem.HasParameterBlock(&(*points)[3 * i])) ordering->AddElementToGroup(&(*points)[3 * i], 0);
  for (size_t k = 0; k < kfs.size(); ++k)
    if (pose_added[k]) ordering->AddElementToGroup(&(*poses)[7 * k], 1);
  so.linear_solver_ordering = ordering;
  so.max_num_iterations = options.max_num_iterations;
  so.max_solver_time_in_seconds = options.max_solver_time_in_seconds;
  so.num_threads = std::max(1, options.num_threads);
  so.logging_type = ceres::SILENT;
  AbortCallback cb(options.abort, options.max_cpu_seconds);
  if (options.abort || options.max_cpu_seconds > 0.0) so.callbacks.push_back(&cb);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);
  sum->iterations = static_cast<int>(s.iterations.size());
  sum->cpu_budget_hit = cb.cpu_budget_hit;
  sum->time_limit_hit = s.termination_type == ceres::NO_CONVERGENCE && s.message.find("time") != std::string::npos;
  sum->initial_cost = s.initial_cost;
  sum->final_cost = s.final_cost;
  return s.IsSolutionUsable();
}

// The default path: schur_lm.h (the same algorithm without Ceres' per-residual overhead).
bool solveWithSchurLM(const CameraModel& cam, const std::vector<BAKeyframe>& kfs, const std::vector<BAObservation>& obs,
                      const std::vector<char>& valid, const BAOptions& options, std::vector<double>* poses,
                      std::vector<double>* points, BASummary* sum) {
  std::vector<schur_lm::Residual> res;
  res.reserve(obs.size());
  for (size_t j = 0; j < obs.size(); ++j)
    if (valid[j]) res.push_back({obs[j].keyframe, obs[j].point, obs[j].uv, 1.0 / obs[j].sigma, obs[j].right});
  std::vector<char> fixed(kfs.size());
  for (size_t k = 0; k < kfs.size(); ++k) fixed[k] = kfs[k].fixed;
  schur_lm::Options so;
  so.max_num_iterations = options.max_num_iterations;
  so.huber_delta = options.huber_delta;
  so.max_wall_seconds = options.max_solver_time_in_seconds;
  so.drop_points_behind = options.drop_points_behind;
  so.right_camera = options.right_camera;
  so.R_rl = options.T_r_l.linear();
  so.t_rl = options.T_r_l.translation();
  AbortCallback cb(options.abort, options.max_cpu_seconds);
  if (options.abort || options.max_cpu_seconds > 0.0)
    so.stop = [&cb] { return cb(ceres::IterationSummary()) != ceres::SOLVER_CONTINUE; };
  schur_lm::Summary s;
  const bool ok = schur_lm::solve(cam, poses, fixed, points, res, so, &s);
  sum->iterations = s.iterations;
  sum->cpu_budget_hit = cb.cpu_budget_hit;
  sum->time_limit_hit = s.termination == schur_lm::Termination::kTimeLimit;
  sum->initial_cost = s.initial_cost;
  sum->final_cost = s.final_cost;
  sum->excluded_points = s.excluded_points;
  return ok;
}

}  // namespace

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
  // Errors before the solve: which observations project, and the initial RMSE (the same values).
  const std::vector<double> e2_initial = observationErrors2(cam, *kfs, *pts, obs, &options);
  std::vector<char> valid(obs.size());
  int n_res = 0;
  for (size_t j = 0; j < obs.size(); ++j) {
    valid[j] = e2_initial[j] >= 0;
    sum.outlier[j] = !valid[j];
    n_res += valid[j];
  }
  bool ok = false;
  if (n_res > 0) {
    sum.initial_rmse_px = rmseOfErrors2(e2_initial);
    // Right-camera observations: the Schur LM path (the Ceres cost has one camera).
    const bool ceres = options.use_ceres && !options.right_camera;
    const BAOptions solve_options = withInstrumentedBudgets(options);
    ok = ceres ? solveWithCeres(cam, *kfs, pts->size(), obs, valid, solve_options, &poses, &points, &sum)
               : solveWithSchurLM(cam, *kfs, obs, valid, solve_options, &poses, &points, &sum);
    if (ok) {
      for (size_t k = 0; k < kfs->size(); ++k)
        if (!(*kfs)[k].fixed) (*kfs)[k].T_c_w = blockToPose(&poses[7 * k]);
      for (size_t i = 0; i < pts->size(); ++i) (*pts)[i].p_w = Eigen::Map<Eigen::Vector3d>(&points[3 * i]);
    }
    const std::vector<double> e2_final = observationErrors2(cam, *kfs, *pts, obs, &options);
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
