#include <iraf_vo/tracking/tracker.h>

#include <opencv2/features2d.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <unordered_map>

namespace iraf_vo {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

using Desc = std::array<uint8_t, 32>;

inline int hamming(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int k = 0; k < 4; ++k) {
    uint64_t x, y;
    std::memcpy(&x, a + 8 * k, 8);
    std::memcpy(&y, b + 8 * k, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

constexpr double kChi2 = 5.991;  // 2 dof, 95 %

struct Frame {
  long index = 0;
  double stamp = 0.0;
  std::vector<cv::KeyPoint> kps;
  double scale_factor = 1.2;  // pyramid scale of kps (FeatureFrame::scale_factor)
  cv::Mat desc;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<char> valid;
  std::vector<long> point_id;  // matched map point, -1 if none
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  // pixel grid for window searches
  double cell = 32.0;
  int cols = 0, rows = 0;
  std::vector<std::vector<int>> grid;

  void buildGrid(int width, int height) {
    cols = std::max(1, static_cast<int>(std::ceil(width / cell)));
    rows = std::max(1, static_cast<int>(std::ceil(height / cell)));
    grid.assign(static_cast<size_t>(cols * rows), {});
    for (size_t i = 0; i < kps.size(); ++i) {
      if (!valid[i]) continue;
      const int cx = std::clamp(static_cast<int>(kps[i].pt.x / cell), 0, cols - 1);
      const int cy = std::clamp(static_cast<int>(kps[i].pt.y / cell), 0, rows - 1);
      grid[static_cast<size_t>(cy * cols + cx)].push_back(static_cast<int>(i));
    }
  }
  void featuresInArea(double u, double v, double r, int min_oct, int max_oct, std::vector<int>* out) const {
    out->clear();
    const int x0 = std::max(0, static_cast<int>((u - r) / cell)), x1 = std::min(cols - 1, static_cast<int>((u + r) / cell));
    const int y0 = std::max(0, static_cast<int>((v - r) / cell)), y1 = std::min(rows - 1, static_cast<int>((v + r) / cell));
    const double r2 = r * r;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        for (int i : grid[static_cast<size_t>(y * cols + x)]) {
          const cv::KeyPoint& kp = kps[i];
          if (kp.octave < min_oct || kp.octave > max_oct) continue;
          const double du = kp.pt.x - u, dv = kp.pt.y - v;
          if (du * du + dv * dv <= r2) out->push_back(i);
        }
  }
};

struct MapPoint {
  long id = 0;
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();
  Desc desc{};
  int octave = 0;
  float angle = -1.f;
  std::map<long, int> obs;  // keyframe id -> keypoint index
  long first_kf = 0;
  int visible = 1, found = 1;
};

struct Keyframe {
  long id = 0;
  long frame_index = 0;
  double stamp = 0.0;
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  std::vector<cv::KeyPoint> kps;  // immutable after creation
  double scale_factor = 1.2;      // pyramid scale of kps
  cv::Mat desc;
  std::vector<Eigen::Vector3d> bearings;
  std::vector<char> valid;
  std::vector<long> point_id;  // guarded by the map mutex
  std::atomic<bool> triangulated{false};  // new points already created (by the mapping thread or a starving tracker)
};

using KfPtr = std::shared_ptr<Keyframe>;
using MpPtr = std::shared_ptr<MapPoint>;

struct LocalPoint {
  long id;
  Eigen::Vector3d p_w;
  Desc desc;
  int octave;
  float angle;
};

Desc descRow(const cv::Mat& d, int r) {
  Desc out;
  std::memcpy(out.data(), d.ptr<uint8_t>(r), 32);
  return out;
}

// Rotation-consistency (ORB-SLAM): keep matches whose keypoint-angle difference falls into the 3 most
// populated of 30 bins (2nd / 3rd only if >= 10 % of the 1st). Matches without angles are kept.
std::vector<char> rotationConsistent(const std::vector<float>& dangle) {
  constexpr int kBins = 30;
  std::array<std::vector<int>, kBins> hist;
  std::vector<char> keep(dangle.size(), 1);
  for (size_t i = 0; i < dangle.size(); ++i) {
    if (dangle[i] < -1000.f) continue;
    float a = std::fmod(dangle[i], 360.f);
    if (a < 0) a += 360.f;
    int b = static_cast<int>(std::lround(a * kBins / 360.f)) % kBins;
    hist[b].push_back(static_cast<int>(i));
  }
  std::array<int, kBins> order;
  for (int b = 0; b < kBins; ++b) order[b] = b;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return hist[a].size() > hist[b].size(); });
  const size_t max1 = hist[order[0]].size();
  std::array<char, kBins> good{};
  good[order[0]] = 1;
  if (hist[order[1]].size() >= 0.1 * max1) good[order[1]] = 1;
  if (hist[order[2]].size() >= 0.1 * max1) good[order[2]] = 1;
  for (int b = 0; b < kBins; ++b)
    if (!good[b])
      for (int i : hist[b]) keep[i] = 0;
  return keep;
}

double octaveSigma(double scale_factor, int octave) { return std::pow(scale_factor, std::max(0, octave)); }

}  // namespace

const char* toString(TrackingState s) {
  switch (s) {
    case TrackingState::kNotInitialized: return "not_initialized";
    case TrackingState::kInitializing: return "initializing";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
  }
  return "?";
}

struct Tracker::Impl {
  CameraModelPtr cam;
  TrackerParams p;

  // ---- map (guarded by map_mutex) ----
  mutable std::mutex map_mutex;
  std::map<long, KfPtr> kfs;
  std::unordered_map<long, MpPtr> pts;
  std::vector<long> recent_points;
  long next_kf_id = 0, next_pt_id = 0;

  // ---- local mapping thread ----
  std::thread mapping;
  std::mutex q_mutex;
  std::condition_variable q_cv, idle_cv;
  std::deque<long> queue;
  bool busy = false, stop = false;
  int kfs_since_ba = 0;  // mapping thread only
  std::atomic<bool> abort_ba{false};

  // ---- stats ----
  mutable std::mutex stats_mutex;
  TrackerStats stats;

  // ---- tracking state (tracking thread only) ----
  TrackingState state = TrackingState::kNotInitialized;
  long frame_counter = 0;
  bool have_ref = false;
  Frame ref;
  Frame last;
  long last_ref_kf = -1;
  Eigen::Isometry3d T_last_rel_kf = Eigen::Isometry3d::Identity();  // T_last_c_w * T_kf_c_w^-1
  Eigen::Isometry3d velocity = Eigen::Isometry3d::Identity();
  bool have_velocity = false;
  long last_kf_id = -1;
  int frames_since_kf = 0;
  int consecutive_lost = 0;
  bool reinitializing = false;  // map was reset after a loss and is being re-initialized
  bool have_last_good = false;
  Eigen::Isometry3d last_good_T_w_c = Eigen::Isometry3d::Identity();
  double last_median_depth = 1.0;

  Impl(CameraModelPtr c, const TrackerParams& params) : cam(std::move(c)), p(params) {
    if (p.mapping_thread) mapping = std::thread([this] { mappingLoop(); });
  }
  ~Impl() {
    {
      std::lock_guard<std::mutex> lk(q_mutex);
      stop = true;
      abort_ba = true;
    }
    q_cv.notify_all();
    if (mapping.joinable()) mapping.join();
  }

  // =========================================================================================
  // Frame preparation
  // =========================================================================================
  bool prepare(const FeatureFrame& in, Frame* f, std::string* err) {
    f->index = frame_counter;
    f->stamp = in.stamp;
    const size_t n = in.keypoints.size();
    if (n > 0 && (in.descriptors.rows != static_cast<int>(n) || in.descriptors.cols != 32 ||
                  in.descriptors.type() != CV_8U)) {
      *err = "descriptors must be N x 32 CV_8U with N = keypoints (" + std::to_string(n) + "), got " +
             std::to_string(in.descriptors.rows) + " x " + std::to_string(in.descriptors.cols);
      return false;
    }
    f->kps = in.keypoints;
    f->scale_factor = in.scale_factor;
    f->desc = in.descriptors.isContinuous() ? in.descriptors : in.descriptors.clone();
    f->bearings.assign(n, Eigen::Vector3d::Zero());
    f->valid.assign(n, 0);
    f->point_id.assign(n, -1);
    for (size_t i = 0; i < n; ++i) {
      const cv::Point2f& pt = f->kps[i].pt;
      if (!std::isfinite(pt.x) || !std::isfinite(pt.y)) continue;
      Eigen::Vector3d b;
      if (cam->unproject(Eigen::Vector2d(pt.x, pt.y), &b) && b.allFinite()) {
        f->bearings[i] = b.normalized();
        f->valid[i] = 1;
      }
    }
    f->buildGrid(cam->width() > 0 ? cam->width() : std::max(1, in.width),
                 cam->height() > 0 ? cam->height() : std::max(1, in.height));
    return true;
  }

  // Brute force a (query) vs b (train) with ratio test, threshold and rotation consistency.
  std::vector<std::pair<int, int>> matchBruteForce(const cv::Mat& da, const std::vector<cv::KeyPoint>& ka,
                                                   const std::vector<char>& va, const cv::Mat& db,
                                                   const std::vector<float>& angles_b, int threshold,
                                                   double ratio) const {
    std::vector<std::pair<int, int>> out;
    if (da.empty() || db.rows < 2) return out;
    cv::BFMatcher matcher(cv::NORM_HAMMING);
    std::vector<std::vector<cv::DMatch>> knn;
    matcher.knnMatch(da, db, knn, 2);
    std::vector<int> best_for_train(db.rows, -1);
    std::vector<float> best_dist(db.rows, 1e9f);
    for (const auto& m : knn) {
      if (m.empty()) continue;
      const cv::DMatch& b = m[0];
      if (!va[b.queryIdx] || b.distance > threshold) continue;
      if (m.size() > 1 && b.distance > ratio * m[1].distance) continue;
      if (b.distance < best_dist[b.trainIdx]) {
        best_dist[b.trainIdx] = b.distance;
        best_for_train[b.trainIdx] = b.queryIdx;
      }
    }
    std::vector<float> dangle;
    for (int t = 0; t < db.rows; ++t) {
      if (best_for_train[t] < 0) continue;
      out.emplace_back(best_for_train[t], t);
      const float a1 = ka[best_for_train[t]].angle, a2 = angles_b[t];
      dangle.push_back(a1 >= 0 && a2 >= 0 ? a1 - a2 : -1e9f);
    }
    if (p.check_orientation && !out.empty()) {
      const auto keep = rotationConsistent(dangle);
      std::vector<std::pair<int, int>> kept;
      for (size_t i = 0; i < out.size(); ++i)
        if (keep[i]) kept.push_back(out[i]);
      out.swap(kept);
    }
    return out;
  }

  // =========================================================================================
  // Initialization
  // =========================================================================================
  void setReference(const Frame& f) {
    if (static_cast<int>(f.kps.size()) >= p.init_min_features) {
      ref = f;
      have_ref = true;
    } else {
      have_ref = false;
    }
  }

  bool initialize(Frame& cur, TrackResult* res) {
    if (!have_ref || cur.index - ref.index > p.init_max_frames) {
      setReference(cur);
      return false;
    }
    std::vector<float> angles_ref(ref.kps.size());
    for (size_t i = 0; i < ref.kps.size(); ++i) angles_ref[i] = ref.kps[i].angle;
    std::vector<std::pair<int, int>> m =
        matchBruteForce(cur.desc, cur.kps, cur.valid, ref.desc, angles_ref, p.match_threshold_high, p.init_match_ratio);
    std::vector<std::pair<int, int>> mv;
    for (const auto& x : m)
      if (ref.valid[x.second]) mv.push_back(x);
    if (static_cast<int>(mv.size()) < p.init_min_matches) {
      setReference(cur);
      return false;
    }
    std::vector<Eigen::Vector3d> b1, b2;
    for (const auto& x : mv) {
      b1.push_back(ref.bearings[x.second]);
      b2.push_back(cur.bearings[x.first]);
    }
    TwoViewParams tvp;
    tvp.threshold_px = p.init_threshold_px;
    tvp.min_parallax_deg = p.init_min_parallax_deg;
    tvp.min_triangulated = p.init_min_triangulated;
    tvp.homography_ratio = p.init_homography_ratio;
    const TwoViewResult tv = initializeTwoView(b1, b2, cam->focal(), tvp);
    if (!tv.ok) return false;

    // Scale: median depth of the triangulated points in the reference frame = target depth.
    std::vector<double> depths;
    for (size_t k = 0; k < mv.size(); ++k)
      if (tv.triangulated[k]) depths.push_back(tv.points[k].z());
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    const double median = depths[depths.size() / 2];
    if (!(median > 0)) return false;
    const double target = have_last_good ? last_median_depth : 1.0;
    const double s = target / median;
    // Anchor: the reference frame sits at the last good pose (or at the origin for the first map).
    const Eigen::Isometry3d T_w_ref = have_last_good ? last_good_T_w_c : Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_cur_ref = Eigen::Isometry3d::Identity();
    T_cur_ref.linear() = tv.R_21;
    T_cur_ref.translation() = s * tv.t_21;
    const Eigen::Isometry3d T_ref_c_w = T_w_ref.inverse();
    const Eigen::Isometry3d T_cur_c_w = T_cur_ref * T_ref_c_w;

    auto kf0 = std::make_shared<Keyframe>();
    auto kf1 = std::make_shared<Keyframe>();
    auto fill = [](Keyframe* kf, const Frame& f, const Eigen::Isometry3d& T) {
      kf->frame_index = f.index;
      kf->stamp = f.stamp;
      kf->T_c_w = T;
      kf->kps = f.kps;
      kf->scale_factor = f.scale_factor;
      kf->desc = f.desc;
      kf->bearings = f.bearings;
      kf->valid = f.valid;
      kf->point_id.assign(f.kps.size(), -1);
    };
    fill(kf0.get(), ref, T_ref_c_w);
    fill(kf1.get(), cur, T_cur_c_w);

    // Two-keyframe BA (first keyframe fixed) before the map goes live.
    std::vector<BAKeyframe> bk(2);
    bk[0].T_c_w = T_ref_c_w;
    bk[0].fixed = true;
    bk[1].T_c_w = T_cur_c_w;
    std::vector<BAPoint> bp;
    std::vector<BAObservation> bo;
    std::vector<std::pair<int, int>> pt_match;
    for (size_t k = 0; k < mv.size(); ++k) {
      if (!tv.triangulated[k]) continue;
      BAPoint q;
      q.p_w = T_w_ref * (s * tv.points[k]);
      const int pi = static_cast<int>(bp.size());
      bp.push_back(q);
      const cv::KeyPoint& k0 = ref.kps[mv[k].second];
      const cv::KeyPoint& k1 = cur.kps[mv[k].first];
      bo.push_back({0, pi, Eigen::Vector2d(k0.pt.x, k0.pt.y), octaveSigma(ref.scale_factor, k0.octave)});
      bo.push_back({1, pi, Eigen::Vector2d(k1.pt.x, k1.pt.y), octaveSigma(cur.scale_factor, k1.octave)});
      pt_match.push_back(mv[k]);
    }
    BAOptions bao;
    bao.max_num_iterations = 20;
    bao.max_solver_time_in_seconds = 0.5;
    bao.huber_delta = p.ba_huber_delta;
    BASummary bs;
    bundleAdjust(*cam, &bk, &bp, bo, bao, &bs);
    kf1->T_c_w = bk[1].T_c_w;

    std::lock_guard<std::mutex> lk(map_mutex);
    kf0->id = next_kf_id++;
    kf1->id = next_kf_id++;
    int created = 0;
    for (size_t i = 0; i < bp.size(); ++i) {
      if (bs.outlier.size() == bo.size() && (bs.outlier[2 * i] || bs.outlier[2 * i + 1])) continue;
      auto mp = std::make_shared<MapPoint>();
      mp->id = next_pt_id++;
      mp->p_w = bp[i].p_w;
      const int i_cur = pt_match[i].first, i_ref = pt_match[i].second;
      mp->desc = descRow(cur.desc, i_cur);
      mp->octave = cur.kps[i_cur].octave;
      mp->angle = cur.kps[i_cur].angle;
      mp->obs[kf0->id] = i_ref;
      mp->obs[kf1->id] = i_cur;
      mp->first_kf = kf1->id;
      kf0->point_id[i_ref] = mp->id;
      kf1->point_id[i_cur] = mp->id;
      cur.point_id[i_cur] = mp->id;
      pts[mp->id] = mp;
      ++created;
    }
    if (created < p.init_min_triangulated) {
      // Roll back.
      for (size_t i = 0; i < cur.point_id.size(); ++i)
        if (cur.point_id[i] >= 0) pts.erase(cur.point_id[i]);
      std::fill(cur.point_id.begin(), cur.point_id.end(), -1);
      return false;
    }
    kfs[kf0->id] = kf0;
    kfs[kf1->id] = kf1;
    cur.T_c_w = kf1->T_c_w;
    last_kf_id = kf1->id;
    res->inliers = created;
    res->is_keyframe = true;
    // Per-frame velocity from the average motion over the initialization baseline.
    const int nframes = std::max<long>(1, cur.index - ref.index);
    const Eigen::Isometry3d T_rel = kf1->T_c_w * kf0->T_c_w.inverse();
    Eigen::Quaterniond q(T_rel.rotation());
    velocity.setIdentity();
    velocity.linear() = Eigen::Quaterniond::Identity().slerp(1.0 / nframes, q).toRotationMatrix();
    velocity.translation() = T_rel.translation() / nframes;
    have_velocity = true;
    return true;
  }

  // =========================================================================================
  // Tracking
  // =========================================================================================
  std::vector<LocalPoint> localPoints() const {
    std::lock_guard<std::mutex> lk(map_mutex);
    std::vector<LocalPoint> out;
    out.reserve(pts.size());
    for (const auto& kv : pts) {
      const MapPoint& mp = *kv.second;
      out.push_back({mp.id, mp.p_w, mp.desc, mp.octave, mp.angle});
    }
    return out;
  }

  // Projection search. Returns matches added; `kp_point` maps keypoint -> local index, `pt_kp` the reverse.
  int searchByProjection(const Frame& f, const Eigen::Isometry3d& T_c_w, const std::vector<LocalPoint>& local,
                         double radius, int octave_margin, std::vector<int>* kp_point, std::vector<int>* pt_kp,
                         std::vector<char>* visible) const {
    const double w = cam->width(), h = cam->height();
    std::vector<int> best_dist_kp(f.kps.size(), 256);
    for (size_t i = 0; i < kp_point->size(); ++i)
      if ((*kp_point)[i] >= 0) best_dist_kp[i] = -1;  // already matched in an earlier pass: keep
    std::vector<int> cand;
    int added = 0;
    for (size_t li = 0; li < local.size(); ++li) {
      if ((*pt_kp)[li] >= 0) continue;
      const LocalPoint& lp = local[li];
      const Eigen::Vector3d p_c = T_c_w * lp.p_w;
      if (p_c.z() <= 1e-6) continue;
      Eigen::Vector2d uv;
      if (!cam->project(p_c, &uv)) continue;
      if (uv.x() < 0 || uv.y() < 0 || uv.x() >= w || uv.y() >= h) continue;
      if (visible) (*visible)[li] = 1;
      const double r = radius * octaveSigma(f.scale_factor, lp.octave);
      f.featuresInArea(uv.x(), uv.y(), r, lp.octave - octave_margin, lp.octave + octave_margin, &cand);
      int best = 256, best2 = 256, best_idx = -1, best_oct = -1, best2_oct = -1;
      for (int j : cand) {
        if (best_dist_kp[j] < 0) continue;  // matched in an earlier pass
        const int d = hamming(lp.desc.data(), f.desc.ptr<uint8_t>(j));
        if (d < best) {
          best2 = best;
          best2_oct = best_oct;
          best = d;
          best_idx = j;
          best_oct = f.kps[j].octave;
        } else if (d < best2) {
          best2 = d;
          best2_oct = f.kps[j].octave;
        }
      }
      if (best_idx < 0 || best > p.match_threshold_high) continue;
      if (best_oct == best2_oct && best > p.match_ratio * best2) continue;
      if (best_dist_kp[best_idx] < 0 || best >= best_dist_kp[best_idx]) continue;
      if ((*kp_point)[best_idx] >= 0) {
        (*pt_kp)[(*kp_point)[best_idx]] = -1;  // replaced by a better point
        --added;
      }
      best_dist_kp[best_idx] = best;
      (*kp_point)[best_idx] = static_cast<int>(li);
      (*pt_kp)[li] = best_idx;
      ++added;
    }
    return added;
  }

  int countMatches(const std::vector<int>& kp_point) const {
    return static_cast<int>(std::count_if(kp_point.begin(), kp_point.end(), [](int x) { return x >= 0; }));
  }

  int refinePose(const Frame& f, const std::vector<LocalPoint>& local, std::vector<int>* kp_point,
                 std::vector<int>* pt_kp, Eigen::Isometry3d* T) const {
    std::vector<Eigen::Vector3d> P;
    std::vector<Eigen::Vector2d> uv;
    std::vector<double> sg;
    std::vector<int> kpi;
    for (size_t i = 0; i < kp_point->size(); ++i) {
      const int li = (*kp_point)[i];
      if (li < 0) continue;
      P.push_back(local[li].p_w);
      uv.emplace_back(f.kps[i].pt.x, f.kps[i].pt.y);
      sg.push_back(octaveSigma(f.scale_factor, f.kps[i].octave));
      kpi.push_back(static_cast<int>(i));
    }
    if (P.size() < 4) return 0;
    PoseOptimizationOptions po;
    po.rounds = p.pose_rounds;
    po.max_num_iterations = p.pose_max_iterations;
    po.use_ceres = p.pose_use_ceres;
    std::vector<char> inl(P.size(), 1);
    Eigen::Isometry3d Tn = *T;
    const int n = optimizePose(*cam, P, uv, sg, po, &Tn, &inl);
    if (n < 4) return n;
    *T = Tn;
    for (size_t k = 0; k < kpi.size(); ++k)
      if (!inl[k]) {
        (*pt_kp)[(*kp_point)[kpi[k]]] = -1;
        (*kp_point)[kpi[k]] = -1;
      }
    return n;
  }

  // Brute force against all map points + PnP RANSAC. Returns inliers (matches in kp_point).
  int relocalize(const Frame& f, const std::vector<LocalPoint>& local, std::vector<int>* kp_point,
                 std::vector<int>* pt_kp, Eigen::Isometry3d* T) const {
    if (local.size() < 10) return 0;
    cv::Mat D(static_cast<int>(local.size()), 32, CV_8U);
    std::vector<float> ang(local.size());
    for (size_t i = 0; i < local.size(); ++i) {
      std::memcpy(D.ptr<uint8_t>(static_cast<int>(i)), local[i].desc.data(), 32);
      ang[i] = local[i].angle;
    }
    const auto m = matchBruteForce(f.desc, f.kps, f.valid, D, ang, p.match_threshold_high, p.match_ratio);
    if (static_cast<int>(m.size()) < p.min_tracking_inliers) return 0;
    std::vector<Eigen::Vector3d> P, B;
    for (const auto& x : m) {
      P.push_back(local[x.second].p_w);
      B.push_back(f.bearings[x.first]);
    }
    std::vector<char> inl;
    Eigen::Isometry3d Tp;
    const int n = solvePnPBearings(P, B, cam->focal(), p.pnp_threshold_px, p.pnp_iterations, &Tp, &inl);
    if (n < p.min_tracking_inliers) return 0;
    std::fill(kp_point->begin(), kp_point->end(), -1);
    std::fill(pt_kp->begin(), pt_kp->end(), -1);
    for (size_t k = 0; k < m.size(); ++k)
      if (inl[k]) {
        (*kp_point)[m[k].first] = m[k].second;
        (*pt_kp)[m[k].second] = m[k].first;
      }
    *T = Tp;
    return n;
  }

  bool trackFrame(Frame& cur, TrackResult* res) {
    auto t0 = Clock::now();
    // Prediction; the last frame pose follows its reference keyframe if BA moved it.
    Eigen::Isometry3d T_last = last.T_c_w;
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      auto it = kfs.find(last_ref_kf);
      if (it != kfs.end()) T_last = T_last_rel_kf * it->second->T_c_w;
    }
    const Eigen::Isometry3d T_pred = have_velocity ? velocity * T_last : T_last;
    const std::vector<LocalPoint> local = localPoints();
    std::vector<int> kp_point(cur.kps.size(), -1), pt_kp(local.size(), -1);
    std::vector<char> visible(local.size(), 0);
    Eigen::Isometry3d T = T_pred;
    int n = searchByProjection(cur, T, local, p.search_radius_px, 1, &kp_point, &pt_kp, nullptr);
    if (n < p.min_search_matches) {
      std::fill(kp_point.begin(), kp_point.end(), -1);
      std::fill(pt_kp.begin(), pt_kp.end(), -1);
      n = searchByProjection(cur, T, local, p.search_radius_wide_px, 2, &kp_point, &pt_kp, nullptr);
    }
    res->timing.ms_match += msSince(t0);
    int inliers = 0;
    if (n >= p.min_search_matches) {
      t0 = Clock::now();
      inliers = refinePose(cur, local, &kp_point, &pt_kp, &T);
      res->timing.ms_pose += msSince(t0);
    }
    if (inliers < p.min_tracking_inliers) {
      t0 = Clock::now();
      inliers = relocalize(cur, local, &kp_point, &pt_kp, &T);
      res->used_pnp = inliers > 0;
      res->timing.ms_match += msSince(t0);
      if (inliers >= p.min_tracking_inliers) {
        t0 = Clock::now();
        inliers = refinePose(cur, local, &kp_point, &pt_kp, &T);
        res->timing.ms_pose += msSince(t0);
      }
    }
    res->matches = n;
    if (inliers < p.min_tracking_inliers) {
      res->inliers = inliers;
      return false;
    }
    // Second, narrow pass with the refined pose.
    t0 = Clock::now();
    searchByProjection(cur, T, local, p.search_radius_refine_px, 1, &kp_point, &pt_kp, &visible);
    res->timing.ms_match += msSince(t0);
    t0 = Clock::now();
    inliers = refinePose(cur, local, &kp_point, &pt_kp, &T);
    res->timing.ms_pose += msSince(t0);
    res->inliers = inliers;
    if (inliers < p.min_tracking_inliers) return false;

    cur.T_c_w = T;
    std::vector<double> depths;
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      for (size_t li = 0; li < local.size(); ++li) {
        if (!visible[li] && pt_kp[li] < 0) continue;
        auto it = pts.find(local[li].id);
        if (it == pts.end()) continue;
        it->second->visible++;
        if (pt_kp[li] >= 0) it->second->found++;
      }
    }
    for (size_t i = 0; i < kp_point.size(); ++i) {
      if (kp_point[i] < 0) continue;
      cur.point_id[i] = local[kp_point[i]].id;
      depths.push_back((T * local[kp_point[i]].p_w).z());
    }
    if (!depths.empty()) {
      std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
      last_median_depth = depths[depths.size() / 2];
    }
    if (last_kf_id >= 0) {
      // velocity from the (possibly BA-updated) last pose
      velocity = T * T_last.inverse();
      velocity.linear() = Eigen::Quaterniond(velocity.rotation()).normalized().toRotationMatrix();
      have_velocity = true;
    }
    return true;
  }

  // =========================================================================================
  // Keyframes
  // =========================================================================================
  bool mappingIdle() {
    if (!p.mapping_thread) return frames_since_kf >= p.sync_mapping_busy_frames;
    std::lock_guard<std::mutex> lk(q_mutex);
    return queue.empty() && !busy;
  }

  bool needKeyframe(int inliers) {
    if (frames_since_kf < p.min_frames_between_keyframes) return false;
    int ref_tracked = 0;
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      auto it = kfs.find(last_kf_id);
      if (it != kfs.end())
        for (long pid : it->second->point_id) {
          if (pid < 0) continue;
          auto pt = pts.find(pid);
          if (pt != pts.end() && pt->second->obs.size() >= 2) ++ref_tracked;
        }
    }
    const bool c_a = inliers < p.keyframe_min_tracked;
    const bool timeout = frames_since_kf >= p.max_frames_between_keyframes;
    const bool c_b = inliers < p.keyframe_tracked_ratio * ref_tracked && (timeout || mappingIdle());
    const bool c_c = timeout && inliers < 0.98 * ref_tracked;
    return c_a || c_b || c_c;
  }

  long insertKeyframe(const Frame& f) {
    auto kf = std::make_shared<Keyframe>();
    kf->frame_index = f.index;
    kf->stamp = f.stamp;
    kf->T_c_w = f.T_c_w;
    kf->kps = f.kps;
    kf->scale_factor = f.scale_factor;
    kf->desc = f.desc;
    kf->bearings = f.bearings;
    kf->valid = f.valid;
    kf->point_id.assign(f.kps.size(), -1);
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      kf->id = next_kf_id++;
      for (size_t i = 0; i < f.point_id.size(); ++i) {
        if (f.point_id[i] < 0) continue;
        auto it = pts.find(f.point_id[i]);
        if (it == pts.end() || it->second->obs.count(kf->id)) continue;
        it->second->obs[kf->id] = static_cast<int>(i);
        kf->point_id[i] = f.point_id[i];
      }
      kfs[kf->id] = kf;
    }
    {
      std::lock_guard<std::mutex> lk(stats_mutex);
      stats.keyframes++;
    }
    return kf->id;
  }

  void enqueue(long kf_id) {
    if (!p.mapping_thread) {
      processKeyframe(kf_id, true);
      return;
    }
    {
      std::unique_lock<std::mutex> lk(q_mutex);
      // Back-pressure: under CPU overload the mapping thread falls behind and the tracker would run on an
      // unoptimized map (monocular scale drifts); wait until fewer than max_pending_keyframes are queued.
      if (p.max_pending_keyframes > 0)
        idle_cv.wait(lk, [this] {
          return stop || static_cast<int>(queue.size()) + (busy ? 1 : 0) < p.max_pending_keyframes;
        });
      queue.push_back(kf_id);
      if (p.ba_abort_on_keyframe) abort_ba = true;
    }
    q_cv.notify_one();
  }

  // =========================================================================================
  // Local mapping
  // =========================================================================================
  void mappingLoop() {
    for (;;) {
      long id;
      bool last_in_queue;
      {
        std::unique_lock<std::mutex> lk(q_mutex);
        q_cv.wait(lk, [this] { return stop || !queue.empty(); });
        if (stop) return;
        id = queue.front();
        queue.pop_front();
        busy = true;
        abort_ba = false;
        last_in_queue = queue.empty();
      }
      idle_cv.notify_all();  // a queue slot is free (back-pressure in enqueue)
      // BA when no keyframe waits, and at least every ba_every_keyframes keyframes even when they keep
      // arriving (otherwise BA starves under load and the monocular scale drifts).
      ++kfs_since_ba;
      const bool run_ba = last_in_queue || kfs_since_ba >= p.ba_every_keyframes;
      if (run_ba) kfs_since_ba = 0;
      processKeyframe(id, run_ba);
      {
        std::lock_guard<std::mutex> lk(q_mutex);
        busy = false;
      }
      idle_cv.notify_all();
    }
  }

  void erasePointLocked(long pid) {
    auto it = pts.find(pid);
    if (it == pts.end()) return;
    for (const auto& o : it->second->obs) {
      auto k = kfs.find(o.first);
      if (k != kfs.end() && o.second < static_cast<int>(k->second->point_id.size()) &&
          k->second->point_id[o.second] == pid)
        k->second->point_id[o.second] = -1;
    }
    pts.erase(it);
  }

  void cullRecentPoints(long current_kf) {
    std::lock_guard<std::mutex> lk(map_mutex);
    std::vector<long> keep;
    for (long pid : recent_points) {
      auto it = pts.find(pid);
      if (it == pts.end()) continue;
      const MapPoint& mp = *it->second;
      const long age = current_kf - mp.first_kf;
      if (static_cast<double>(mp.found) / std::max(1, mp.visible) < p.min_found_ratio) {
        erasePointLocked(pid);
      } else if (age >= 2 && mp.obs.size() <= 2) {
        erasePointLocked(pid);
      } else if (age < 3) {
        keep.push_back(pid);
      }
    }
    recent_points.swap(keep);
  }

  void triangulateNew(long kf_id) {
    KfPtr kf;
    std::vector<long> kf_pids;
    Eigen::Isometry3d T1;
    struct Nb {
      KfPtr kf;
      Eigen::Isometry3d T;
      std::vector<long> pids;
    };
    std::vector<Nb> nbs;
    double median_depth = 1.0;
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      auto it = kfs.find(kf_id);
      if (it == kfs.end()) return;
      kf = it->second;
      if (kf->triangulated.exchange(true)) return;  // done already (tracker or mapping thread)
      kf_pids = kf->point_id;
      T1 = kf->T_c_w;
      std::map<long, int> covis;
      std::vector<double> depths;
      for (long pid : kf_pids) {
        if (pid < 0) continue;
        auto pt = pts.find(pid);
        if (pt == pts.end()) continue;
        depths.push_back((T1 * pt->second->p_w).z());
        for (const auto& o : pt->second->obs)
          if (o.first != kf_id) covis[o.first]++;
      }
      if (!depths.empty()) {
        std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
        median_depth = depths[depths.size() / 2];
      }
      std::vector<std::pair<int, long>> order;
      for (const auto& c : covis) order.emplace_back(c.second, c.first);
      std::sort(order.rbegin(), order.rend());
      // Fill with the most recent keyframes when covisibility is thin.
      for (auto k = kfs.rbegin(); k != kfs.rend(); ++k)
        if (k->first != kf_id && !covis.count(k->first)) order.emplace_back(0, k->first);
      for (const auto& o : order) {
        if (static_cast<int>(nbs.size()) >= p.num_triangulation_neighbors) break;
        auto k = kfs.find(o.second);
        if (k == kfs.end()) continue;
        nbs.push_back({k->second, k->second->T_c_w, k->second->point_id});
      }
    }
    const double f = cam->focal();
    const Eigen::Vector3d c1 = T1.inverse().translation();
    struct NewPoint {
      Eigen::Vector3d p_w;
      int i1;
      long nb_id;
      int i2;
    };
    std::vector<NewPoint> created;
    std::vector<char> used1(kf->kps.size(), 0);
    for (size_t i = 0; i < kf_pids.size(); ++i) used1[i] = kf_pids[i] >= 0 || !kf->valid[i];
    const double cos_min_par = std::cos(p.min_triangulation_parallax_deg * M_PI / 180.0);
    for (Nb& nb : nbs) {
      const Eigen::Vector3d c2 = nb.T.inverse().translation();
      if ((c2 - c1).norm() / median_depth < 0.01) continue;  // baseline too small
      const Eigen::Isometry3d T21 = nb.T * T1.inverse();
      const Eigen::Matrix3d R21 = T21.rotation();
      const Eigen::Vector3d t21 = T21.translation();
      const Keyframe& k2 = *nb.kf;
      std::vector<int> cand2;
      for (size_t j = 0; j < k2.kps.size(); ++j)
        if (nb.pids[j] < 0 && k2.valid[j]) cand2.push_back(static_cast<int>(j));
      std::vector<int> match_of_2(k2.kps.size(), -1), dist_of_2(k2.kps.size(), 256);
      for (size_t i = 0; i < kf->kps.size(); ++i) {
        if (used1[i]) continue;
        Eigen::Vector3d n = t21.cross(R21 * kf->bearings[i]);  // epipolar plane normal in frame 2
        const double nn = n.norm();
        if (nn < 1e-12) continue;
        n /= nn;
        const uint8_t* d1 = kf->desc.ptr<uint8_t>(static_cast<int>(i));
        int best = p.match_threshold_low + 1, best_j = -1;
        for (int j : cand2) {
          const int d = hamming(d1, k2.desc.ptr<uint8_t>(j));
          if (d >= best) continue;
          // eq.: |n . b2| = sin(angle to the epipolar plane); gate at 2 sigma (chi2 1 dof 3.84) in pixels
          const double sig = octaveSigma(k2.scale_factor, k2.kps[j].octave);
          if (std::abs(n.dot(k2.bearings[j])) * f > 1.96 * sig) continue;
          best = d;
          best_j = j;
        }
        if (best_j < 0 || best >= dist_of_2[best_j]) continue;
        dist_of_2[best_j] = best;
        match_of_2[best_j] = static_cast<int>(i);
      }
      for (size_t j = 0; j < match_of_2.size(); ++j) {
        const int i = match_of_2[j];
        if (i < 0 || used1[i]) continue;
        Eigen::Vector3d X;
        if (!triangulateBearings(T1, kf->bearings[i], nb.T, k2.bearings[j], &X)) continue;
        const Eigen::Vector3d r1 = (X - c1).normalized(), r2 = (X - c2).normalized();
        if (r1.dot(r2) > cos_min_par) continue;
        const cv::KeyPoint& kp1 = kf->kps[i];
        const cv::KeyPoint& kp2 = k2.kps[j];
        const double s1 = octaveSigma(kf->scale_factor, kp1.octave), s2 = octaveSigma(k2.scale_factor, kp2.octave);
        const double e1 = reprojectionError2(*cam, T1, X, Eigen::Vector2d(kp1.pt.x, kp1.pt.y));
        const double e2 = reprojectionError2(*cam, nb.T, X, Eigen::Vector2d(kp2.pt.x, kp2.pt.y));
        if (e1 < 0 || e2 < 0 || e1 > kChi2 * s1 * s1 || e2 > kChi2 * s2 * s2) continue;
        used1[i] = 1;
        nb.pids[j] = -2;  // taken
        created.push_back({X, i, k2.id, static_cast<int>(j)});
      }
    }
    std::lock_guard<std::mutex> lk(map_mutex);
    for (const NewPoint& np : created) {
      auto k2 = kfs.find(np.nb_id);
      if (k2 == kfs.end() || kfs.find(kf_id) == kfs.end()) continue;
      if (kf->point_id[np.i1] >= 0 || k2->second->point_id[np.i2] >= 0) continue;
      auto mp = std::make_shared<MapPoint>();
      mp->id = next_pt_id++;
      mp->p_w = np.p_w;
      mp->desc = descRow(kf->desc, np.i1);
      mp->octave = kf->kps[np.i1].octave;
      mp->angle = kf->kps[np.i1].angle;
      mp->obs[kf_id] = np.i1;
      mp->obs[np.nb_id] = np.i2;
      mp->first_kf = kf_id;
      kf->point_id[np.i1] = mp->id;
      k2->second->point_id[np.i2] = mp->id;
      pts[mp->id] = mp;
      recent_points.push_back(mp->id);
    }
  }

  void localBundleAdjustment() {
    std::vector<long> kf_ids, pt_ids;
    std::vector<BAKeyframe> bk;
    std::vector<BAPoint> bp;
    std::vector<BAObservation> bo;
    std::vector<std::pair<long, int>> obs_ref;  // (kf id, keypoint) per observation
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      if (kfs.size() < 2) return;
      std::unordered_map<long, int> kf_index;
      int nwin = 0;
      for (auto it = kfs.rbegin(); it != kfs.rend() && nwin < p.ba_window_size; ++it, ++nwin) {
        kf_index[it->first] = static_cast<int>(kf_ids.size());
        kf_ids.push_back(it->first);
        BAKeyframe b;
        b.T_c_w = it->second->T_c_w;
        bk.push_back(b);
      }
      std::unordered_map<long, int> pt_index;
      for (int w = 0; w < nwin; ++w) {
        const Keyframe& kf = *kfs[kf_ids[w]];
        for (long pid : kf.point_id) {
          if (pid < 0 || pt_index.count(pid)) continue;
          auto pt = pts.find(pid);
          if (pt == pts.end() || pt->second->obs.size() < 2) continue;
          pt_index[pid] = static_cast<int>(pt_ids.size());
          pt_ids.push_back(pid);
          bp.push_back({pt->second->p_w});
        }
      }
      // Observations; keyframes outside the window that see window points are fixed (gauge).
      int nfixed = 0;
      for (size_t pi = 0; pi < pt_ids.size(); ++pi) {
        const MapPoint& mp = *pts[pt_ids[pi]];
        for (const auto& o : mp.obs) {
          auto k = kfs.find(o.first);
          if (k == kfs.end()) continue;
          auto ki = kf_index.find(o.first);
          int kidx;
          if (ki == kf_index.end()) {
            kidx = static_cast<int>(kf_ids.size());
            kf_index[o.first] = kidx;
            kf_ids.push_back(o.first);
            BAKeyframe b;
            b.T_c_w = k->second->T_c_w;
            b.fixed = true;
            bk.push_back(b);
            ++nfixed;
          } else {
            kidx = ki->second;
          }
          const cv::KeyPoint& kp = k->second->kps[o.second];
          bo.push_back({kidx, static_cast<int>(pi), Eigen::Vector2d(kp.pt.x, kp.pt.y),
                        octaveSigma(k->second->scale_factor, kp.octave)});
          obs_ref.emplace_back(o.first, o.second);
        }
      }
      // Monocular gauge (6 dof + scale): at least two fixed keyframes, and their centres must span at least
      // ba_min_fixed_span of the window's extent (oldest to newest centre); otherwise the scale is only weakly
      // held and drifts while tracking and BA interleave. Fix the oldest window keyframes until both hold,
      // keeping at least one keyframe free.
      auto centre = [&](int k) { return Eigen::Vector3d(bk[k].T_c_w.inverse().translation()); };
      const double wspan = (centre(0) - centre(nwin - 1)).norm();
      auto fixedSpan = [&]() {
        double m = 0.0;
        for (size_t i = 0; i < bk.size(); ++i)
          for (size_t j = i + 1; j < bk.size(); ++j)
            if (bk[i].fixed && bk[j].fixed) m = std::max(m, (centre(i) - centre(j)).norm());
        return m;
      };
      for (int w = nwin - 1; w >= 1; --w) {
        if (bk[w].fixed) continue;
        if (nfixed >= 2 && fixedSpan() >= p.ba_min_fixed_span * wspan) break;
        bk[w].fixed = true;
        ++nfixed;
      }
    }
    if (bo.empty()) return;
    BAOptions bao;
    bao.max_num_iterations = p.ba_max_num_iterations;
    bao.max_solver_time_in_seconds = p.ba_max_solver_time_in_seconds;
    bao.huber_delta = p.ba_huber_delta;
    bao.abort = p.mapping_thread ? &abort_ba : nullptr;
    BASummary bs;
    const bool ok = bundleAdjust(*cam, &bk, &bp, bo, bao, &bs);
    {
      std::lock_guard<std::mutex> lk(stats_mutex);
      stats.ba_runs++;
      stats.ba_ms_total += bs.ms;
      stats.ba_final_rmse_px = bs.final_rmse_px;
    }
    if (!ok) return;
    std::lock_guard<std::mutex> lk(map_mutex);
    for (size_t k = 0; k < kf_ids.size(); ++k) {
      if (bk[k].fixed) continue;
      auto it = kfs.find(kf_ids[k]);
      if (it != kfs.end()) it->second->T_c_w = bk[k].T_c_w;
    }
    for (size_t i = 0; i < pt_ids.size(); ++i) {
      auto it = pts.find(pt_ids[i]);
      if (it != pts.end()) it->second->p_w = bp[i].p_w;
    }
    for (size_t j = 0; j < bo.size(); ++j) {
      if (!bs.outlier[j]) continue;
      auto pt = pts.find(pt_ids[bo[j].point]);
      auto k = kfs.find(obs_ref[j].first);
      if (pt == pts.end()) continue;
      pt->second->obs.erase(obs_ref[j].first);
      if (k != kfs.end() && k->second->point_id[obs_ref[j].second] == pt->first)
        k->second->point_id[obs_ref[j].second] = -1;
      if (pt->second->obs.empty()) pts.erase(pt);
    }
  }

  void dropOldKeyframes() {
    std::lock_guard<std::mutex> lk(map_mutex);
    while (static_cast<int>(kfs.size()) > p.max_map_keyframes) {
      auto it = kfs.begin();
      const Keyframe& kf = *it->second;
      for (size_t i = 0; i < kf.point_id.size(); ++i) {
        const long pid = kf.point_id[i];
        if (pid < 0) continue;
        auto pt = pts.find(pid);
        if (pt == pts.end()) continue;
        pt->second->obs.erase(kf.id);
        if (pt->second->obs.empty()) pts.erase(pt);
      }
      kfs.erase(it);
    }
  }

  // ORB-SLAM's distinctive descriptor: of all observations of a point, the one with the least median Hamming
  // distance to the others. Updated for the points seen by a new keyframe.
  void updateDescriptors(long kf_id) {
    std::lock_guard<std::mutex> lk(map_mutex);
    auto k = kfs.find(kf_id);
    if (k == kfs.end()) return;
    std::vector<const uint8_t*> d;
    std::vector<int> dist;
    for (long pid : k->second->point_id) {
      if (pid < 0) continue;
      auto pt = pts.find(pid);
      if (pt == pts.end() || pt->second->obs.size() < 3) continue;
      d.clear();
      for (const auto& o : pt->second->obs) {
        auto ko = kfs.find(o.first);
        if (ko != kfs.end()) d.push_back(ko->second->desc.ptr<uint8_t>(o.second));
      }
      const size_t n = d.size();
      if (n < 3) continue;
      dist.assign(n * n, 0);
      for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j) dist[i * n + j] = dist[j * n + i] = hamming(d[i], d[j]);
      int best = 1 << 30;
      size_t best_i = 0;
      std::vector<int> row(n);
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

  void processKeyframe(long kf_id, bool run_ba) {
    cullRecentPoints(kf_id);
    updateDescriptors(kf_id);
    triangulateNew(kf_id);

    if (run_ba && !(p.mapping_thread && p.ba_abort_on_keyframe && abort_ba.load())) localBundleAdjustment();
    dropOldKeyframes();
  }

  void waitForMapping() {
    if (!p.mapping_thread) return;
    std::unique_lock<std::mutex> lk(q_mutex);
    idle_cv.wait(lk, [this] { return queue.empty() && !busy; });
  }

  void clearMap() {
    {
      std::lock_guard<std::mutex> lk(q_mutex);
      queue.clear();
      abort_ba = true;
    }
    waitForMapping();
    std::lock_guard<std::mutex> lk(map_mutex);
    kfs.clear();
    pts.clear();
    recent_points.clear();
    have_ref = false;
    have_velocity = false;
    last_kf_id = -1;
    last_ref_kf = -1;
    frames_since_kf = 0;
    consecutive_lost = 0;
    state = TrackingState::kNotInitialized;
  }

  // =========================================================================================
  // Per frame
  // =========================================================================================
  TrackResult track(const FeatureFrame& in) {
    const auto t_start = Clock::now();
    TrackResult res;
    Frame cur;
    std::string err;
    auto t0 = Clock::now();
    const bool ok_input = prepare(in, &cur, &err);
    res.timing.ms_prepare = msSince(t0);
    ++frame_counter;
    {
      std::lock_guard<std::mutex> lk(stats_mutex);
      stats.frames++;
    }
    if (!ok_input) {
      // Bad frame: report it as not tracked, keep the state machine as is.
      res.state = state == TrackingState::kTracking ? TrackingState::kLost : state;
      res.T_w_c = last_good_T_w_c;
      res.timing.ms_total = msSince(t_start);
      return res;
    }

    if (state == TrackingState::kNotInitialized || state == TrackingState::kInitializing) {
      t0 = Clock::now();
      const bool done = initialize(cur, &res);
      res.timing.ms_init = msSince(t0);
      if (!done) {
        state = have_ref ? TrackingState::kInitializing : TrackingState::kNotInitialized;
        res.state = state;
        if (reinitializing) {  // after a loss: these frames are lost frames of the same lost event
          res.state = TrackingState::kLost;
          std::lock_guard<std::mutex> lk(stats_mutex);
          stats.lost_frames++;
        }
        res.T_w_c = last_good_T_w_c;
        res.timing.ms_total = msSince(t_start);
        return res;
      }
      state = TrackingState::kTracking;
      reinitializing = false;
      res.initialized_now = true;
      {
        std::lock_guard<std::mutex> lk(stats_mutex);
        stats.initializations++;
        stats.keyframes += 2;
      }
      t0 = Clock::now();
      enqueue(last_kf_id);
      res.timing.ms_keyframe = msSince(t0);
      onTracked(cur, &res, true);
      res.timing.ms_total = msSince(t_start);
      return res;
    }

    // kTracking or kLost (relocalization attempts before the reset)
    if (state == TrackingState::kLost) have_velocity = false;
    const bool tracked = trackFrame(cur, &res);
    if (!tracked) {
      {
        std::lock_guard<std::mutex> lk(stats_mutex);
        stats.lost_frames++;
        if (state == TrackingState::kTracking) stats.lost_events++;
      }
      state = TrackingState::kLost;
      ++consecutive_lost;
      if (consecutive_lost > p.lost_frames_before_reset) {
        {
          std::lock_guard<std::mutex> lk(stats_mutex);
          stats.resets++;
        }
        clearMap();
        setReference(cur);  // this frame starts the new initialization
        reinitializing = true;
        state = have_ref ? TrackingState::kInitializing : TrackingState::kNotInitialized;
      }
      res.state = TrackingState::kLost;
      res.T_w_c = last_good_T_w_c;
      res.timing.ms_total = msSince(t_start);
      return res;
    }
    state = TrackingState::kTracking;
    consecutive_lost = 0;
    ++frames_since_kf;
    bool kf = false;
    t0 = Clock::now();
    if (needKeyframe(res.inliers)) {
      last_kf_id = insertKeyframe(cur);
      frames_since_kf = 0;
      enqueue(last_kf_id);
      kf = true;
      // Map starvation: triangulate this keyframe's new points right here instead of waiting for the mapping
      // thread (never waits for BA; the mapping thread skips the triangulation of this keyframe).
      if (p.mapping_thread && res.inliers < p.starving_inliers) triangulateNew(last_kf_id);
    }
    res.timing.ms_keyframe = msSince(t0);
    onTracked(cur, &res, kf);
    res.timing.ms_total = msSince(t_start);
    return res;
  }

  void onTracked(const Frame& cur, TrackResult* res, bool is_kf) {
    res->state = TrackingState::kTracking;
    res->is_keyframe = is_kf;
    res->T_w_c = cur.T_c_w.inverse();
    res->keypoint_inlier.assign(cur.point_id.size(), 0);
    for (size_t i = 0; i < cur.point_id.size(); ++i) res->keypoint_inlier[i] = cur.point_id[i] >= 0;
    last_good_T_w_c = res->T_w_c;
    have_last_good = true;
    last = cur;
    {
      std::lock_guard<std::mutex> lk(map_mutex);
      auto it = kfs.find(last_kf_id);
      last_ref_kf = last_kf_id;
      T_last_rel_kf = it != kfs.end() ? cur.T_c_w * it->second->T_c_w.inverse() : Eigen::Isometry3d::Identity();
      if (it == kfs.end()) last_ref_kf = -1;
    }
    std::lock_guard<std::mutex> lk(stats_mutex);
    stats.tracked++;
  }
};

// ============================================================================================
Tracker::Tracker(CameraModelPtr camera, const TrackerParams& params) {
  if (!camera) throw std::invalid_argument("Tracker: camera model is null");
  const std::string err = validate(params);
  if (!err.empty()) throw std::invalid_argument("Tracker: " + err);
  impl_ = std::make_unique<Impl>(std::move(camera), params);
}

Tracker::~Tracker() = default;

TrackResult Tracker::track(const FeatureFrame& frame) { return impl_->track(frame); }

std::vector<Eigen::Vector3d> Tracker::mapPoints() const {
  std::lock_guard<std::mutex> lk(impl_->map_mutex);
  std::vector<Eigen::Vector3d> out;
  out.reserve(impl_->pts.size());
  for (const auto& kv : impl_->pts) out.push_back(kv.second->p_w);
  return out;
}

std::vector<KeyframePose> Tracker::keyframePoses() const {
  std::lock_guard<std::mutex> lk(impl_->map_mutex);
  std::vector<KeyframePose> out;
  for (const auto& kv : impl_->kfs) out.push_back({kv.first, kv.second->stamp, kv.second->T_c_w.inverse()});
  return out;
}

TrackerStats Tracker::stats() const {
  std::lock_guard<std::mutex> lk(impl_->stats_mutex);
  return impl_->stats;
}

TrackingState Tracker::state() const { return impl_->state; }
const TrackerParams& Tracker::params() const { return impl_->p; }
void Tracker::waitForMapping() { impl_->waitForMapping(); }
void Tracker::reset() { impl_->clearMap(); }

}  // namespace iraf_vo
