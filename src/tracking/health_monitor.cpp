#include "iraf_vo/tracking/health_monitor.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "iraf_vo/common/median.h"

namespace iraf_vo {

namespace {

constexpr size_t kHistory = 5;
constexpr size_t kMinHistory = 3;

double rotationDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

}  // namespace

bool TrackingHealthMonitor::moving(double median_depth) const {
  return !speeds_.empty() &&
         (median(speeds_) > p_.health_min_accel_depth * median_depth || median(rotations_deg_) > 0.1);
}

void TrackingHealthMonitor::accept(const Eigen::Isometry3d& T_w_last, const Eigen::Isometry3d& T_w_c) {
  speeds_.push_back((T_w_c.translation() - T_w_last.translation()).norm());
  rotations_deg_.push_back(rotationDeg(T_w_last.rotation().transpose() * T_w_c.rotation()));
  while (speeds_.size() > kHistory) speeds_.pop_front(), rotations_deg_.pop_front();
}

std::string TrackingHealthMonitor::check(const HealthInput& in) const {
  if (!p_.health_monitor) return "";
  std::ostringstream why;
  const double ratio = in.refine_matches > 0 ? static_cast<double>(in.inliers) / in.refine_matches : 0.0;
  if (ratio < p_.health_min_inlier_ratio) {
    why << "inlier ratio " << ratio << " < " << p_.health_min_inlier_ratio;
    return why.str();
  }
  if (in.median_chi2 > p_.health_max_median_chi2) {
    why << "median reprojection chi2 " << in.median_chi2 << " > " << p_.health_max_median_chi2;
    return why.str();
  }
  if (in.duplicate_of_last && moving(in.median_depth)) return "duplicate of the last frame while moving";
  const double scale_change = std::max(in.ba_scale_change, 1.0 / std::max(1e-9, in.ba_scale_change));
  if (!in.metric_scale && scale_change > p_.health_max_ba_scale_change) {
    why << "local BA changed the map scale by a factor " << in.ba_scale_change;
    return why.str();
  }
  // The motion model needs a few frames to settle (after initialization its velocity is the average over the
  // initialization baseline).
  if (!in.have_motion_model || speeds_.size() < kMinHistory) return "";
  const double floor = p_.health_min_accel_depth * in.median_depth;
  const double deviation = (in.T_w_c.translation() - in.T_w_predicted.translation()).norm();
  const double limit = p_.health_max_accel_ratio * median(speeds_) + floor;
  if (deviation > limit) {
    why << "motion jump: " << deviation << " from the motion model's prediction (limit " << limit << ")";
    return why.str();
  }
  // A camera cannot reverse its direction within one frame at speed (swapped / out-of-order frames).
  const Eigen::Vector3d v_model = in.T_w_predicted.translation() - in.T_w_last.translation();
  const Eigen::Vector3d v_now = in.T_w_c.translation() - in.T_w_last.translation();
  const double reverse_floor = 0.5 * floor;
  if (v_model.norm() > reverse_floor && v_now.norm() > reverse_floor &&
      v_now.dot(v_model) < -0.5 * v_now.norm() * v_model.norm()) {
    why << "motion jump: direction reversed within one frame at speed " << v_now.norm();
    return why.str();
  }
  const double rot_deviation = rotationDeg(in.T_w_predicted.rotation().transpose() * in.T_w_c.rotation());
  const double rot_limit = p_.health_max_rot_accel_deg + p_.health_max_accel_ratio * median(rotations_deg_);
  if (rot_deviation > rot_limit) {
    why << "rotation jump: " << rot_deviation << " deg from the prediction (limit " << rot_limit << " deg)";
    return why.str();
  }
  return "";
}

}  // namespace iraf_vo
