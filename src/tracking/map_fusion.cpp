// Map-point fusion on the map's side (map_fusion.h). ROS-free.
#include "iraf_vo/tracking/map_fusion.h"

#include <algorithm>
#include <unordered_set>

namespace iraf_vo {

std::vector<FusionTarget> fusionTargets(const Map& map, long kf_id, int num_neighbors, const CameraModel* camera) {
  std::lock_guard<std::mutex> lk(map.mutex_);
  const auto& keyframes = map.keyframes_;
  const auto& points = map.points_;
  std::vector<FusionTarget> out;
  auto it = keyframes.find(kf_id);
  if (it == keyframes.end() || num_neighbors <= 0) return out;
  const Keyframe& kf = *it->second;
  std::vector<const MapPoint*> own;
  for (long pid : kf.point_id) {
    auto pt = pid < 0 ? points.end() : points.find(pid);
    if (pt != points.end()) own.push_back(pt->second.get());
  }
  // Covisibility: shared points per other keyframe; most shared first, then the most recent.
  std::vector<std::pair<int, long>> order = map.covisibilityLocked(kf.point_id, kf_id);
  if (static_cast<int>(order.size()) > num_neighbors) order.resize(num_neighbors);

  FusionTarget self{it->second, kf.T_c_w, kf.point_id, {}};
  std::unordered_set<long> seen(kf.point_id.begin(), kf.point_id.end());
  for (const auto& o : order) {
    auto k = keyframes.find(o.second);
    if (k == keyframes.end()) continue;
    const Keyframe& nb = *k->second;
    FusionTarget t{k->second, nb.T_c_w, nb.point_id, {}};
    const std::unordered_set<long> nb_points(nb.point_id.begin(), nb.point_id.end());
    for (const MapPoint* mp : own)
      if (!nb_points.count(mp->id)) t.candidates.push_back(map.localPointLocked(*mp, camera));
    out.push_back(std::move(t));
    for (long pid : nb.point_id) {  // the neighbor's points, into the keyframe
      if (pid < 0 || !seen.insert(pid).second) continue;
      auto pt = points.find(pid);
      if (pt != points.end()) self.candidates.push_back(map.localPointLocked(*pt->second, camera));
    }
  }
  out.insert(out.begin(), std::move(self));
  return out;
}

std::pair<int, int> applyFusion(const std::vector<FusionLink>& links, Map* map) {
  std::lock_guard<std::mutex> lk(map->mutex_);
  auto& keyframes = map->keyframes_;
  auto& points = map->points_;
  int added = 0, merged = 0;
  for (const FusionLink& l : links) {
    auto k = keyframes.find(l.kf_id);
    auto pt = points.find(l.point_id);
    if (k == keyframes.end() || pt == points.end()) continue;
    Keyframe& kf = *k->second;
    MapPoint* p = pt->second.get();
    if (l.kp < 0 || l.kp >= static_cast<int>(kf.point_id.size()) || p->obs.count(kf.id)) continue;
    const long q_id = kf.point_id[l.kp];
    auto q = q_id >= 0 ? points.find(q_id) : points.end();
    if (q == points.end()) {
      kf.point_id[l.kp] = p->id;
      p->obs[kf.id] = l.kp;
      ++added;
      continue;
    }
    // Two points for one keypoint: keep the better observed one (the older on ties).
    MapPoint* other = q->second.get();
    const bool keep_p = p->obs.size() > other->obs.size() || (p->obs.size() == other->obs.size() && p->id < other->id);
    MapPointPtr hold = keep_p ? q->second : pt->second;  // alive until the merge is done
    if (keep_p) map->mergePointsLocked(p, other);
    else map->mergePointsLocked(other, p);
    ++merged;
  }
  return {added, merged};
}

}  // namespace iraf_vo
