// Map-point fusion on the map's side (map.h: fusionTargets, fuse): what to project where, copied under the
// lock, and the observations / merges the projection search found. ROS-free.
//
// Without it a point gains observations only from the frame that becomes a keyframe; a point that frame
// missed is triangulated again from other keyframes, as a duplicate with two observations. Fusion (ORB-SLAM's
// LocalMapping::SearchInNeighbors) links such keypoints to the existing point, so the local BA sees one point
// with many views instead of several weakly constrained ones.
#include <iraf_vo/tracking/map.h>

#include <algorithm>
#include <unordered_set>

namespace iraf_vo {

std::vector<FusionTarget> Map::fusionTargets(long kf_id, int num_neighbors, const CameraModel* camera) const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<FusionTarget> out;
  auto it = keyframes_.find(kf_id);
  if (it == keyframes_.end() || num_neighbors <= 0) return out;
  const Keyframe& kf = *it->second;
  // Covisibility: shared points per other keyframe; most shared first, then the most recent.
  std::map<long, int> covisibility;
  std::vector<const MapPoint*> own;
  for (long pid : kf.point_id) {
    if (pid < 0) continue;
    auto pt = points_.find(pid);
    if (pt == points_.end()) continue;
    own.push_back(pt->second.get());
    for (const auto& o : pt->second->obs)
      if (o.first != kf_id) covisibility[o.first]++;
  }
  std::vector<std::pair<int, long>> order;
  for (const auto& c : covisibility) order.emplace_back(c.second, c.first);
  std::sort(order.rbegin(), order.rend());
  if (static_cast<int>(order.size()) > num_neighbors) order.resize(num_neighbors);

  FusionTarget self{it->second, kf.T_c_w, kf.point_id, {}};
  std::unordered_set<long> seen(kf.point_id.begin(), kf.point_id.end());
  for (const auto& o : order) {
    auto k = keyframes_.find(o.second);
    if (k == keyframes_.end()) continue;
    const Keyframe& nb = *k->second;
    FusionTarget t{k->second, nb.T_c_w, nb.point_id, {}};
    const std::unordered_set<long> nb_points(nb.point_id.begin(), nb.point_id.end());
    for (const MapPoint* mp : own)
      if (!nb_points.count(mp->id)) t.candidates.push_back(localPointLocked(*mp, camera));
    out.push_back(std::move(t));
    for (long pid : nb.point_id) {  // the neighbor's points, into the keyframe
      if (pid < 0 || !seen.insert(pid).second) continue;
      auto pt = points_.find(pid);
      if (pt != points_.end()) self.candidates.push_back(localPointLocked(*pt->second, camera));
    }
  }
  out.insert(out.begin(), std::move(self));
  return out;
}

void Map::mergePointsLocked(MapPoint* keep, MapPoint* gone) {
  for (const auto& o : gone->obs) {
    auto k = keyframes_.find(o.first);
    if (k == keyframes_.end()) continue;
    std::vector<long>& ids = k->second->point_id;
    if (o.second >= static_cast<int>(ids.size()) || ids[o.second] != gone->id) continue;
    if (keep->obs.count(o.first)) {
      ids[o.second] = -1;  // the keyframe shows the kept point at another keypoint already
    } else {
      ids[o.second] = keep->id;
      keep->obs[o.first] = o.second;
    }
  }
  keep->visible += gone->visible;
  keep->found += gone->found;
  points_.erase(gone->id);
}

std::pair<int, int> Map::fuse(const std::vector<FusionLink>& links) {
  std::lock_guard<std::mutex> lk(mutex_);
  int added = 0, merged = 0;
  for (const FusionLink& l : links) {
    auto k = keyframes_.find(l.kf_id);
    auto pt = points_.find(l.point_id);
    if (k == keyframes_.end() || pt == points_.end()) continue;
    Keyframe& kf = *k->second;
    MapPoint* p = pt->second.get();
    if (l.kp < 0 || l.kp >= static_cast<int>(kf.point_id.size()) || p->obs.count(kf.id)) continue;
    const long q_id = kf.point_id[l.kp];
    auto q = q_id >= 0 ? points_.find(q_id) : points_.end();
    if (q == points_.end()) {
      kf.point_id[l.kp] = p->id;
      p->obs[kf.id] = l.kp;
      ++added;
      continue;
    }
    // Two points for one keypoint: keep the better observed one (the older on ties).
    MapPoint* other = q->second.get();
    const bool keep_p = p->obs.size() > other->obs.size() || (p->obs.size() == other->obs.size() && p->id < other->id);
    MapPointPtr hold = keep_p ? q->second : pt->second;  // alive until the merge is done
    if (keep_p) mergePointsLocked(p, other);
    else mergePointsLocked(other, p);
    ++merged;
  }
  return {added, merged};
}

}  // namespace iraf_vo
