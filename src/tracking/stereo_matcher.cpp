#include "iraf_vo/tracking/stereo_matcher.h"

#include "iraf_vo/tracking/geometry.h"
#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/stereo_refinement.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace iraf_vo {

StereoMatcher::StereoMatcher(const StereoRig& rig, const TrackerParams& params)
    : rig_(rig), p_(params), max_depth_(params.stereo_max_depth_baselines * rig.baseline()),
      close_depth_(max_depth_) {
  if (params.stereo_min_disparity_px > 0 && rig.left)
    close_depth_ = std::min(max_depth_, rig.left->focal() * rig.baseline() / params.stereo_min_disparity_px);
  E_ = skew(rig.T_r_l.translation()) * rig.T_r_l.linear();
  c_r_in_l_ = rig.T_r_l.inverse().translation();
}

std::vector<StereoMatch> StereoMatcher::match(const Frame& left, const Frame& right, const cv::Mat& left_image,
                                              const cv::Mat& right_image) const {
  std::vector<StereoMatch> out;
  if (!rig_.left || !rig_.right || left.size() == 0 || right.size() == 0) return out;
  const CameraModel& cam_l = *rig_.left;
  const CameraModel& cam_r = *rig_.right;
  const int max_dist = (p_.match_threshold_high + p_.match_threshold_low) / 2;
  const double f_r = cam_r.focal();
  const Eigen::Matrix3d R_rl = rig_.T_r_l.linear();
  const Eigen::Vector3d t_rl = rig_.T_r_l.translation();
  const double min_depth = p_.stereo_min_depth;

  // The right bearings as rows (invalid ones far off every epipolar plane): one matrix-vector product per left
  // keypoint gives every right bearing's distance from its epipolar plane.
  Eigen::Matrix<double, Eigen::Dynamic, 3> B(right.size(), 3);
  for (size_t j = 0; j < right.size(); ++j)
    B.row(static_cast<Eigen::Index>(j)) = right.valid[j] ? right.bearings[j].transpose() : Eigen::RowVector3d(1e3, 1e3, 1e3);
  Eigen::VectorXd off_plane(right.size());
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
    // Orientation of the arc from the near to the far end in the plane (sines of in-plane angles).
    const Eigen::Vector3d axis = d_near.cross(d_far).dot(n) >= 0.0 ? n : Eigen::Vector3d(-n);
    const int oct = left.keypoints[i].octave;
    const double sigma = left.sigma(oct);
    const double max_angle = p_.stereo_epipolar_px * sigma / f_r;
    const uint8_t* dl = left.descriptors.ptr<uint8_t>(static_cast<int>(i));
    int best = std::numeric_limits<int>::max(), second = std::numeric_limits<int>::max(), best_j = -1;
    off_plane.noalias() = B * n;
    for (size_t j = 0; j < right.size(); ++j) {
      if (std::abs(off_plane(static_cast<Eigen::Index>(j))) > max_angle) continue;
      if (std::abs(right.keypoints[j].octave - oct) > 1) continue;
      const Eigen::Vector3d& br = right.bearings[j];
      // Between the near and far ends of the arc (within the tolerance), in front of the right camera.
      if (br.dot(d_near) + br.dot(d_far) < 0.0 || axis.dot(d_near.cross(br)) < -max_angle ||
          axis.dot(br.cross(d_far)) < -max_angle)
        continue;
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
  const bool refine = !left_image.empty() && !right_image.empty();
  for (size_t i = 0; i < left.size(); ++i) {
    const int j = left_choice[i];
    if (j < 0 || right_partner[j] != static_cast<int>(i)) continue;
    Eigen::Vector2d uv_r(right.keypoints[j].pt.x, right.keypoints[j].pt.y);
    Eigen::Vector3d b_r = right.bearings[j];
    if (refine && !refineRight(left, i, right.keypoints[j].octave, left_image, right_image, &uv_r, &b_r)) continue;
    Eigen::Vector3d p_l;
    if (!triangulateBearings(T_l_l, left.bearings[i], rig_.T_r_l, b_r, &p_l)) continue;
    const Eigen::Vector3d p_r = rig_.T_r_l * p_l;
    if (!(p_l.dot(left.bearings[i]) > 0.0) || !(p_r.dot(b_r) > 0.0)) continue;
    const double depth = p_l.norm();
    if (!(depth >= min_depth && depth <= max_depth_)) continue;
    const double s_l = left.sigma(left.keypoints[i].octave), s_r = right.sigma(right.keypoints[j].octave);
    const Eigen::Vector2d uv_l(left.keypoints[i].pt.x, left.keypoints[i].pt.y);
    const double e_l = reprojectionError2(cam_l, T_l_l, p_l, uv_l);
    const double e_r = reprojectionError2(cam_r, rig_.T_r_l, p_l, uv_r);
    if (e_l < 0.0 || e_r < 0.0 || e_l > kChi2TwoDof * s_l * s_l || e_r > kChi2TwoDof * s_r * s_r) continue;
    StereoMatch m;
    m.left = static_cast<int>(i);
    m.right = j;
    m.p_l = p_l;
    m.uv_r = uv_r;
    out.push_back(m);
  }
  keepClosePoints(&out);
  return out;
}

void StereoMatcher::keepClosePoints(std::vector<StereoMatch>* matches) const {
  auto far = std::stable_partition(matches->begin(), matches->end(),
                                   [this](const StereoMatch& m) { return m.depth() <= close_depth_; });
  const long missing = p_.stereo_far_fill_points - (far - matches->begin());
  if (missing > 0) {  // too few close points: the nearest far ones too (ORB-SLAM's keyframe rule)
    std::stable_sort(far, matches->end(),
                     [](const StereoMatch& a, const StereoMatch& b) { return a.depth() < b.depth(); });
    far += std::min<long>(missing, matches->end() - far);
  }
  matches->erase(far, matches->end());
}

bool StereoMatcher::refineRight(const Frame& left, size_t i, int right_octave, const cv::Mat& left_image,
                                const cv::Mat& right_image, Eigen::Vector2d* uv_r, Eigen::Vector3d* b_r) const {
  // The epipolar curve's tangent at the right pixel: the left ray's points at inverse depths rho +- eps project to
  // R b_l + rho t (rho of the raw triangulation, 0 = infinity when it fails); eps spans ~2 px of disparity.
  const Eigen::Vector3d rb = rig_.T_r_l.linear() * left.bearings[i], t = rig_.T_r_l.translation();
  Eigen::Vector3d p_l;
  double rho = 0.0;
  if (triangulateBearings(Eigen::Isometry3d::Identity(), left.bearings[i], rig_.T_r_l, *b_r, &p_l) &&
      p_l.dot(left.bearings[i]) > 0.0)
    rho = 1.0 / std::max(p_l.norm(), p_.stereo_min_depth);
  const double eps = 2.0 / (rig_.right->focal() * rig_.baseline());
  Eigen::Vector2d a, b;
  if (!rig_.right->project(rb + (rho + eps) * t, &a) || !rig_.right->project(rb + std::max(0.0, rho - eps) * t, &b))
    return false;
  if (!((a - b).norm() > 1e-6)) return false;
  const Eigen::Vector2d dir = (a - b).normalized();
  // The search starts at the right keypoint moved onto the epipolar line (its level-grid offset across the line
  // would otherwise stay in the observation).
  const Eigen::Vector2d start = b + dir * (*uv_r - b).dot(dir);
  const cv::KeyPoint& kl = left.keypoints[i];
  const double step = left.sigma(std::min(kl.octave, right_octave));
  Eigen::Vector2d refined;
  if (!refineAlongEpipolar(left_image, right_image, Eigen::Vector2d(kl.pt.x, kl.pt.y), start, dir, step, &refined))
    return false;
  Eigen::Vector3d bearing;
  if (!rig_.right->unproject(refined, &bearing) || !bearing.allFinite() || !(bearing.norm() > 0.5)) return false;
  *uv_r = refined;
  *b_r = bearing.normalized();
  return true;
}

bool StereoMatcher::matchRight(Frame* left, const FeatureFrame& right, std::vector<StereoMatch>* matches,
                               const cv::Mat& left_image) const {
  matches->clear();
  left->right_obs.clear();
  Frame rf;
  std::string err;
  if (right.keypoints.empty() || !Frame::fromFeatures(right, *rig_.right, left->index, &rf, &err)) return false;
  *matches = match(*left, rf, left_image, left_image.empty() ? cv::Mat() : right.image);
  left->right_obs.assign(left->size(), Eigen::Vector3f::Zero());
  for (const StereoMatch& m : *matches) {
    const cv::KeyPoint& kp = rf.keypoints[m.right];
    left->right_obs[m.left] =
        Eigen::Vector3f(static_cast<float>(m.uv_r.x()), static_cast<float>(m.uv_r.y()), static_cast<float>(rf.sigma(kp.octave)));
  }
  return true;
}

std::vector<StereoMapPoint> stereoMapPoints(const std::vector<StereoMatch>& matches, const Frame& left, bool only_new) {
  std::vector<StereoMapPoint> out;
  const Eigen::Isometry3d T_w_c = left.T_c_w.inverse();
  for (const StereoMatch& m : matches) {
    if (only_new && left.point_id[m.left] >= 0) continue;
    StereoMapPoint sp;
    sp.kp = m.left;
    sp.p_w = T_w_c * m.p_l;
    out.push_back(sp);
  }
  return out;
}

double closeShareWithoutPoint(const std::vector<StereoMatch>& matches, const Frame& left, double close_depth) {
  if (left.size() == 0) return 0.0;
  const auto n = std::count_if(matches.begin(), matches.end(), [&](const StereoMatch& m) {
    return left.point_id[m.left] < 0 && m.depth() <= close_depth;
  });
  return static_cast<double>(n) / static_cast<double>(left.size());
}

}  // namespace iraf_vo
