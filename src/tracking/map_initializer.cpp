#include "iraf_vo/tracking/map_initializer.h"

#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/two_view.h"

#include <algorithm>

namespace iraf_vo {

void MapInitializer::setReference(const Frame& f) {
  have_reference_ = static_cast<int>(f.size()) >= p_.init_min_features;
  if (have_reference_) reference_ = f;
}

std::vector<std::pair<int, int>> MapInitializer::matchToReference(const Frame& ref, const Frame& cur) const {
  std::vector<float> reference_angles(ref.size());
  for (size_t i = 0; i < ref.size(); ++i) reference_angles[i] = ref.keypoints[i].angle;
  const auto matches = matcher_.matchBruteForce(cur.descriptors, cur.keypoints, cur.valid, ref.descriptors,
                                                reference_angles, p_.match_threshold_high, p_.init_match_ratio);
  std::vector<std::pair<int, int>> valid;  // (cur, reference)
  for (const auto& m : matches)
    if (ref.valid[m.second]) valid.push_back(m);
  return valid;
}

bool MapInitializer::initialize(Frame& cur, const MapAnchor& anchor, Map* map, KeyframePtr* kf0_out,
                                KeyframePtr* kf1_out, int* num_points) {
  last_failure_.clear();
  if (!have_reference_ || cur.index - reference_.index > p_.init_max_frames) {
    last_failure_ = have_reference_ ? "reference too old" : "no reference";
    have_previous_ = false;
    setReference(cur);
    return false;
  }
  const std::vector<std::pair<int, int>> matches = matchToReference(reference_, cur);
  const bool enough = static_cast<int>(matches.size()) >= p_.init_min_matches;
  if (enough && initializeFrom(reference_, matches, cur, anchor, map, kf0_out, kf1_out, num_points)) return true;
  if (initializeFromPrevious(cur, anchor, map, kf0_out, kf1_out, num_points)) return true;
  if (!enough) {
    last_failure_ =
        "too few matches (" + std::to_string(matches.size()) + " < " + std::to_string(p_.init_min_matches) + ")";
    // Fast forward motion carries the matches out of the view before the parallax suffices: the replaced
    // reference stays a second candidate while it keeps enough matches for an initial map.
    previous_ = reference_;
    have_previous_ = true;
    setReference(cur);
  }
  return false;
}

bool MapInitializer::initializeFromPrevious(Frame& cur, const MapAnchor& anchor, Map* map, KeyframePtr* kf0,
                                            KeyframePtr* kf1, int* num_points) {
  if (!have_previous_) return false;
  const std::vector<std::pair<int, int>> matches = matchToReference(previous_, cur);
  if (cur.index - previous_.index > p_.init_max_frames || static_cast<int>(matches.size()) < p_.init_min_triangulated) {
    have_previous_ = false;
    return false;
  }
  const std::string failure = last_failure_;  // the current reference's: the one the log reports
  if (initializeFrom(previous_, matches, cur, anchor, map, kf0, kf1, num_points)) {
    last_failure_.clear();
    return true;
  }
  last_failure_ = failure;
  return false;
}

bool MapInitializer::initializeFrom(const Frame& ref, const std::vector<std::pair<int, int>>& matches,
                                    Frame& cur, const MapAnchor& anchor, Map* map, KeyframePtr* kf0_out,
                                    KeyframePtr* kf1_out, int* num_points) {
  std::vector<Eigen::Vector3d> b_ref, b_cur;
  for (const auto& m : matches) {
    b_ref.push_back(ref.bearings[m.second]);
    b_cur.push_back(cur.bearings[m.first]);
  }
  TwoViewParams two_view_params;
  two_view_params.threshold_px = p_.init_threshold_px;
  two_view_params.min_parallax_deg = p_.init_min_parallax_deg;
  two_view_params.min_parallax_points = p_.init_min_parallax_points;
  two_view_params.min_median_parallax_deg = p_.init_min_median_parallax_deg;
  two_view_params.determined_parallax_points = p_.init_determined_parallax_points;
  two_view_params.determined_min_chi2 = p_.init_determined_min_chi2;
  two_view_params.min_triangulated = p_.init_min_triangulated;
  two_view_params.homography_ratio = p_.init_homography_ratio;
  two_view_params.ambiguity_max_chi2 = p_.init_ambiguity_max_chi2;
  two_view_params.ambiguity_angle_deg = p_.init_ambiguity_angle_deg;
  two_view_params.ba_use_ceres = p_.ba_use_ceres;
  const TwoViewResult two_view = initializeTwoView(b_ref, b_cur, cam_.focal(), two_view_params);
  if (!two_view.ok) {
    last_failure_ = "ref " + std::to_string(ref.index) + " " + std::to_string(matches.size()) +
                    " matches: " + two_view.reason;
    return false;
  }

  // Scale: median depth of the triangulated points in the reference frame = anchor depth.
  std::vector<double> depths;
  for (size_t k = 0; k < matches.size(); ++k)
    if (two_view.triangulated[k]) depths.push_back(two_view.points[k].z());
  std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
  const double median = depths[depths.size() / 2];
  if (!(median > 0)) return (last_failure_ = "median depth not positive"), false;
  const double s = anchor.median_depth / median;
  Eigen::Isometry3d T_cur_ref = Eigen::Isometry3d::Identity();
  T_cur_ref.linear() = two_view.R_21;
  T_cur_ref.translation() = s * two_view.t_21;
  const Eigen::Isometry3d T_ref_c_w = anchor.T_w_ref.inverse();
  const Eigen::Isometry3d T_cur_c_w = T_cur_ref * T_ref_c_w;
  KeyframePtr kf0 = Keyframe::fromFrame(ref, T_ref_c_w);
  KeyframePtr kf1 = Keyframe::fromFrame(cur, T_cur_c_w);

  // Two-keyframe BA (first keyframe fixed) before the map goes live.
  std::vector<BAKeyframe> ba_keyframes(2);
  ba_keyframes[0].T_c_w = T_ref_c_w;
  ba_keyframes[0].fixed = true;
  ba_keyframes[1].T_c_w = T_cur_c_w;
  std::vector<BAPoint> ba_points;
  std::vector<BAObservation> ba_observations;
  std::vector<std::pair<int, int>> point_match;
  for (size_t k = 0; k < matches.size(); ++k) {
    if (!two_view.triangulated[k]) continue;
    const int pi = static_cast<int>(ba_points.size());
    ba_points.push_back({anchor.T_w_ref * (s * two_view.points[k])});
    const cv::KeyPoint& k0 = ref.keypoints[matches[k].second];
    const cv::KeyPoint& k1 = cur.keypoints[matches[k].first];
    ba_observations.push_back({0, pi, Eigen::Vector2d(k0.pt.x, k0.pt.y), ref.sigma(k0.octave)});
    ba_observations.push_back({1, pi, Eigen::Vector2d(k1.pt.x, k1.pt.y), cur.sigma(k1.octave)});
    point_match.push_back(matches[k]);
  }
  BAOptions options;
  options.max_num_iterations = 20;
  options.max_cpu_seconds = 0.5;  // CPU time: the result does not depend on the machine load
  options.max_solver_time_in_seconds = 10.0;  // wall-clock safety cap only
  options.huber_delta = p_.ba_huber_delta;
  options.use_ceres = p_.ba_use_ceres;
  BASummary summary;
  bundleAdjust(cam_, &ba_keyframes, &ba_points, ba_observations, options, &summary);
  kf1->T_c_w = ba_keyframes[1].T_c_w;

  std::vector<NewMapPoint> points;
  for (size_t i = 0; i < ba_points.size(); ++i) {
    if (summary.outlier.size() == ba_observations.size() && (summary.outlier[2 * i] || summary.outlier[2 * i + 1]))
      continue;
    points.push_back({ba_points[i].p_w, 0, point_match[i].first, 0, point_match[i].second});
  }
  if (!map->createInitialMap(kf0, kf1, points, p_.init_min_triangulated, num_points))
    return (last_failure_ = "too few points after the two-keyframe BA (" + std::to_string(points.size()) + ")"), false;
  cur.T_c_w = kf1->T_c_w;
  cur.point_id = kf1->point_id;
  *kf0_out = kf0;
  *kf1_out = kf1;
  have_previous_ = false;
  return true;
}

}  // namespace iraf_vo
