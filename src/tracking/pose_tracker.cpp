#include "iraf_vo/tracking/pose_tracker.h"

#include "iraf_vo/common/wall_clock.h"
#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/pose_covariance.h"
#include "iraf_vo/tracking/pose_optimization.h"

#include <algorithm>
#include <cstring>
#include <unordered_map>

namespace iraf_vo {
namespace {

// Matches of candidate points (MapPoint::candidate): matched and kept, but no pose term.
int candidateMatches(const MatchSet& matches, const std::vector<LocalPoint>& local) {
  int n = 0;
  for (size_t i = 0; i < matches.numKeypoints(); ++i) {
    const int li = matches.pointOf(static_cast<int>(i));
    if (li >= 0 && local[static_cast<size_t>(li)].candidate) ++n;
  }
  return n;
}

}  // namespace

PoseTrackingResult PoseTracker::trackLocalMap(Frame& cur, const Eigen::Isometry3d& T_predicted, Map* map,
                                              bool prediction_unknown, int min_search_inliers,
                                              bool rough_prediction) const {
  const std::vector<LocalPoint> local = map->localPoints(p_.predict_scale ? &cam_ : nullptr);
  Solution s = solve(cur, T_predicted, local, prediction_unknown, min_search_inliers, rough_prediction);
  PoseTrackingResult& res = s.res;
  if (!res.tracked) return res;
  cur.T_c_w = s.T;
  map->countVisibility(local, s.visible, s.matches.keypointOfPoint());
  std::vector<double> depths;
  for (size_t i = 0; i < cur.size(); ++i) {
    const int li = s.matches.pointOf(static_cast<int>(i));
    if (li < 0) continue;
    cur.point_id[i] = local[li].id;
    depths.push_back((s.T * local[li].p_w).z());
  }
  if (!depths.empty()) {
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    res.median_depth = depths[depths.size() / 2];
    res.has_median_depth = true;
  }
  return res;
}

int PoseTracker::inliersFrom(const Frame& cur, const Eigen::Isometry3d& T_predicted, const Map& map,
                             bool prediction_unknown, bool rough_prediction) const {
  const std::vector<LocalPoint> local = map.localPoints(p_.predict_scale ? &cam_ : nullptr);
  const Solution s = solve(cur, T_predicted, local, prediction_unknown, 0, rough_prediction);
  return s.res.tracked ? s.res.inliers : 0;
}

PoseTracker::Solution PoseTracker::solve(const Frame& cur, const Eigen::Isometry3d& T_predicted,
                                         const std::vector<LocalPoint>& local, bool prediction_unknown,
                                         int min_search_inliers, bool rough_prediction) const {
  Solution sol(cur.size(), local.size());
  PoseTrackingResult& res = sol.res;
  MatchSet& matches = sol.matches;
  std::vector<char>& visible = sol.visible;
  Eigen::Isometry3d& T = sol.T;
  auto t0 = SteadyClock::now();
  T = T_predicted;
  int n = 0;
  if (prediction_unknown) {
    // No motion model: a projection search around T_predicted finds only the far points when the camera moved
    // fast, and a pose from them alone comes out short. Brute force + PnP first; the projection search if it fails.
    // A PnP with fewer inliers than tracking needs (a wide fisheye: the RANSAC's threshold on the normalized plane
    // drops the peripheral matches) still predicts the step.
    Eigen::Isometry3d T_pnp = T;
    MatchSet pnp_matches(cur.size(), local.size());
    const int n_pnp = relocalize(cur, local, &pnp_matches, &T_pnp, kMinPnPPrediction);
    // On far points the PnP's direction of motion is better known than its length, which comes out short: the
    // motion lengthened 2x and 4x compete with it and with the last pose, judged by the inliers of a search and
    // refinement from each.
    if (n_pnp > 0) {
      const Eigen::Isometry3d motion = T_pnp * T.inverse();
      const auto lengthened = [&](int k) {  // the PnP's motion, its translation x k, from the last pose
        Eigen::Isometry3d M = motion;
        M.translation() *= k;
        return Eigen::Isometry3d(M * T);
      };
      int best = inliersFromStart(cur, local, T);
      int best_k = 0;
      for (int k : {1, 2, 4}) {
        const int n_k = inliersFromStart(cur, local, lengthened(k));
        if (n_k > best) best = n_k, best_k = k;
      }
      if (best_k == 1 && n_pnp >= p_.min_tracking_inliers) {
        matches = pnp_matches;
        T = T_pnp;
        n = n_pnp;
        res.used_pnp = true;
      } else if (best_k > 0) {
        T = lengthened(best_k);
      }
    }
  }
  if (!res.used_pnp) n = searchAround(cur, T, local, &matches);
  res.ms_match += msSince(t0);
  int inliers = 0;
  if (res.used_pnp || n >= p_.min_search_matches) {
    t0 = SteadyClock::now();
    inliers = refinePose(cur, local, &matches, &T);
    res.ms_pose += msSince(t0);
  }
  for (int k = 0; rough_prediction && k < kMaxResearches && inliers >= p_.min_tracking_inliers; ++k) {
    MatchSet again(cur.size(), local.size());
    Eigen::Isometry3d T_again = T;
    const int n_again = matcher_.searchByProjection(cur, T_again, local, p_.search_radius_px, 1, &again, nullptr);
    if (n_again < p_.min_search_matches) break;
    const int inliers_again = refinePose(cur, local, &again, &T_again);
    if (inliers_again <= inliers) break;
    matches = std::move(again);
    T = T_again;
    inliers = inliers_again;
    n = n_again;
  }
  // A pose from PnP needs min_tracking_inliers; one from the projection search around T_predicted may need more.
  const int search_needs = std::max(p_.min_tracking_inliers, min_search_inliers);
  if (inliers < (res.used_pnp ? p_.min_tracking_inliers : search_needs))
    inliers = pnpPose(cur, local, &matches, &T, &res, &res.used_pnp);
  res.matches = n;
  res.inliers = inliers;
  if (inliers < p_.min_tracking_inliers) return sol;
  narrowPass(cur, local, &matches, &T, &visible, &res);
  if (min_search_inliers > 0 && !res.used_pnp) {
    // A relocalization from the search around T_predicted: the prior-free brute force + PnP pose competes.
    MatchSet pnp_matches(cur.size(), local.size());
    Eigen::Isometry3d T_pnp = T;
    if (pnpPose(cur, local, &pnp_matches, &T_pnp, &res) >= p_.min_tracking_inliers) {
      std::vector<char> pnp_visible(local.size(), 0);
      PoseTrackingResult pnp;
      narrowPass(cur, local, &pnp_matches, &T_pnp, &pnp_visible, &pnp);
      res.ms_match += pnp.ms_match;
      res.ms_pose += pnp.ms_pose;
      if (pnp.inliers > res.inliers) {
        matches = std::move(pnp_matches);
        T = T_pnp;
        visible = std::move(pnp_visible);
        res.used_pnp = true;
        res.refine_matches = pnp.refine_matches;
        res.inliers = pnp.inliers;
        res.right_inliers = pnp.right_inliers;
      }
    }
  }
  if (res.inliers < p_.min_tracking_inliers) return sol;
  describeInliers(cur, local, matches, T, &res);
  res.tracked = true;
  return sol;
}

int PoseTracker::pnpPose(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches,
                         Eigen::Isometry3d* T, PoseTrackingResult* timing, bool* found) const {
  auto t0 = SteadyClock::now();
  int inliers = relocalize(f, local, matches, T);
  if (found) *found = inliers > 0;
  timing->ms_match += msSince(t0);
  if (inliers >= p_.min_tracking_inliers) {
    t0 = SteadyClock::now();
    inliers = refinePose(f, local, matches, T);
    timing->ms_pose += msSince(t0);
  }
  return inliers;
}

void PoseTracker::narrowPass(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches,
                             Eigen::Isometry3d* T, std::vector<char>* visible, PoseTrackingResult* res) const {
  auto t0 = SteadyClock::now();
  matcher_.searchByProjection(f, *T, local, p_.search_radius_refine_px, 1, matches, visible);
  res->ms_match += msSince(t0);
  t0 = SteadyClock::now();
  res->refine_matches = matches->size() - candidateMatches(*matches, local);
  res->inliers = refinePose(f, local, matches, T, &res->right_inliers);
  res->ms_pose += msSince(t0);
}

int PoseTracker::refineWithRight(Frame& cur, const Map& map) const {
  if (!rig_ || cur.right_obs.size() != cur.size()) return -1;
  const std::vector<LocalPoint> local = map.localPoints();
  std::unordered_map<long, int> index;
  for (size_t k = 0; k < local.size(); ++k) index[local[k].id] = static_cast<int>(k);
  MatchSet matches(cur.size(), local.size());
  for (size_t i = 0; i < cur.size(); ++i) {
    const auto it = index.find(cur.point_id[i]);
    if (it != index.end()) matches.link(static_cast<int>(i), it->second);
  }
  Eigen::Isometry3d T = cur.T_c_w;
  int right_inliers = 0;
  if (refinePose(cur, local, &matches, &T, &right_inliers) < p_.min_tracking_inliers) return -1;
  cur.T_c_w = T;
  for (size_t i = 0; i < cur.size(); ++i)
    if (matches.pointOf(static_cast<int>(i)) < 0) cur.point_id[i] = -1;
  return right_inliers;
}

void PoseTracker::describeInliers(const Frame& f, const std::vector<LocalPoint>& local, const MatchSet& matches,
                                  const Eigen::Isometry3d& T, PoseTrackingResult* res) const {
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> sigma, chi2;
  for (size_t i = 0; i < f.size(); ++i) {
    const int li = matches.pointOf(static_cast<int>(i));
    if (li < 0 || local[li].candidate) continue;
    P.push_back(local[li].p_w);
    uv.emplace_back(f.keypoints[i].pt.x, f.keypoints[i].pt.y);
    sigma.push_back(f.sigma(f.keypoints[i].octave));
    const double e2 = reprojectionError2(cam_, T, P.back(), uv.back());
    chi2.push_back(e2 < 0 ? 1e9 : e2 / (sigma.back() * sigma.back()));
  }
  if (!chi2.empty()) {
    std::nth_element(chi2.begin(), chi2.begin() + chi2.size() / 2, chi2.end());
    res->median_chi2 = chi2[chi2.size() / 2];
  }
  res->information = poseInformation(cam_, P, uv, sigma, T);
}

int PoseTracker::refinePose(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches,
                            Eigen::Isometry3d* T, int* right_inliers) const {
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> sigma;
  std::vector<int> keypoint, candidates;
  const bool stereo = rig_ && f.right_obs.size() == f.size();
  RightObservations right;
  if (stereo) {
    right.camera = rig_->right.get();
    right.T_r_l = rig_->T_r_l;
  }
  for (size_t i = 0; i < f.size(); ++i) {
    const int li = matches->pointOf(static_cast<int>(i));
    if (li < 0) continue;
    if (local[li].candidate) {
      candidates.push_back(static_cast<int>(i));
      continue;
    }
    P.push_back(local[li].p_w);
    uv.emplace_back(f.keypoints[i].pt.x, f.keypoints[i].pt.y);
    sigma.push_back(f.sigma(f.keypoints[i].octave));
    keypoint.push_back(static_cast<int>(i));
    if (!stereo) continue;
    const Eigen::Vector3f& r = f.right_obs[i];  // sigma 0: no right match
    right.uv.emplace_back(r.x(), r.y());
    right.sigma.push_back(r.z());
  }
  if (P.size() < 4) return 0;
  PoseOptimizationOptions options;
  options.rounds = p_.pose_rounds;
  options.max_num_iterations = p_.pose_max_iterations;
  options.use_ceres = p_.pose_use_ceres;
  std::vector<char> inlier(P.size(), 1);
  Eigen::Isometry3d T_refined = *T;
  const int n = optimizePose(cam_, P, uv, sigma, options, &T_refined, &inlier, stereo ? &right : nullptr, right_inliers);
  if (n < 4) return n;
  *T = T_refined;
  for (size_t k = 0; k < keypoint.size(); ++k)
    if (!inlier[k]) matches->unlinkKeypoint(keypoint[k]);
  for (int i : candidates) {  // kept (the next keyframe observes them) where the pose reprojects them
    const cv::KeyPoint& kp = f.keypoints[static_cast<size_t>(i)];
    const double s = f.sigma(kp.octave);
    const double e2 = reprojectionError2(cam_, *T, local[static_cast<size_t>(matches->pointOf(i))].p_w,
                                         Eigen::Vector2d(kp.pt.x, kp.pt.y));
    if (e2 < 0 || e2 > kChi2TwoDof * s * s) matches->unlinkKeypoint(i);
  }
  return n;
}

int PoseTracker::searchAround(const Frame& f, const Eigen::Isometry3d& T, const std::vector<LocalPoint>& local,
                              MatchSet* matches) const {
  const int n = matcher_.searchByProjection(f, T, local, p_.search_radius_px, 1, matches, nullptr);
  if (n >= p_.min_search_matches) return n;
  matches->clear();
  return matcher_.searchByProjection(f, T, local, p_.search_radius_wide_px, 2, matches, nullptr);
}

int PoseTracker::inliersFromStart(const Frame& f, const std::vector<LocalPoint>& local, Eigen::Isometry3d T) const {
  MatchSet m(f.size(), local.size());
  if (searchAround(f, T, local, &m) < p_.min_search_matches) return 0;
  return refinePose(f, local, &m, &T);
}

int PoseTracker::relocalize(const Frame& f, const std::vector<LocalPoint>& local, MatchSet* matches,
                            Eigen::Isometry3d* T, int min_inliers) const {
  if (min_inliers <= 0) min_inliers = p_.min_tracking_inliers;
  if (local.size() < 10) return 0;
  cv::Mat D(static_cast<int>(local.size()), 32, CV_8U);
  std::vector<float> angles(local.size());
  for (size_t i = 0; i < local.size(); ++i) {
    std::memcpy(D.ptr<uint8_t>(static_cast<int>(i)), local[i].desc.data(), 32);
    angles[i] = local[i].angle;
  }
  const auto m = matcher_.matchBruteForce(f.descriptors, f.keypoints, f.valid, D, angles, p_.match_threshold_high,
                                          p_.match_ratio);
  if (static_cast<int>(m.size()) < min_inliers) return 0;
  std::vector<Eigen::Vector3d> P, B;
  std::vector<std::pair<int, int>> used;  // candidates carry no pose
  for (const auto& x : m) {
    if (local[x.second].candidate) continue;
    used.push_back(x);
    P.push_back(local[x.second].p_w);
    B.push_back(f.bearings[x.first]);
  }
  if (static_cast<int>(used.size()) < min_inliers) return 0;
  std::vector<char> inlier;
  Eigen::Isometry3d T_pnp;
  const int n = solvePnPBearings(P, B, cam_.focal(), p_.pnp_threshold_px, p_.pnp_iterations, &T_pnp, &inlier);
  if (n < min_inliers) return 0;
  matches->clear();
  for (size_t k = 0; k < used.size(); ++k)
    if (inlier[k]) matches->link(used[k].first, used[k].second);
  *T = T_pnp;
  return n;
}

}  // namespace iraf_vo
