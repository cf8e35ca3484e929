#include "iraf_vo/tracking/local_ba.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace iraf_vo {

int fixMonocularGauge(std::vector<BAKeyframe>* keyframes, int window_size, double min_fixed_span) {
  std::vector<BAKeyframe>& bk = *keyframes;
  int num_fixed = static_cast<int>(std::count_if(bk.begin(), bk.end(), [](const BAKeyframe& k) { return k.fixed; }));
  if (window_size < 1) return num_fixed;
  auto centre = [&](size_t k) { return Eigen::Vector3d(bk[k].T_c_w.inverse().translation()); };
  const double window_span = (centre(0) - centre(static_cast<size_t>(window_size - 1))).norm();
  auto fixedSpan = [&]() {
    double m = 0.0;
    for (size_t i = 0; i < bk.size(); ++i)
      for (size_t j = i + 1; j < bk.size(); ++j)
        if (bk[i].fixed && bk[j].fixed) m = std::max(m, (centre(i) - centre(j)).norm());
    return m;
  };
  for (int w = window_size - 1; w >= 1; --w) {
    if (bk[w].fixed) continue;
    if (num_fixed >= 2 && fixedSpan() >= min_fixed_span * window_span) break;
    bk[w].fixed = true;
    ++num_fixed;
  }
  return num_fixed;
}

double windowExtent(const LocalBAProblem& prob) {
  double extent = 0.0;
  if (prob.window_size < 1) return 0.0;
  const Eigen::Vector3d newest = prob.keyframes[0].T_c_w.inverse().translation();
  for (int k = 1; k < prob.window_size; ++k)
    extent = std::max(extent, (prob.keyframes[k].T_c_w.inverse().translation() - newest).norm());
  return extent;
}

double anchorBaseline(const LocalBAProblem& prob) {
  if (prob.scale_anchor < 1) return 0.0;
  const auto centre = [&](int k) -> Eigen::Vector3d {
    return prob.keyframes[static_cast<size_t>(k)].T_c_w.inverse().translation();
  };
  return (centre(prob.scale_anchor - 1) - centre(prob.scale_anchor)).norm();
}

void holdScaleAboutAnchor(LocalBAProblem* prob, double baseline) {
  const double now = anchorBaseline(*prob);
  if (!(now > 1e-12) || !(baseline > 0)) return;
  const double s = baseline / now;
  const Eigen::Vector3d c0 = prob->keyframes[static_cast<size_t>(prob->scale_anchor)].T_c_w.inverse().translation();
  // x -> c0 + s (x - c0) in the world; a camera keeps its rotation, its centre moves the same way.
  for (auto& k : prob->keyframes) {
    if (k.fixed) continue;
    const Eigen::Vector3d c = k.T_c_w.inverse().translation();
    k.T_c_w.translation() = -(k.T_c_w.linear() * (c0 + s * (c - c0)));
  }
  for (auto& p : prob->points) p.p_w = c0 + s * (p.p_w - c0);
}

// The map's side of the local BA: building the problem and merging the result, each under the map lock.
LocalBAProblem buildLocalBAProblem(const Map& map, int window_size, double min_fixed_span, bool stereo) {
  LocalBAProblem prob;
  std::lock_guard<std::mutex> lk(map.mutex_);
  const auto& keyframes = map.keyframes_;
  const auto& points = map.points_;
  if (keyframes.size() < 2) return prob;
  prob.next_keyframe_id = map.next_keyframe_id_;
  prob.next_point_id = map.next_point_id_;
  // Keyframe id -> problem index, and the keyframe of each problem index (no map lookup per observation).
  std::unordered_map<long, int> kf_index;
  std::vector<const Keyframe*> keyframe_of;
  int nwin = 0;
  for (auto it = keyframes.rbegin(); it != keyframes.rend() && nwin < window_size; ++it, ++nwin) {
    kf_index[it->first] = static_cast<int>(prob.keyframe_ids.size());
    prob.keyframe_ids.push_back(it->first);
    keyframe_of.push_back(it->second.get());
    BAKeyframe b;
    b.T_c_w = it->second->T_c_w;
    prob.keyframes.push_back(b);
  }
  prob.window_size = nwin;
  // Points seen in the window with >= 2 observations, in the order the window first sees them. A point id is looked
  // up once: `considered` also holds the rejected ones.
  std::unordered_set<long> considered;
  if (nwin > 0) considered.reserve(4 * keyframe_of.front()->point_id.size());
  std::vector<const MapPoint*> point_of;
  for (int w = 0; w < nwin; ++w) {
    for (long pid : keyframe_of[static_cast<size_t>(w)]->point_id) {
      if (pid < 0 || !considered.insert(pid).second) continue;
      auto pt = points.find(pid);
      if (pt == points.end() || pt->second->observations() < 2) continue;
      prob.point_ids.push_back(pid);
      prob.points.push_back({pt->second->p_w});
      point_of.push_back(pt->second.get());
    }
  }
  // Observations; keyframes outside the window that see window points are fixed (gauge).
  for (size_t pi = 0; pi < point_of.size(); ++pi) {
    for (const auto& o : point_of[pi]->obs) {
      auto ki = kf_index.find(o.first);
      int kidx;
      if (ki != kf_index.end()) {
        kidx = ki->second;
      } else {
        auto k = keyframes.find(o.first);
        if (k == keyframes.end()) continue;
        kidx = static_cast<int>(prob.keyframe_ids.size());
        kf_index[o.first] = kidx;
        prob.keyframe_ids.push_back(o.first);
        keyframe_of.push_back(k->second.get());
        BAKeyframe b;
        b.T_c_w = k->second->T_c_w;
        b.fixed = true;
        prob.keyframes.push_back(b);
      }
      const Keyframe& kf = *keyframe_of[static_cast<size_t>(kidx)];
      const cv::KeyPoint& kp = kf.keypoints[o.second];
      prob.observations.push_back({kidx, static_cast<int>(pi), Eigen::Vector2d(kp.pt.x, kp.pt.y), kf.sigma(kp.octave)});
      prob.observation_keypoint.emplace_back(o.first, o.second);
      if (!stereo || kf.right_obs.empty() || !(kf.right_obs[o.second].z() > 0.f)) continue;
      const Eigen::Vector3f& r = kf.right_obs[o.second];
      BAObservation right{kidx, static_cast<int>(pi), Eigen::Vector2d(r.x(), r.y()), r.z()};
      right.right = true;
      prob.observations.push_back(right);
      prob.observation_keypoint.emplace_back(o.first, o.second);
    }
  }
  if (stereo) {  // 6-dof gauge: the scale is observed
    const bool anchored = std::any_of(prob.keyframes.begin(), prob.keyframes.end(),
                                      [](const BAKeyframe& k) { return k.fixed; });
    if (!anchored && nwin >= 1) prob.keyframes[static_cast<size_t>(nwin - 1)].fixed = true;
    return prob;
  }
  const bool anchored_outside = std::any_of(prob.keyframes.begin(), prob.keyframes.end(),
                                            [](const BAKeyframe& k) { return k.fixed; });
  if (!anchored_outside && nwin >= 2) {
    prob.scale_anchor = nwin - 1;
    prob.keyframes[static_cast<size_t>(nwin - 1)].fixed = true;
  } else {
    fixMonocularGauge(&prob.keyframes, nwin, min_fixed_span);
  }
  return prob;
}

void applyLocalBA(const LocalBAProblem& prob, const BASummary& summary, Map* map) {
  std::lock_guard<std::mutex> lk(map->mutex_);
  auto& keyframes = map->keyframes_;
  auto& points = map->points_;
  // correction[kf id] maps the pre-BA world to the optimized one for things anchored at that keyframe:
  // p_new = T_new^-1 * T_old * p_old (identity for fixed keyframes).
  std::unordered_map<long, Eigen::Isometry3d> correction;
  for (size_t k = 0; k < prob.keyframe_ids.size(); ++k) {
    if (prob.keyframes[k].fixed) continue;
    auto it = keyframes.find(prob.keyframe_ids[k]);
    if (it == keyframes.end()) continue;
    correction[it->first] = prob.keyframes[k].T_c_w.inverse() * it->second->T_c_w;
    it->second->T_c_w = prob.keyframes[k].T_c_w;
  }
  for (size_t i = 0; i < prob.point_ids.size(); ++i) {
    auto it = points.find(prob.point_ids[i]);
    if (it != points.end()) it->second->p_w = prob.points[i].p_w;
  }
  // Added while BA ran: keyframes (posed against the pre-BA map) follow the newest window keyframe; points
  // follow the keyframe that created them (if it was optimized) or the newest window keyframe.
  const auto newest = prob.keyframe_ids.empty() ? correction.end() : correction.find(prob.keyframe_ids[0]);
  if (newest != correction.end()) {
    const Eigen::Isometry3d C_newest = newest->second;
    for (auto it = keyframes.lower_bound(prob.next_keyframe_id); it != keyframes.end(); ++it) {
      it->second->T_c_w = it->second->T_c_w * C_newest.inverse();
      correction[it->first] = C_newest;
    }
  }
  if (!correction.empty()) {
    for (auto& kv : points) {
      if (kv.first < prob.next_point_id) continue;
      auto c = correction.find(kv.second->first_kf);
      if (c != correction.end()) kv.second->p_w = c->second * kv.second->p_w;
    }
  }
  for (size_t j = 0; j < prob.observations.size(); ++j) {
    if (!summary.outlier[j] || prob.observations[j].right) continue;  // a right outlier: the left one decides
    auto pt = points.find(prob.point_ids[prob.observations[j].point]);
    if (pt == points.end()) continue;
    const auto& [kf_id, kp] = prob.observation_keypoint[j];
    auto k = keyframes.find(kf_id);
    pt->second->obs.erase(kf_id);
    if (k != keyframes.end() && k->second->point_id[kp] == pt->first) k->second->point_id[kp] = -1;
    if (pt->second->obs.empty()) points.erase(pt);
  }
}

}  // namespace iraf_vo
