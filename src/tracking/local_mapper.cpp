#include "iraf_vo/tracking/local_mapper.h"

#include "iraf_vo/common/cpu_clock.h"
#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/local_ba.h"
#include "iraf_vo/tracking/map_fusion.h"
#include "iraf_vo/tracking/multiview.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace iraf_vo {

LocalMapper::LocalMapper(const CameraModel& camera, const TrackerParams& params, Map* map)
    : cam_(camera), p_(params), map_(map), matcher_(camera, params) {
  if (p_.mapping_thread) thread_ = std::thread([this] { run(); });
}

LocalMapper::~LocalMapper() {
  {
    std::lock_guard<std::mutex> lk(queue_mutex_);
    stop_ = true;
    abort_ba_ = true;
  }
  queue_cv_.notify_all();
  idle_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

long LocalMapper::addKeyframe(const Frame& f, const std::vector<StereoMapPoint>& stereo) {
  waitUntilIdle();  // the running BA took its window before this keyframe exists (the same window every run)
  const long kf_id = map_->addKeyframe(f);
  if (!stereo.empty()) map_->addStereoPoints(kf_id, stereo);
  acceptKeyframe(kf_id);
  return kf_id;
}

void LocalMapper::acceptKeyframe(long kf_id) {
  if (p_.mapping_thread) {
    commitPendingBA();
    map_->dropOldKeyframes(p_.max_map_keyframes);
  }
  mapKeyframe(kf_id);
}

void LocalMapper::insertKeyframe(long kf_id) {
  if (!p_.mapping_thread) {
    localBundleAdjustment();
    map_->dropOldKeyframes(p_.max_map_keyframes);
    return;
  }
  {
    std::lock_guard<std::mutex> lk(queue_mutex_);
    queue_.push_back(kf_id);
  }
  queue_cv_.notify_one();
}

bool LocalMapper::idle() const {
  std::lock_guard<std::mutex> lk(queue_mutex_);
  return queue_.empty() && !busy_;
}

void LocalMapper::waitUntilIdle() {
  if (!p_.mapping_thread) return;
  std::unique_lock<std::mutex> lk(queue_mutex_);
  idle_cv_.wait(lk, [this] { return stop_ || (queue_.empty() && !busy_); });
}

void LocalMapper::clearQueue() {
  {
    std::lock_guard<std::mutex> lk(queue_mutex_);
    queue_.clear();
    abort_ba_ = true;
  }
  waitUntilIdle();
  std::lock_guard<std::mutex> lk(queue_mutex_);
  pending_ba_.reset();
}

LocalMapperStats LocalMapper::stats() const {
  std::lock_guard<std::mutex> lk(stats_mutex_);
  return stats_;
}

void LocalMapper::run() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lk(queue_mutex_);
      queue_cv_.wait(lk, [this] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      queue_.pop_front();
      busy_ = true;
      abort_ba_ = false;
    }
    localBundleAdjustment();
    {
      std::lock_guard<std::mutex> lk(queue_mutex_);
      busy_ = false;
    }
    idle_cv_.notify_all();
  }
}

void LocalMapper::mapKeyframe(long kf_id) {
  map_->cullRecentPoints(kf_id, p_.min_found_ratio);
  map_->updateDescriptors(kf_id);
  createNewMapPoints(kf_id);
}

void LocalMapper::commitPendingBA() {
  waitUntilIdle();
  std::unique_ptr<PendingBA> done;
  {
    std::lock_guard<std::mutex> lk(queue_mutex_);
    done.swap(pending_ba_);
  }
  if (!done) return;
  applyLocalBA(done->problem, done->summary, map_);
  promoteCandidates(done->problem);
  recordScaleChange(done->extent_before, done->problem);
}

// A corner found at octave o from distance d is found at octave 0 from d * sigma(o): a true match has
// d1 * sigma1 ~= d2 * sigma2, i.e. d2 / d1 ~= sigma1 / sigma2; a wrong epipolar match triangulated at the wrong
// depth need not. Tolerance: a factor 1.5 x scale_factor either way.
bool scaleConsistent(double d1, double d2, double octave_ratio, double scale_factor) {
  if (!(d1 > 0.0) || !(d2 > 0.0)) return false;
  const double distance_ratio = d2 / d1, tolerance = 1.5 * scale_factor;
  return distance_ratio * tolerance >= octave_ratio && distance_ratio <= octave_ratio * tolerance;
}

void LocalMapper::createNewMapPoints(long kf_id) {
  TriangulationInput in;
  if (!map_->claimForTriangulation(kf_id, p_.num_triangulation_neighbors, &in)) return;
  const Keyframe& kf = *in.keyframe;
  const Eigen::Isometry3d& T1 = in.T_c_w;
  const Eigen::Vector3d c1 = T1.inverse().translation();
  std::vector<NewMapPoint> created;
  std::vector<char> used1(kf.keypoints.size(), 0);
  for (size_t i = 0; i < in.point_id.size(); ++i) used1[i] = in.point_id[i] >= 0 || !kf.valid[i];
  const double cos_min_parallax = std::cos(p_.min_triangulation_parallax_deg * M_PI / 180.0);
  const double cos_candidate_parallax =
      std::cos(p_.candidate_parallax_ratio * p_.min_triangulation_parallax_deg * M_PI / 180.0);
  // Keypoint -> its widest candidate (below the gate) and that neighbour; made a point only if no neighbour gives
  // the keypoint an ordinary one.
  struct Candidate {
    NewMapPoint point;
    double cos_parallax;
    TriangulationNeighbor* neighbor;
  };
  std::map<int, Candidate> candidate_of;
  for (TriangulationNeighbor& nb : in.neighbors) {
    const Eigen::Vector3d c2 = nb.T_c_w.inverse().translation();
    if ((c2 - c1).norm() / in.median_depth < 0.01) continue;  // baseline too small
    const Keyframe& kf2 = *nb.keyframe;
    const std::vector<int> match_of_2 = matcher_.searchForTriangulation(kf, used1, kf2, nb.point_id, nb.T_c_w * T1.inverse());
    for (size_t j = 0; j < match_of_2.size(); ++j) {
      const int i = match_of_2[j];
      if (i < 0 || used1[i]) continue;
      Eigen::Vector3d X;
      if (!triangulateBearings(T1, kf.bearings[i], nb.T_c_w, kf2.bearings[j], &X)) continue;
      const double cos_parallax = (X - c1).normalized().dot((X - c2).normalized());
      const bool candidate = cos_parallax > cos_min_parallax;
      if (candidate && cos_parallax > cos_candidate_parallax) continue;
      const cv::KeyPoint& kp1 = kf.keypoints[i];
      const cv::KeyPoint& kp2 = kf2.keypoints[j];
      const double s1 = kf.sigma(kp1.octave), s2 = kf2.sigma(kp2.octave);
      if (!scaleConsistent((X - c1).norm(), (X - c2).norm(), s1 / s2, kf.scale_factor)) continue;
      const double e1 = reprojectionError2(cam_, T1, X, Eigen::Vector2d(kp1.pt.x, kp1.pt.y));
      const double e2 = reprojectionError2(cam_, nb.T_c_w, X, Eigen::Vector2d(kp2.pt.x, kp2.pt.y));
      if (e1 < 0 || e2 < 0 || e1 > kChi2TwoDof * s1 * s1 || e2 > kChi2TwoDof * s2 * s2) continue;
      const NewMapPoint np{X, kf_id, i, kf2.id, static_cast<int>(j), candidate};
      if (candidate) {
        auto it = candidate_of.find(i);
        if (it == candidate_of.end() || cos_parallax < it->second.cos_parallax) candidate_of[i] = {np, cos_parallax, &nb};
        continue;
      }
      used1[i] = 1;
      nb.point_id[j] = -2;  // taken
      created.push_back(np);
    }
  }
  for (const auto& [i, c] : candidate_of) {  // in keypoint order
    long& taken = c.neighbor->point_id[static_cast<size_t>(c.point.kp_b)];
    if (used1[i] || taken == -2) continue;
    used1[i] = 1;
    taken = -2;
    created.push_back(c.point);
  }
  map_->addTriangulatedPoints(created);
  fuseMapPoints(kf_id);
}

void LocalMapper::fuseMapPoints(long kf_id) {
  if (p_.fuse_neighbors <= 0) return;
  std::vector<FusionLink> links;
  for (const FusionTarget& t : fusionTargets(*map_, kf_id, p_.fuse_neighbors, p_.predict_scale ? &cam_ : nullptr)) {
    const std::vector<FusionLink> l = matcher_.searchForFusion(t, p_.fuse_radius_px);
    links.insert(links.end(), l.begin(), l.end());
  }
  applyFusion(links, map_);
}

void LocalMapper::localBundleAdjustment() {
  const double cpu0 = threadCpuMs();
  LocalBAProblem prob = buildLocalBAProblem(*map_, p_.ba_window_size, p_.ba_min_fixed_span, rig_ != nullptr);
  if (prob.observations.empty()) return;
  BAOptions options;
  // A stereo map: its cost falls by < 0.1 % per iteration after ~4 (far points creeping in depth), and 10
  // iterations instead of 5 changed EuRoC's ATE by < 0.1 mm at twice the BA time.
  options.max_num_iterations = rig_ ? p_.stereo_ba_max_iterations : p_.ba_max_num_iterations;
  // The time budget is CPU time of this thread: a wall-clock budget shrinks with the machine's load (at a load
  // of ~10 on 2 cores BA stopped after 0-1 iterations, the map stayed unoptimized and the scale drifted / collapsed
  // in some runs). The wall clock only bounds pathological cases.
  options.max_cpu_seconds = p_.ba_max_solver_time_in_seconds;
  options.max_solver_time_in_seconds = std::max(2.0, 20.0 * p_.ba_max_solver_time_in_seconds);
  options.huber_delta = p_.ba_huber_delta;
  options.use_ceres = p_.ba_use_ceres;
  options.abort = p_.mapping_thread ? &abort_ba_ : nullptr;
  if (rig_) {
    options.right_camera = rig_->right.get();
    options.T_r_l = rig_->T_r_l;
  }
  BASummary summary;
  const double before = windowExtent(prob);
  const double baseline = anchorBaseline(prob);
  const bool ok = bundleAdjust(cam_, &prob.keyframes, &prob.points, prob.observations, options, &summary);
  if (ok && prob.scale_anchor >= 0) holdScaleAboutAnchor(&prob, baseline);
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.ba_runs++;
    stats_.ba_ms_total += summary.ms;
    stats_.ba_cpu_ms_total += threadCpuMsSince(cpu0);
    stats_.ba_final_rmse_px = summary.final_rmse_px;
  }
  if (!ok) return;
  if (p_.mapping_thread) {  // written back by the tracking thread at its next keyframe (acceptKeyframe)
    std::lock_guard<std::mutex> lk(queue_mutex_);
    pending_ba_.reset(new PendingBA{std::move(prob), std::move(summary), before});
    return;
  }
  auto update = map_->lockUpdates();
  applyLocalBA(prob, summary, map_);
  promoteCandidates(prob);
  recordScaleChange(before, prob);
}

void LocalMapper::promoteCandidates(const LocalBAProblem& prob) {
  if (p_.candidate_parallax_ratio >= 1.0) return;
  map_->promoteCandidates(prob.point_ids, std::cos(p_.min_triangulation_parallax_deg * M_PI / 180.0));
}

void LocalMapper::recordScaleChange(double extent_before, const LocalBAProblem& after) {
  const double extent_after = windowExtent(after);
  if (!(extent_before > 1e-12) || !(extent_after > 0)) return;
  const double change = extent_after / extent_before;
  std::lock_guard<std::mutex> lk(scale_mutex_);
  if (std::max(change, 1.0 / change) > std::max(scale_change_, 1.0 / scale_change_)) scale_change_ = change;
}

double LocalMapper::takeScaleChange() {
  std::lock_guard<std::mutex> lk(scale_mutex_);
  const double c = scale_change_;
  scale_change_ = 1.0;
  return c;
}

}  // namespace iraf_vo
