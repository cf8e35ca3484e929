#include "iraf_vo/tracking/map.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace iraf_vo {

std::shared_ptr<Keyframe> Keyframe::fromFrame(const Frame& f, const Eigen::Isometry3d& T_c_w) {
  auto kf = std::make_shared<Keyframe>();
  kf->frame_index = f.index;
  kf->stamp = f.stamp;
  kf->scale_factor = f.scale_factor;
  kf->T_c_w = T_c_w;
  kf->keypoints = f.keypoints;
  kf->descriptors = f.descriptors;
  kf->bearings = f.bearings;
  kf->valid = f.valid;
  kf->right_obs = f.right_obs;
  kf->point_id.assign(f.keypoints.size(), -1);
  return kf;
}

// ---------------------------------------------------------------------------------------------
// Creation
// ---------------------------------------------------------------------------------------------
// A new point created by keypoint kp of keyframe kf (its descriptor, octave and angle; its first observation).
MapPoint& Map::newPointLocked(const Eigen::Vector3d& p_w, Keyframe& kf, int kp) {
  auto mp = std::make_shared<MapPoint>();
  mp->id = next_point_id_++;
  mp->p_w = p_w;
  mp->desc = descriptorRow(kf.descriptors, kp);
  mp->octave = kf.keypoints[kp].octave;
  mp->angle = kf.keypoints[kp].angle;
  mp->obs[kf.id] = kp;
  mp->first_kf = kf.id;
  kf.point_id[kp] = mp->id;
  points_[mp->id] = mp;
  return *mp;
}

long Map::createPointLocked(const Eigen::Vector3d& p_w, Keyframe& a, int kp_a, Keyframe& b, int kp_b) {
  MapPoint& mp = newPointLocked(p_w, a, kp_a);
  mp.obs[b.id] = kp_b;
  b.point_id[kp_b] = mp.id;
  return mp.id;
}

long Map::createStereoPointLocked(const Eigen::Vector3d& p_w, Keyframe& kf, int kp) {
  MapPoint& mp = newPointLocked(p_w, kf, kp);
  mp.stereo_obs = 1;  // the right image of the same keyframe
  return mp.id;
}

bool Map::createStereoMap(const KeyframePtr& kf, const std::vector<StereoMapPoint>& points, int min_points,
                          int* created) {
  std::lock_guard<std::mutex> lk(mutex_);
  *created = static_cast<int>(points.size());
  if (*created < min_points) return false;
  kf->id = next_keyframe_id_++;
  for (const StereoMapPoint& sp : points) createStereoPointLocked(sp.p_w, *kf, sp.kp);
  keyframes_[kf->id] = kf;
  return true;
}

int Map::addStereoPoints(long kf_id, const std::vector<StereoMapPoint>& points) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto k = keyframes_.find(kf_id);
  if (k == keyframes_.end()) return 0;
  int n = 0;
  for (const StereoMapPoint& sp : points) {
    if (sp.kp < 0 || sp.kp >= static_cast<int>(k->second->point_id.size()) || k->second->point_id[sp.kp] >= 0)
      continue;
    recent_points_.push_back(createStereoPointLocked(sp.p_w, *k->second, sp.kp));
    ++n;
  }
  return n;
}

bool Map::createInitialMap(const KeyframePtr& kf0, const KeyframePtr& kf1, const std::vector<NewMapPoint>& points,
                           int min_points, int* created) {
  std::lock_guard<std::mutex> lk(mutex_);
  kf0->id = next_keyframe_id_++;
  kf1->id = next_keyframe_id_++;
  std::vector<long> ids;
  for (const NewMapPoint& np : points) ids.push_back(createPointLocked(np.p_w, *kf1, np.kp_a, *kf0, np.kp_b));
  *created = static_cast<int>(ids.size());
  if (*created < min_points) {
    for (long id : ids) points_.erase(id);  // roll back: the keyframes were never added
    return false;
  }
  keyframes_[kf0->id] = kf0;
  keyframes_[kf1->id] = kf1;
  return true;
}

long Map::addKeyframe(const Frame& f) {
  auto kf = Keyframe::fromFrame(f, f.T_c_w);
  std::lock_guard<std::mutex> lk(mutex_);
  kf->id = next_keyframe_id_++;
  for (size_t i = 0; i < f.point_id.size(); ++i) {
    if (f.point_id[i] < 0) continue;
    auto it = points_.find(f.point_id[i]);
    if (it == points_.end() || it->second->obs.count(kf->id)) continue;
    it->second->obs[kf->id] = static_cast<int>(i);
    kf->point_id[i] = f.point_id[i];
  }
  keyframes_[kf->id] = kf;
  return kf->id;
}

void Map::clear() {
  std::lock_guard<std::mutex> lk(mutex_);
  keyframes_.clear();
  points_.clear();
  recent_points_.clear();
}

// ---------------------------------------------------------------------------------------------
// Tracking thread
// ---------------------------------------------------------------------------------------------
std::vector<LocalPoint> Map::localPoints(const CameraModel* camera) const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<LocalPoint> out;
  out.reserve(points_.size());
  for (const auto& kv : points_) out.push_back(localPointLocked(*kv.second, camera));
  return out;
}

LocalPoint Map::localPointLocked(const MapPoint& mp, const CameraModel* camera) const {
  LocalPoint lp{mp.id, mp.p_w, mp.desc, mp.octave, mp.angle};
  lp.candidate = mp.candidate;
  if (!camera) return lp;  // no scale prediction: no reference (its lookups were ~2 % of the whole VO's CPU)
  for (const auto& [kf_id, kp] : mp.obs) {  // the oldest keyframe in the map that observes the point
    auto kf = keyframes_.find(kf_id);
    if (kf == keyframes_.end() || kp >= static_cast<int>(kf->second->keypoints.size())) continue;
    lp.ref_center = kf->second->T_c_w.inverse().translation();
    lp.ref_octave = kf->second->keypoints[kp].octave;
    lp.has_ref = true;
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    if (camera->project(kf->second->T_c_w * mp.p_w, &uv, &J)) lp.ref_scale = imageScale(J);
    break;
  }
  return lp;
}

double imageScale(const Eigen::Matrix<double, 2, 3>& J) {
  const double det = (J * J.transpose()).determinant();
  return det > 0 ? std::sqrt(std::sqrt(det)) : 0.0;
}

bool predictOctave(const LocalPoint& lp, const Eigen::Vector3d& center, double scale, double scale_factor, int* octave) {
  *octave = lp.octave;
  if (!lp.has_ref) return true;
  const Eigen::Vector3d ref_ray = lp.p_w - lp.ref_center, ray = lp.p_w - center;
  const double d_ref = ref_ray.norm(), d = ray.norm();
  if (d_ref <= 1e-9 || d <= 1e-9) return true;
  if (ref_ray.dot(ray) < 0.5 * d_ref * d) return false;  // viewing angle > 60 deg
  const double ratio = (scale > 0 && lp.ref_scale > 0) ? scale / lp.ref_scale : d_ref / d;
  const double level = lp.ref_octave + std::log(ratio) / std::log(scale_factor);
  if (level < -1.0) return false;  // farther than octave 0 resolves
  *octave = std::max(0, static_cast<int>(std::lround(level)));
  return true;
}

bool Map::keyframePose(long id, Eigen::Isometry3d* T_c_w) const {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = keyframes_.find(id);
  if (it == keyframes_.end()) return false;
  *T_c_w = it->second->T_c_w;
  return true;
}

std::vector<std::vector<long>> Map::pointsByKeyframe() const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<std::vector<long>> out;
  for (auto it = keyframes_.rbegin(); it != keyframes_.rend(); ++it) {
    out.emplace_back();
    for (long id : it->second->point_id)
      if (id >= 0 && points_.count(id)) out.back().push_back(id);
  }
  return out;
}

void Map::countVisibility(const std::vector<LocalPoint>& local, const std::vector<char>& visible,
                          const std::vector<int>& keypoint_of_point) {
  std::lock_guard<std::mutex> lk(mutex_);
  for (size_t li = 0; li < local.size(); ++li) {
    if (!visible[li] && keypoint_of_point[li] < 0) continue;
    auto it = points_.find(local[li].id);
    if (it == points_.end()) continue;
    it->second->visible++;
    if (keypoint_of_point[li] >= 0) it->second->found++;
  }
}

int Map::trackedPoints(long kf_id, size_t min_observations, double max_depth, int* nearer) const {
  std::lock_guard<std::mutex> lk(mutex_);
  int n = 0;
  if (nearer) *nearer = 0;
  auto it = keyframes_.find(kf_id);
  if (it == keyframes_.end()) return 0;
  const Keyframe& kf = *it->second;
  for (long pid : kf.point_id) {
    if (pid < 0) continue;
    auto pt = points_.find(pid);
    if (pt == points_.end() || pt->second->observations() < min_observations || pt->second->candidate) continue;
    ++n;
    if (nearer) {
      const double z = (kf.T_c_w * pt->second->p_w).z();
      if (z > 0 && z < max_depth) ++*nearer;
    }
  }
  return n;
}

long Map::mostCovisibleKeyframe(const std::vector<long>& ids, long fallback) const {
  std::lock_guard<std::mutex> lk(mutex_);
  const std::vector<std::pair<int, long>> order = covisibilityLocked(ids, -1);
  return order.empty() ? fallback : order.front().second;
}

std::vector<std::pair<int, long>> Map::covisibilityLocked(const std::vector<long>& ids, long exclude,
                                                          bool fill_recent) const {
  std::map<long, int> shared;
  for (long pid : ids) {
    auto pt = pid < 0 ? points_.end() : points_.find(pid);
    if (pt == points_.end()) continue;
    for (const auto& o : pt->second->obs)
      if (o.first != exclude) shared[o.first]++;
  }
  std::vector<std::pair<int, long>> order;
  for (const auto& c : shared) order.emplace_back(c.second, c.first);
  std::sort(order.rbegin(), order.rend());
  for (auto k = keyframes_.rbegin(); fill_recent && k != keyframes_.rend(); ++k)
    if (k->first != exclude && !shared.count(k->first)) order.emplace_back(0, k->first);
  return order;
}

int Map::pointsNearerThan(const std::vector<long>& ids, const Eigen::Isometry3d& T_c_w, double max_depth) const {
  std::lock_guard<std::mutex> lk(mutex_);
  int n = 0;
  for (long pid : ids) {
    if (pid < 0) continue;
    auto pt = points_.find(pid);
    if (pt == points_.end() || pt->second->candidate) continue;
    const double z = (T_c_w * pt->second->p_w).z();
    if (z > 0 && z < max_depth) ++n;
  }
  return n;
}

// ---------------------------------------------------------------------------------------------
// Local mapping
// ---------------------------------------------------------------------------------------------
void Map::erasePointLocked(long id) {
  auto it = points_.find(id);
  if (it == points_.end()) return;
  for (const auto& o : it->second->obs) {
    auto k = keyframes_.find(o.first);
    if (k != keyframes_.end() && o.second < static_cast<int>(k->second->point_id.size()) &&
        k->second->point_id[o.second] == id)
      k->second->point_id[o.second] = -1;
  }
  points_.erase(it);
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

void Map::cullRecentPoints(long current_kf, double min_found_ratio) {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<long> keep;
  for (long pid : recent_points_) {
    auto it = points_.find(pid);
    if (it == points_.end()) continue;
    const MapPoint& mp = *it->second;
    const long age = current_kf - mp.first_kf;
    if (static_cast<double>(mp.found) / std::max(1, mp.visible) < min_found_ratio) {
      erasePointLocked(pid);
    } else if (age >= 2 && mp.observations() <= 2) {
      erasePointLocked(pid);
    } else if (age < 3) {
      keep.push_back(pid);
    }
  }
  recent_points_.swap(keep);
}

void Map::updateDescriptors(long kf_id) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto k = keyframes_.find(kf_id);
  if (k == keyframes_.end()) return;
  std::vector<const uint8_t*> d;
  std::vector<int> dist, row;
  for (long pid : k->second->point_id) {
    if (pid < 0) continue;
    auto pt = points_.find(pid);
    if (pt == points_.end() || pt->second->obs.size() < 3) continue;
    d.clear();
    for (const auto& o : pt->second->obs) {
      auto ko = keyframes_.find(o.first);
      if (ko != keyframes_.end()) d.push_back(ko->second->descriptors.ptr<uint8_t>(o.second));
    }
    const size_t n = d.size();
    if (n < 3) continue;
    // The observation with the least median distance to the others.
    dist.assign(n * n, 0);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) dist[i * n + j] = dist[j * n + i] = hammingDistance(d[i], d[j]);
    int best = 1 << 30;
    size_t best_i = 0;
    row.resize(n);
    for (size_t i = 0; i < n; ++i) {
      std::copy(dist.begin() + i * n, dist.begin() + (i + 1) * n, row.begin());
      std::nth_element(row.begin(), row.begin() + n / 2, row.end());
      if (row[n / 2] < best) {
        best = row[n / 2];
        best_i = i;
      }
    }
    std::memcpy(pt->second->desc.data(), d[best_i], 32);
  }
}

bool Map::claimForTriangulation(long kf_id, int num_neighbors, TriangulationInput* in) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = keyframes_.find(kf_id);
  if (it == keyframes_.end()) return false;
  in->keyframe = it->second;
  if (in->keyframe->triangulated.exchange(true)) return false;  // done already (tracker or mapping thread)
  in->point_id = in->keyframe->point_id;
  in->T_c_w = in->keyframe->T_c_w;
  std::vector<double> depths;
  for (long pid : in->point_id) {
    auto pt = pid < 0 ? points_.end() : points_.find(pid);
    if (pt != points_.end()) depths.push_back((in->T_c_w * pt->second->p_w).z());
  }
  in->median_depth = 1.0;
  if (!depths.empty()) {
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    in->median_depth = depths[depths.size() / 2];
  }
  in->neighbors.clear();
  for (const auto& o : covisibilityLocked(in->point_id, kf_id, true)) {
    if (static_cast<int>(in->neighbors.size()) >= num_neighbors) break;
    auto k = keyframes_.find(o.second);
    if (k == keyframes_.end()) continue;
    in->neighbors.push_back({k->second, k->second->T_c_w, k->second->point_id});
  }
  return true;
}

void Map::addTriangulatedPoints(const std::vector<NewMapPoint>& points) {
  std::lock_guard<std::mutex> lk(mutex_);
  for (const NewMapPoint& np : points) {
    auto ka = keyframes_.find(np.kf_a);
    auto kb = keyframes_.find(np.kf_b);
    if (ka == keyframes_.end() || kb == keyframes_.end()) continue;
    if (ka->second->point_id[np.kp_a] >= 0 || kb->second->point_id[np.kp_b] >= 0) continue;
    const long id = createPointLocked(np.p_w, *ka->second, np.kp_a, *kb->second, np.kp_b);
    points_[id]->candidate = np.candidate;
    recent_points_.push_back(id);
  }
}

int Map::promoteCandidates(const std::vector<long>& point_ids, double cos_gate) {
  std::lock_guard<std::mutex> lk(mutex_);
  int promoted = 0;
  std::vector<Eigen::Vector3d> rays;
  for (long pid : point_ids) {
    auto pt = points_.find(pid);
    if (pt == points_.end() || !pt->second->candidate) continue;
    MapPoint& mp = *pt->second;
    rays.clear();
    for (const auto& o : mp.obs) {
      auto kf = keyframes_.find(o.first);
      if (kf != keyframes_.end()) rays.push_back((mp.p_w - kf->second->T_c_w.inverse().translation()).normalized());
    }
    bool wide = false;
    for (size_t a = 0; a < rays.size() && !wide; ++a)
      for (size_t b = a + 1; b < rays.size() && !wide; ++b) wide = rays[a].dot(rays[b]) <= cos_gate;
    if (!wide) continue;
    mp.candidate = false;
    ++promoted;
  }
  return promoted;
}

void Map::dropOldKeyframes(int max_keyframes) {
  std::lock_guard<std::mutex> lk(mutex_);
  while (static_cast<int>(keyframes_.size()) > max_keyframes) {
    auto it = keyframes_.begin();
    const Keyframe& kf = *it->second;
    for (size_t i = 0; i < kf.point_id.size(); ++i) {
      const long pid = kf.point_id[i];
      if (pid < 0) continue;
      auto pt = points_.find(pid);
      if (pt == points_.end()) continue;
      pt->second->obs.erase(kf.id);
      if (pt->second->obs.empty()) points_.erase(pt);
    }
    keyframes_.erase(it);
  }
}

// ---------------------------------------------------------------------------------------------
// Queries
// ---------------------------------------------------------------------------------------------
std::vector<Eigen::Vector3d> Map::pointPositions() const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<Eigen::Vector3d> out;
  out.reserve(points_.size());
  for (const auto& kv : points_) out.push_back(kv.second->p_w);
  return out;
}

std::vector<KeyframePose> Map::keyframePoses() const {
  std::lock_guard<std::mutex> lk(mutex_);
  std::vector<KeyframePose> out;
  for (const auto& kv : keyframes_) out.push_back({kv.first, kv.second->stamp, kv.second->T_c_w.inverse()});
  return out;
}

size_t Map::numKeyframes() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return keyframes_.size();
}

size_t Map::numPoints() const {
  std::lock_guard<std::mutex> lk(mutex_);
  return points_.size();
}

}  // namespace iraf_vo
