// Trajectory evaluation (ROS-free): timestamp association, Umeyama alignment (SE(3) / Sim(3)),
// ATE and RPE statistics, per-pose error CSV and a JSON / text summary.
// Conventions follow evo (https://github.com/MichaelGrupp/evo): the ESTIMATE is aligned onto the GROUND TRUTH,
// ATE = RMSE of || p_gt_i - S(p_est_i) || (evo_ape --pose_relation trans_part, -a / -as),
// RPE over pairs (i, j): E = (G_i^-1 G_j)^-1 (A_i^-1 A_j) with A = aligned estimate; trans = |t(E)|,
// rot = angle(E) in degrees (evo_rpe trans_part / angle_deg).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "iraf_vo/io/trajectory.h"

namespace iraf_vo {

enum class AlignMode { kNone, kSE3, kSim3 };
/// "none" | "se3" | "sim3" (case-insensitive). false for anything else.
bool parseAlignMode(const std::string& s, AlignMode* mode);
const char* alignModeName(AlignMode mode);

/// Similarity transform x -> s R x + t.
struct Sim3 {
  double s = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return s * R * x + t; }
  /// Applies to a pose: rotation R * R_p, position s R p + t (the pose stays a rigid transform).
  Eigen::Isometry3d apply(const Eigen::Isometry3d& T) const;
  Sim3 inverse() const;
  Eigen::Matrix4d matrix() const;
};

/// One-to-one nearest-neighbour association: pairs (gt index, est index) with |t_gt - t_est| <= max_dt,
/// chosen greedily by increasing |dt| (as TUM's associate.py). Inputs must be sorted; output sorted by gt index.
std::vector<std::pair<size_t, size_t>> associate(const std::vector<double>& t_gt, const std::vector<double>& t_est,
                                                 double max_dt);

/// Umeyama (Eigen::umeyama): S minimizing sum_i |gt_i - S(est_i)|^2. kSE3 fixes s = 1, kNone gives identity.
/// Needs >= 3 points (>= 1 for kNone) and non-degenerate (not all identical) points; false + *error otherwise.
bool alignUmeyama(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt, AlignMode mode,
                  Sim3* S, std::string* error);

struct ErrorStats {
  size_t n = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
};
ErrorStats computeStats(const std::vector<double>& errors);

struct EvalParams {
  AlignMode align = AlignMode::kSim3;  ///< Sim(3) is the monocular default
  double max_dt = 0.02;                ///< association tolerance [s]
  double rpe_delta = 1.0;              ///< RPE step: seconds, or frames when rpe_delta_frames
  bool rpe_delta_frames = false;
};

struct PoseError {
  double stamp = 0;               ///< GT stamp [s]
  double error = 0;               ///< |p_gt - S(p_est)| [m]
  Eigen::Vector3d est_aligned;    ///< S(p_est)
  Eigen::Vector3d gt;             ///< p_gt
};

struct EvalResult {
  size_t n_gt = 0, n_est = 0, n_matched = 0;
  double coverage = 0;  ///< n_matched / n_gt: fraction of GT poses with an estimate
  Sim3 alignment;       ///< estimate -> GT
  double scale = 1;     ///< alignment.s
  double gt_length = 0; ///< path length of the matched GT [m]
  ErrorStats ate;       ///< translation [m]
  /// Metric view, whatever the mode (both from the same matched positions; valid when metric_valid):
  /// the ATE RMSE after SE(3) alignment (scale fixed 1) and the scale Sim(3) alignment finds (1 = metric).
  bool metric_valid = false;
  double se3_ate_rmse = 0;
  double sim3_scale = 1;
  double sim3_ate_rmse = 0;
  ErrorStats rpe_trans; ///< [m] per delta
  ErrorStats rpe_rot;   ///< [deg] per delta
  std::vector<PoseError> per_pose;
};

/// Associates, aligns and computes ATE / RPE. false + *error when too few poses match (< 3, or < 1 for kNone)
/// or the alignment is degenerate.
bool evaluateTrajectory(const Trajectory& gt, const Trajectory& est, const EvalParams& params, EvalResult* result,
                        std::string* error);

/// The ATE of each map of a run that reset its map (a new map, a new scale and frame): the maps begin at the
/// stamps `map_starts` (increasing; poses before the first start belong to the first map), each map's poses are
/// aligned on their own with `params`; a map with too few poses gives n_matched 0.
std::vector<EvalResult> evaluatePerMap(const Trajectory& gt, const Trajectory& est, const std::vector<double>& map_starts,
                                       const EvalParams& params);

/// CSV "t,error,est_x,est_y,est_z,gt_x,gt_y,gt_z" (aligned estimate), one row per matched pose.
bool writeErrorsCsv(const std::string& path, const EvalResult& result, std::string* error);
/// Human-readable multi-line summary.
std::string formatSummary(const EvalResult& result, const EvalParams& params);
/// JSON object with the same numbers.
std::string toJson(const EvalResult& result, const EvalParams& params);

}  // namespace iraf_vo
