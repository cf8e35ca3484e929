// Two-view geometry, triangulation, PnP and Ceres pose / bundle-adjustment building blocks of the
// monocular tracker. Everything works on unit bearing vectors (CameraModel::unproject) or on pixels
// through CameraModel::project (with its 2x3 Jacobian), so pinhole-radtan and Kannala-Brandt both work.
// ROS-free.
//
// Conventions: T_c_w maps world points into the camera (REP-103 optical frame, z forward);
// the published pose is T_w_c = T_c_w^-1. Pixel noise of a keypoint at pyramid level o is
// sigma = scale_factor^o (pixels); chi2 gates use 2 dof (5.991 at 95 %).
#pragma once

#include <iraf_vo/camera/camera_model.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <string>
#include <vector>

namespace iraf_vo {

/// Cross-product matrix: skew(v) x = v.cross(x).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// One observation's Gauss-Newton terms of 6-dof pose normal equations: the lower triangle (j <= i) of *H gets
/// w Jp^T Jp and *g gets w Jp^T r, every entry rounded exactly as by Eigen's `H.noalias() += w * Jp.transpose() * Jp`
/// (w Jp(k, i) first). The strict upper triangle is not touched (copyLowerToUpper after the last observation).
inline void addWeightedNormalEquations(const Eigen::Matrix<double, 2, 6>& Jp, const Eigen::Vector2d& r, double w,
                                       Eigen::Matrix<double, 6, 6>* H, Eigen::Matrix<double, 6, 1>* g) {
  for (int i = 0; i < 6; ++i) {
    const double wa = w * Jp(0, i), wb = w * Jp(1, i);
    for (int j = 0; j <= i; ++j) (*H)(i, j) += wa * Jp(0, j) + wb * Jp(1, j);
    (*g)(i) += wa * r(0) + wb * r(1);
  }
}

/// H(i, j) = H(j, i) for j > i.
inline void copyLowerToUpper(Eigen::Matrix<double, 6, 6>* H) {
  for (int j = 1; j < 6; ++j)
    for (int i = 0; i < j; ++i) (*H)(i, j) = (*H)(j, i);
}

/// Linear (DLT on bearings, [b]x P X = 0) triangulation of a point seen as bearing b1 from T1_c_w and
/// b2 from T2_c_w. Returns false when the system is degenerate (point at infinity).
bool triangulateBearings(const Eigen::Isometry3d& T1_c_w, const Eigen::Vector3d& b1,
                         const Eigen::Isometry3d& T2_c_w, const Eigen::Vector3d& b2, Eigen::Vector3d* p_w);

/// Parallax angle (radians) at p_w between the two camera centres.
double parallaxAngle(const Eigen::Isometry3d& T1_c_w, const Eigen::Isometry3d& T2_c_w, const Eigen::Vector3d& p_w);

/// Squared pixel reprojection error of p_w in a camera; < 0 when the point does not project.
double reprojectionError2(const CameraModel& cam, const Eigen::Isometry3d& T_c_w, const Eigen::Vector3d& p_w,
                          const Eigen::Vector2d& uv);

// ---------------------------------------------------------------------------------------------
// Two-view initialization
// ---------------------------------------------------------------------------------------------
struct TwoViewParams {
  double threshold_px = 1.5;       // RANSAC / scoring inlier threshold (pixels at level 0; converted with focal)
  double min_parallax_deg = 1.0;   // parallax test: at least min_parallax_points triangulated points (all if
  int min_parallax_points = 50;    // fewer) have this parallax (ORB-SLAM); min_parallax_points 0 = the median
  double min_median_parallax_deg = 0.5;  // and the median point has this parallax. A homography's median point
                                         // needs min_parallax_deg.
  int min_triangulated = 50;
  double homography_ratio = 0.45;  // R_H = S_H / (S_H + S_F) above this -> homography (ORB-SLAM)
  double model_fallback_margin = 0.1;  // |R_H - homography_ratio| below this and the chosen model fails its
                                       // checks -> the other model is tried (0 = never)
  // Essential-matrix motions: refused while a translation direction >= ambiguity_angle_deg away explains the
  // matches about as well (profile chi2 < ambiguity_max_chi2, two_view_ambiguity.h); 0 = no check.
  double ambiguity_max_chi2 = 9.21;
  double ambiguity_angle_deg = 20.0;
  bool ba_use_ceres = false;  // the motion refinement's BAOptions::use_ceres (TrackerParams::ba_use_ceres)
};

struct TwoViewResult {
  bool ok = false;
  std::string model;               // "homography" or "essential"
  std::string reason;              // why it failed ("" when ok)
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();  // x2 = R_21 x1 + t_21
  Eigen::Vector3d t_21 = Eigen::Vector3d::Zero();      // unit norm
  std::vector<Eigen::Vector3d> points;  // per match, in frame-1 coordinates (valid where triangulated)
  std::vector<char> triangulated;       // per match
  int num_triangulated = 0;
  double median_parallax_deg = 0.0;
  double parallax_deg = 0.0;       // the tested parallax (min_parallax_points-th largest, or the median)
  double score_h = 0.0, score_f = 0.0;
  double translation_profile_chi2 = -1.0;  // the ambiguity check's value (-1: not run)
};

/// Relative pose + structure from matched bearings (b1[i] <-> b2[i]). Uses cv::findEssentialMat and
/// cv::findHomography on normalized coordinates, ORB-SLAM symmetric-transfer scores for model selection,
/// then triangulation with cheirality, reprojection (threshold_px, via `focal`) and parallax checks.
TwoViewResult initializeTwoView(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                double focal, const TwoViewParams& params);

// ---------------------------------------------------------------------------------------------
// PnP
// ---------------------------------------------------------------------------------------------
/// cv::solvePnPRansac (AP3P minimal solver) on normalized coordinates of the bearings, threshold in pixels.
/// Returns the number of inliers (0 on failure); *T_c_w is written only on success.
int solvePnPBearings(const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector3d>& bearings,
                     double focal, double threshold_px, int iterations, Eigen::Isometry3d* T_c_w,
                     std::vector<char>* inliers = nullptr);

// ---------------------------------------------------------------------------------------------
// Ceres: pose-only refinement and sliding-window bundle adjustment
// ---------------------------------------------------------------------------------------------
struct PoseOptimizationOptions {
  int rounds = 3;                  // solve -> classify outliers (chi2) -> solve again
  int max_num_iterations = 10;     // per round
  double chi2_threshold = 5.991;   // 2 dof, 95 %
  double huber_delta = 2.447;      // sqrt(5.991), on the sigma-normalized residual
  /// false: Levenberg-Marquardt on the 6x6 normal equations (same residual / Jacobian, ~10x faster than
  /// building a ceres::Problem per frame); true: ceres::Solve with PoseOnlyCost + Huber.
  bool use_ceres = false;
};

/// Pose-only refinement of T_c_w from 3D points and their observed pixels (sigma per observation).
/// `inlier` (in/out, same size) marks which observations are used; updated by the chi2 test of each round.
/// Returns the number of inliers after the last round.
int optimizePose(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<double>& sigma, const PoseOptimizationOptions& options, Eigen::Isometry3d* T_c_w,
                 std::vector<char>* inlier);

/// Information matrix (J^T J of the sigma-normalized residuals) of T_c_w in its left-perturbation tangent
/// [dt, dtheta] (t' = t + dt, R' = Exp(dtheta) R) over the given observations.
Eigen::Matrix<double, 6, 6> poseInformation(const CameraModel& cam, const std::vector<Eigen::Vector3d>& p_w,
                                            const std::vector<Eigen::Vector2d>& uv, const std::vector<double>& sigma,
                                            const Eigen::Isometry3d& T_c_w);

/// Covariance of the camera pose T_w_c = T_c_w^-1 in the world frame, [x y z rx ry rz] (position, then a small
/// rotation about the world axes), from the information matrix of T_c_w (poseInformation).
Eigen::Matrix<double, 6, 6> worldPoseCovariance(const Eigen::Matrix<double, 6, 6>& information,
                                                const Eigen::Isometry3d& T_c_w);

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
