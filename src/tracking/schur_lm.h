// Bundle adjustment by Levenberg-Marquardt on the Schur complement (points eliminated, dense reduced camera system).
// Internal to src/tracking (bundle_adjustment.cpp: bundleAdjust). The same algorithm as the Ceres configuration it replaces
// (TRUST_REGION, LEVENBERG_MARQUARDT, DENSE_SCHUR, Jacobi scaling, Huber loss, default tolerances and trust-region
// updates), without Ceres' per-residual cost-function calls, block bookkeeping and problem preprocessing: the
// rotation of every pose is formed once per evaluation, the Jacobians of a residual go straight into the normal
// equations. ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace iraf_vo {
namespace schur_lm {

/// r = (pi(R p_w + t) - uv) * inv_sigma, pose block `pose` (7 doubles, ceres_blocks layout [t q]), point `point`.
struct Residual {
  int pose = 0;
  int point = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double inv_sigma = 1.0;
  bool right = false;  // observed by the right camera of a stereo rig: pi_r(R_rl (R p_w + t) + t_rl) (Options)
};

struct Options {
  int max_num_iterations = 10;     // steps taken or rejected (Ceres' max_num_iterations)
  double huber_delta = 2.447;      // on the sigma-normalized residual
  double function_tolerance = 1e-6;   // |cost change| <= tol * cost -> converged (Ceres defaults)
  double parameter_tolerance = 1e-8;  // |step| <= tol * (|x| + tol) -> converged
  double gradient_tolerance = 1e-10;  // max |gradient| <= tol -> converged
  double initial_trust_region_radius = 1e4;
  double max_wall_seconds = 0.0;      // > 0: stop after this much wall time
  bool drop_points_behind = true;     // a point a step moves behind a camera leaves the problem; false: Ceres' rule
  std::function<bool()> stop;         // asked after every iteration (incl. the initial evaluation): true = stop
  const CameraModel* right_camera = nullptr;  // stereo: the camera of the `right` residuals
  Eigen::Matrix3d R_rl = Eigen::Matrix3d::Identity();  // stereo: left camera -> right camera
  Eigen::Vector3d t_rl = Eigen::Vector3d::Zero();
};

enum class Termination { kConvergence, kMaxIterations, kStopped, kTimeLimit, kFailure };

struct Summary {
  int iterations = 0;        // incl. the initial evaluation, as ceres::Solver::Summary::iterations.size()
  int successful_steps = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // 0.5 * sum of Huber(r^2)
  Termination termination = Termination::kFailure;
  int excluded_points = 0;      // points taken out of the problem because a step moved them behind a camera
                                // (their parameters are those before that step)
  bool usable() const { return termination != Termination::kFailure; }
};

/// Minimizes over the poses with fixed[k] == 0 and every point that has a residual. Every residual must project
/// at the start (the caller drops the others). A point that a step moves behind a camera leaves the problem
/// (Summary::excluded_points). Returns Summary::usable(); the parameters hold the best point found (the start when nothing
/// was accepted).
bool solve(const CameraModel& cam, std::vector<double>* poses, const std::vector<char>& fixed,
           std::vector<double>* points, const std::vector<Residual>& residuals, const Options& options,
           Summary* summary);

}  // namespace schur_lm
}  // namespace iraf_vo
