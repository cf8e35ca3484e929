#include <iraf_vo/tracking/health_monitor.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace iraf_vo {

namespace {

constexpr size_t kHistory = 6;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double rotationDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

// Per-frame motion between consecutive poses: centre displacement (world) and rotation (camera frame).
Eigen::Vector3d step(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return b.translation() - a.translation(); }
Eigen::Matrix3d turn(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return a.rotation().transpose() * b.rotation(); }

}  // namespace

double TrackingHealthMonitor::medianSpeed() const {
  std::vector<double> s;
  for (size_t i = 1; i < poses_.size(); ++i) s.push_back(step(poses_[i - 1], poses_[i]).norm());
  return median(s);
}

double TrackingHealthMonitor::medianRotationDeg() const {
  std::vector<double> s;
  for (size_t i = 1; i < poses_.size(); ++i) s.push_back(rotationDeg(turn(poses_[i - 1], poses_[i])));
  return median(s);
}

bool TrackingHealthMonitor::moving(double median_depth) const {
  return poses_.size() >= 2 &&
         (medianSpeed() > p_.health_min_accel_depth * median_depth || medianRotationDeg() > 0.1);
}

void TrackingHealthMonitor::accept(const Eigen::Isometry3d& T_w_c) {
  poses_.push_back(T_w_c);
  while (poses_.size() > kHistory) poses_.pop_front();
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
  if (scale_change > p_.health_max_ba_scale_change) {
    why << "local BA changed the map scale by a factor " << in.ba_scale_change;
    return why.str();
  }
  if (poses_.size() < 2) return "";
  const Eigen::Isometry3d& prev = poses_[poses_.size() - 2];
  const Eigen::Isometry3d& last = poses_.back();
  const Eigen::Vector3d v_last = step(prev, last), v_now = step(last, in.T_w_c);
  const double floor = p_.health_min_accel_depth * in.median_depth;
  const double accel = (v_now - v_last).norm();
  const double accel_limit = p_.health_max_accel_ratio * medianSpeed() + floor;
  if (accel > accel_limit) {
    why << "motion jump: velocity changed by " << accel << " (limit " << accel_limit << ")";
    return why.str();
  }
  // A camera cannot reverse its direction within one frame at speed (swapped / out-of-order frames).
  const double reverse_floor = 0.25 * floor;
  if (v_last.norm() > reverse_floor && v_now.norm() > reverse_floor &&
      v_now.dot(v_last) < -0.5 * v_now.norm() * v_last.norm()) {
    why << "motion jump: direction reversed within one frame at speed " << v_now.norm();
    return why.str();
  }
  // Rotation rate change: the rotation of this step against the rotation of the last step.
  const Eigen::Matrix3d w_last = turn(prev, last), w_now = turn(last, in.T_w_c);
  const double rot_accel = rotationDeg(w_last.transpose() * w_now);
  const double rot_limit = p_.health_max_rot_accel_deg + p_.health_max_accel_ratio * medianRotationDeg();
  if (rot_accel > rot_limit) {
    why << "rotation jump: rate changed by " << rot_accel << " deg (limit " << rot_limit << " deg)";
    return why.str();
  }
  return "";
}

}  // namespace iraf_vo
