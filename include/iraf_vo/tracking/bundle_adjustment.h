// Bundle adjustment of keyframe poses and points (geometry.h conventions), by the Schur-complement
// Levenberg-Marquardt (schur_lm.h) or ceres::Solve. ROS-free.
#pragma once

#include "iraf_vo/camera/camera_model.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <atomic>
#include <vector>

namespace iraf_vo {

struct BAKeyframe {
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  bool fixed = false;
};
struct BAPoint {
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
};
struct BAObservation {
  int keyframe = 0;  // index into the keyframe vector
  int point = 0;     // index into the point vector
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double sigma = 1.0;  // pixels
  bool right = false;  // seen by the right camera of the keyframe's stereo pair (BAOptions::right_camera)
};
struct BAOptions {
  int max_num_iterations = 10;
  double max_solver_time_in_seconds = 0.2;  // wall clock (grows with the machine's load)
  double max_cpu_seconds = 0.0;  // > 0: stop between iterations after this much CPU time of the calling thread
  double huber_delta = 2.447;          // on the sigma-normalized residual
  double chi2_threshold = 5.991;       // for the outlier flags of the summary
  const std::atomic<bool>* abort = nullptr;  // checked between iterations (new keyframe waiting)
  int num_threads = 1;
  bool dense_schur = true;  // use_ceres: DENSE_SCHUR (fast for <= ~30 poses) or SPARSE_SCHUR
  bool use_ceres = false;   // ceres::Solve instead of the equivalent Schur-complement LM (schur_lm.h)
  const CameraModel* right_camera = nullptr;  // stereo: camera of the `right` observations (Schur LM path only)
  Eigen::Isometry3d T_r_l = Eigen::Isometry3d::Identity();  // stereo: left camera -> right camera
  bool drop_points_behind = true;  // schur_lm: a point a step moves behind a camera leaves the problem where it
                                   // was; false: Ceres' rule (the whole step is invalid)
};
struct BASummary {
  bool ran = false;
  int iterations = 0;           // Ceres iterations incl. iteration 0 (1 = no step taken)
  bool cpu_budget_hit = false;  // stopped by max_cpu_seconds
  bool time_limit_hit = false;  // stopped by max_solver_time_in_seconds (wall clock)
  double initial_rmse_px = 0.0, final_rmse_px = 0.0;
  double initial_cost = 0.0, final_cost = 0.0;  // 0.5 * sum of Huber(sigma-normalized squared error)
  std::vector<char> outlier;  // per observation, chi2 after the solve
  int excluded_points = 0;    // points the solver took out because a step moved them behind a camera
  double ms = 0.0;
};

/// Bundle adjustment of keyframe poses (non-fixed ones) and all points, pixel reprojection residuals through
/// the camera model (analytic Jacobian: CameraModel::project's 2x3 J composed with the pose derivative).
bool bundleAdjust(const CameraModel& cam, std::vector<BAKeyframe>* keyframes, std::vector<BAPoint>* points,
                  const std::vector<BAObservation>& observations, const BAOptions& options, BASummary* summary);

/// Reprojection RMSE (pixels) of a BA problem; observations that do not project count as 1e3 px.
double reprojectionRmse(const CameraModel& cam, const std::vector<BAKeyframe>& keyframes,
                        const std::vector<BAPoint>& points, const std::vector<BAObservation>& observations);

}  // namespace iraf_vo
