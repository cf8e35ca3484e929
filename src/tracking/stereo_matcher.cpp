#include "iraf_vo/tracking/stereo_matcher.h"

#include "iraf_vo/tracking/geometry.h"
#include "iraf_vo/tracking/multiview.h"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace iraf_vo {

StereoMatcher::StereoMatcher(const StereoRig& rig, const TrackerParams& params)
    : rig_(rig), p_(params), max_depth_(params.stereo_max_depth_baselines * rig.baseline()) {
  E_ = skew(rig.T_r_l.translation()) * rig.T_r_l.linear();
  c_r_in_l_ = rig.T_r_l.inverse().translation();
}

std::vector<StereoMatch> StereoMatcher::match(const Frame& left, const Frame& right) const {
  std::vector<StereoMatch> out;
  if (!rig_.left || !rig_.right || left.size() == 0 || right.size() == 0) return out;
  const CameraModel& cam_l = *rig_.left;
  const CameraModel& cam_r = *rig_.right;
  const int max_dist = (p_.match_threshold_high + p_.match_threshold_low) / 2;
  const double f_r = cam_r.focal();
  const Eigen::Matrix3d R_rl = rig_.T_r_l.linear();
  const Eigen::Vector3d t_rl = rig_.T_r_l.translation();
  const double min_depth = p_.stereo_min_depth;

  // Per right keypoint: its best left partner (distance, left index, right index).
  std::vector<int> right_best(right.size(), max_dist + 1), right_partner(right.size(), -1);
  std::vector<int> left_choice(left.size(), -1);
  for (size_t i = 0; i < left.size(); ++i) {
    if (!left.valid[i]) continue;
    const Eigen::Vector3d& bl = left.bearings[i];
    Eigen::Vector3d n = E_ * bl;  // normal of the epipolar plane in the right camera
    const double nn = n.norm();
    if (!(nn > 1e-12)) continue;
    n /= nn;
    // The epipolar arc of the depth range: directions of the point at min and max depth seen from the right.
    const Eigen::Vector3d d_near = (R_rl * (min_depth * bl) + t_rl).normalized();
    const Eigen::Vector3d d_far = (R_rl * (max_depth_ * bl) + t_rl).normalized();
    const double arc = std::acos(std::min(1.0, d_near.dot(d_far)));
    const int oct = left.keypoints[i].octave;
    const double sigma = left.sigma(oct);
    const double max_angle = p_.stereo_epipolar_px * sigma / f_r;
    const uint8_t* dl = left.descriptors.ptr<uint8_t>(static_cast<int>(i));
    int best = std::numeric_limits<int>::max(), second = std::numeric_limits<int>::max(), best_j = -1;
    for (size_t j = 0; j < right.size(); ++j) {
      if (!right.valid[j] || std::abs(right.keypoints[j].octave - oct) > 1) continue;
      const Eigen::Vector3d& br = right.bearings[j];
      if (std::abs(n.dot(br)) > max_angle) continue;
      // Between the near and far ends of the arc (within the tolerance).
      const double a_near = std::acos(std::min(1.0, br.dot(d_near)));
      const double a_far = std::acos(std::min(1.0, br.dot(d_far)));
      if (a_near + a_far > arc + 2.0 * max_angle) continue;
      const int d = hammingDistance(dl, right.descriptors.ptr<uint8_t>(static_cast<int>(j)));
      if (d < best) {
        second = best;
        best = d;
        best_j = static_cast<int>(j);
      } else if (d < second) {
        second = d;
      }
    }
    if (best_j < 0 || best > max_dist) continue;
    if (second != std::numeric_limits<int>::max() && best >= p_.match_ratio * second) continue;
    left_choice[i] = best_j;
    if (best < right_best[best_j]) {
      right_best[best_j] = best;
      right_partner[best_j] = static_cast<int>(i);
    }
  }

  const Eigen::Isometry3d T_l_l = Eigen::Isometry3d::Identity();
  for (size_t i = 0; i < left.size(); ++i) {
    const int j = left_choice[i];
    if (j < 0 || right_partner[j] != static_cast<int>(i)) continue;
    Eigen::Vector3d p_l;
    if (!triangulateBearings(T_l_l, left.bearings[i], rig_.T_r_l, right.bearings[j], &p_l)) continue;
    const Eigen::Vector3d p_r = rig_.T_r_l * p_l;
    if (!(p_l.dot(left.bearings[i]) > 0.0) || !(p_r.dot(right.bearings[j]) > 0.0)) continue;
    const double depth = p_l.norm();
    if (!(depth >= min_depth && depth <= max_depth_)) continue;
    const double s_l = left.sigma(left.keypoints[i].octave), s_r = right.sigma(right.keypoints[j].octave);
    const Eigen::Vector2d uv_l(left.keypoints[i].pt.x, left.keypoints[i].pt.y);
    const Eigen::Vector2d uv_r(right.keypoints[j].pt.x, right.keypoints[j].pt.y);
    const double e_l = reprojectionError2(cam_l, T_l_l, p_l, uv_l);
    const double e_r = reprojectionError2(cam_r, rig_.T_r_l, p_l, uv_r);
    if (e_l < 0.0 || e_r < 0.0 || e_l > kChi2TwoDof * s_l * s_l || e_r > kChi2TwoDof * s_r * s_r) continue;
    StereoMatch m;
    m.left = static_cast<int>(i);
    m.right = j;
    m.p_l = p_l;
    out.push_back(m);
  }
  return out;
}

}  // namespace iraf_vo
