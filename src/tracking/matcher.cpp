#include "iraf_vo/tracking/matcher.h"

#include <opencv2/features2d.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace iraf_vo {

// ---------------------------------------------------------------------------------------------
// MatchSet
// ---------------------------------------------------------------------------------------------
void MatchSet::link(int keypoint, int point) {
  if (point_of_[keypoint] >= 0) keypoint_of_[point_of_[keypoint]] = -1;
  point_of_[keypoint] = point;
  keypoint_of_[point] = keypoint;
}

void MatchSet::unlinkKeypoint(int keypoint) {
  if (point_of_[keypoint] < 0) return;
  keypoint_of_[point_of_[keypoint]] = -1;
  point_of_[keypoint] = -1;
}

void MatchSet::clear() {
  std::fill(point_of_.begin(), point_of_.end(), -1);
  std::fill(keypoint_of_.begin(), keypoint_of_.end(), -1);
}

int MatchSet::size() const {
  return static_cast<int>(std::count_if(point_of_.begin(), point_of_.end(), [](int x) { return x >= 0; }));
}

// ---------------------------------------------------------------------------------------------
std::vector<char> rotationConsistent(const std::vector<float>& angle_differences) {
  constexpr int kBins = 30;
  std::array<std::vector<int>, kBins> hist;
  std::vector<char> keep(angle_differences.size(), 1);
  for (size_t i = 0; i < angle_differences.size(); ++i) {
    if (angle_differences[i] < -1000.f) continue;
    float a = std::fmod(angle_differences[i], 360.f);
    if (a < 0) a += 360.f;
    const int b = static_cast<int>(std::lround(a * kBins / 360.f)) % kBins;
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

// ---------------------------------------------------------------------------------------------
bool Matcher::projectInView(const LocalPoint& lp, const Eigen::Isometry3d& T_c_w, const Eigen::Vector3d& center,
                            double scale_factor, Eigen::Vector2d* uv, int* octave) const {
  const Eigen::Vector3d p_c = T_c_w * lp.p_w;
  if (p_c.z() <= 1e-6) return false;
  Eigen::Matrix<double, 2, 3> J;
  if (!cam_.project(p_c, uv, p_.predict_scale ? &J : nullptr)) return false;
  if (uv->x() < 0 || uv->y() < 0 || uv->x() >= cam_.width() || uv->y() >= cam_.height()) return false;
  *octave = lp.octave;
  return !p_.predict_scale || predictOctave(lp, center, imageScale(J), scale_factor, octave);
}

int Matcher::searchByProjection(const Frame& f, const Eigen::Isometry3d& T_c_w, const std::vector<LocalPoint>& local,
                                double radius, int octave_margin, MatchSet* matches, std::vector<char>* visible) const {
  std::vector<int> best_dist_of_kp(f.size(), 256);
  for (size_t i = 0; i < f.size(); ++i)
    if (matches->pointOf(static_cast<int>(i)) >= 0) best_dist_of_kp[i] = -1;  // matched in an earlier pass: keep
  std::vector<int> candidates;
  int added = 0;
  const Eigen::Vector3d center = T_c_w.inverse().translation();
  for (size_t li = 0; li < local.size(); ++li) {
    if (matches->keypointOf(static_cast<int>(li)) >= 0) continue;
    const LocalPoint& lp = local[li];
    Eigen::Vector2d uv;
    int octave;
    if (!projectInView(lp, T_c_w, center, f.scale_factor, &uv, &octave)) continue;
    if (visible) (*visible)[li] = 1;
    const double r = radius * f.sigma(octave);
    f.featuresInArea(uv.x(), uv.y(), r, octave - octave_margin, octave + octave_margin, &candidates);
    int best = 256, second = 256, best_idx = -1, best_octave = -1, second_octave = -1;
    for (int j : candidates) {
      if (best_dist_of_kp[j] < 0) continue;
      const int d = hammingDistance(lp.desc.data(), f.descriptors.ptr<uint8_t>(j));
      if (d < best) {
        second = best;
        second_octave = best_octave;
        best = d;
        best_idx = j;
        best_octave = f.keypoints[j].octave;
      } else if (d < second) {
        second = d;
        second_octave = f.keypoints[j].octave;
      }
    }
    if (best_idx < 0 || best > p_.match_threshold_high) continue;
    if (best_octave == second_octave && best > p_.match_ratio * second) continue;
    if (best_dist_of_kp[best_idx] < 0 || best >= best_dist_of_kp[best_idx]) continue;
    if (matches->pointOf(best_idx) >= 0) --added;  // replaced by a better point
    best_dist_of_kp[best_idx] = best;
    matches->link(best_idx, static_cast<int>(li));
    ++added;
  }
  return added;
}

std::vector<std::pair<int, int>> Matcher::matchBruteForce(const cv::Mat& query, const std::vector<cv::KeyPoint>& query_kps,
                                                          const std::vector<char>& query_valid, const cv::Mat& train,
                                                          const std::vector<float>& train_angles, int threshold,
                                                          double ratio) const {
  std::vector<std::pair<int, int>> out;
  if (query.empty() || train.rows < 2) return out;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query, train, knn, 2);
  std::vector<int> best_query_of_train(train.rows, -1);
  std::vector<float> best_dist(train.rows, 1e9f);
  for (const auto& m : knn) {
    if (m.empty()) continue;
    const cv::DMatch& b = m[0];
    if (!query_valid[b.queryIdx] || b.distance > threshold) continue;
    if (m.size() > 1 && b.distance > ratio * m[1].distance) continue;
    if (b.distance < best_dist[b.trainIdx]) {
      best_dist[b.trainIdx] = b.distance;
      best_query_of_train[b.trainIdx] = b.queryIdx;
    }
  }
  std::vector<float> angle_differences;
  for (int t = 0; t < train.rows; ++t) {
    if (best_query_of_train[t] < 0) continue;
    out.emplace_back(best_query_of_train[t], t);
    const float a1 = query_kps[best_query_of_train[t]].angle, a2 = train_angles[t];
    angle_differences.push_back(a1 >= 0 && a2 >= 0 ? a1 - a2 : -1e9f);
  }
  if (p_.check_orientation && !out.empty()) {
    const auto keep = rotationConsistent(angle_differences);
    std::vector<std::pair<int, int>> kept;
    for (size_t i = 0; i < out.size(); ++i)
      if (keep[i]) kept.push_back(out[i]);
    out.swap(kept);
  }
  return out;
}

namespace {

// Keypoints of keyframe 2 indexed by the epipolar plane they lie on. Every epipolar plane contains t_21, so its
// normal is n(phi) = cos(phi) e1 + sin(phi) e2 with (e1, e2) a basis orthogonal to t_21, and for a bearing b with
// e1.b = rho cos(psi), e2.b = rho sin(psi): n.b = rho cos(phi - psi). The gate |n.b| <= g therefore holds only for
// phi within asin(g / rho) of kappa = psi + 90 deg (mod 180 deg): sorted by kappa, a keypoint's candidates are one
// range (two at the wrap). Bearings near the epipole (wide angle) are checked for every keypoint. The index only
// preselects: the gate itself is evaluated exactly as without it.
class EpipolarIndex {
 public:
  static constexpr double kMaxHalfWidth = 0.05;  // rad; wider candidates go to the always-checked list

  EpipolarIndex(const Eigen::Vector3d& t21, const std::vector<Eigen::Vector3d>& bearings, const std::vector<double>& gate)
      : e1_(t21.normalized().unitOrthogonal()), e2_(t21.normalized().cross(e1_)) {
    for (size_t c = 0; c < bearings.size(); ++c) {
      const double u = e1_.dot(bearings[c]), v = e2_.dot(bearings[c]), rho = std::hypot(u, v);
      if (!(gate[c] < rho * std::sin(kMaxHalfWidth))) {
        always_.push_back(static_cast<int>(c));
        continue;
      }
      sorted_.push_back({wrap(std::atan2(v, u) + M_PI / 2), static_cast<int>(c)});
    }
    std::sort(sorted_.begin(), sorted_.end());
  }

  /// Calls visit(c) for every candidate c whose gate can hold for the plane with normal n (n orthogonal to t21).
  template <typename Visit>
  void forEachNear(const Eigen::Vector3d& n, Visit visit) const {
    for (int c : always_) visit(c);
    const double phi = wrap(std::atan2(e2_.dot(n), e1_.dot(n)));
    const double lo = phi - kMaxHalfWidth, hi = phi + kMaxHalfWidth;
    visitRange(std::max(0.0, lo), std::min(M_PI, hi), visit);
    if (lo < 0) visitRange(lo + M_PI, M_PI, visit);
    if (hi > M_PI) visitRange(0.0, hi - M_PI, visit);
  }

 private:
  static double wrap(double a) {  // into [0, pi)
    a = std::fmod(a, M_PI);
    return a < 0 ? a + M_PI : a;
  }
  template <typename Visit>
  void visitRange(double from, double to, Visit& visit) const {
    auto it = std::lower_bound(sorted_.begin(), sorted_.end(), std::make_pair(from, -1));
    for (; it != sorted_.end() && it->first <= to; ++it) visit(it->second);
  }

  Eigen::Vector3d e1_, e2_;
  std::vector<std::pair<double, int>> sorted_;  // (kappa, candidate)
  std::vector<int> always_;
};

}  // namespace

std::vector<int> Matcher::searchForTriangulation(const Keyframe& kf1, const std::vector<char>& used1, const Keyframe& kf2,
                                                 const std::vector<long>& point_id2, const Eigen::Isometry3d& T_21) const {
  const double f = cam_.focal();
  const Eigen::Matrix3d R21 = T_21.rotation();
  const Eigen::Vector3d t21 = T_21.translation();
  std::vector<int> match_of_2(kf2.keypoints.size(), -1), dist_of_2(kf2.keypoints.size(), 256);
  if (!(t21.norm() > 1e-12)) return match_of_2;
  std::vector<int> candidates2;
  std::vector<Eigen::Vector3d> bearings2;
  std::vector<double> gate;
  for (size_t j = 0; j < kf2.keypoints.size(); ++j) {
    if (point_id2[j] >= 0 || !kf2.valid[j]) continue;
    candidates2.push_back(static_cast<int>(j));
    bearings2.push_back(kf2.bearings[j]);
    // |n . b2| = sin(angle to the epipolar plane); gate at 2 sigma (chi2 1 dof 3.84) in pixels
    gate.push_back(1.96 * kf2.sigma(kf2.keypoints[j].octave) / f);
  }
  const EpipolarIndex index(t21, bearings2, gate);
  std::vector<std::pair<int, int>> on_line;  // (candidate, Hamming distance) within the gate
  // Repeated texture along the line (a facade's windows on the horizon, where forward motion makes the epipolar
  // lines horizontal) matches a wrong copy: a point far too close that drags the monocular scale down. The best must
  // beat every candidate farther than kSameCornerPx from it (closer ones are the same corner at another octave).
  const auto distinctOnLine = [this](int best, const cv::Point2f& at, const std::vector<std::pair<int, int>>& line,
                                     const std::vector<int>& cand, const Keyframe& kf) {
    constexpr float kSameCornerPx = 5.f;
    int other = 256;
    for (const auto& [c, d] : line) {
      const cv::Point2f q = kf.keypoints[cand[c]].pt;
      if (std::hypot(q.x - at.x, q.y - at.y) > kSameCornerPx) other = std::min(other, d);
    }
    return best <= p_.triangulation_match_ratio * other;
  };
  for (size_t i = 0; i < kf1.keypoints.size(); ++i) {
    if (used1[i]) continue;
    Eigen::Vector3d n = t21.cross(R21 * kf1.bearings[i]);  // epipolar plane normal in frame 2
    const double nn = n.norm();
    if (nn < 1e-12) continue;
    n /= nn;
    const uint8_t* d1 = kf1.descriptors.ptr<uint8_t>(static_cast<int>(i));
    // The closest descriptor among the candidates within the gate; ties go to the lowest candidate index.
    int best = p_.match_threshold_low + 1, best_c = -1;
    on_line.clear();
    index.forEachNear(n, [&](int c) {
      if (!(std::abs(n.dot(bearings2[c])) <= gate[c])) return;
      const int d = hammingDistance(d1, kf2.descriptors.ptr<uint8_t>(candidates2[c]));
      on_line.emplace_back(c, d);
      if (d < best || (d == best && best_c >= 0 && c < best_c)) {
        best = d;
        best_c = c;
      }
    });
    if (best_c < 0) continue;
    const int best_j = candidates2[best_c];
    if (!distinctOnLine(best, kf2.keypoints[best_j].pt, on_line, candidates2, kf2)) continue;
    if (best >= dist_of_2[best_j]) continue;
    dist_of_2[best_j] = best;
    match_of_2[best_j] = static_cast<int>(i);
  }
  return match_of_2;
}

std::vector<FusionLink> Matcher::searchForFusion(const FusionTarget& target, double radius) const {
  std::vector<FusionLink> out;
  const Keyframe& kf = *target.keyframe;
  const int n = static_cast<int>(kf.keypoints.size());
  if (target.candidates.empty() || n == 0) return out;
  // Keypoints bucketed in 32-pixel cells (the keyframe keeps no search grid).
  constexpr double kCell = 32.0;
  const double w = cam_.width(), h = cam_.height();
  const int cols = std::max(1, static_cast<int>(std::ceil(w / kCell))), rows = std::max(1, static_cast<int>(std::ceil(h / kCell)));
  std::vector<int> start(static_cast<size_t>(cols) * rows + 1, 0), order(n);
  auto cellOf = [&](const cv::Point2f& pt) {
    const int cx = std::min(cols - 1, std::max(0, static_cast<int>(pt.x / kCell)));
    const int cy = std::min(rows - 1, std::max(0, static_cast<int>(pt.y / kCell)));
    return cy * cols + cx;
  };
  for (int i = 0; i < n; ++i) ++start[cellOf(kf.keypoints[i].pt) + 1];
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) order[fill[cellOf(kf.keypoints[i].pt)]++] = i;

  std::vector<int> best_dist(n, p_.match_threshold_low + 1), best_point(n, -1);
  const Eigen::Vector3d center = target.T_c_w.inverse().translation();
  for (size_t c = 0; c < target.candidates.size(); ++c) {
    const LocalPoint& lp = target.candidates[c];
    Eigen::Vector2d uv;
    int octave;
    if (!projectInView(lp, target.T_c_w, center, kf.scale_factor, &uv, &octave)) continue;
    const double r = radius * kf.sigma(octave);
    const int x0 = std::max(0, static_cast<int>((uv.x() - r) / kCell)), x1 = std::min(cols - 1, static_cast<int>((uv.x() + r) / kCell));
    const int y0 = std::max(0, static_cast<int>((uv.y() - r) / kCell)), y1 = std::min(rows - 1, static_cast<int>((uv.y() + r) / kCell));
    int best = p_.match_threshold_low + 1, best_kp = -1;
    for (int cy = y0; cy <= y1; ++cy)
      for (int cx = x0; cx <= x1; ++cx)
        for (int k = start[cy * cols + cx]; k < start[cy * cols + cx + 1]; ++k) {
          const int j = order[k];
          const cv::KeyPoint& kp = kf.keypoints[j];
          if (!kf.valid[j] || std::abs(kp.octave - octave) > 1) continue;
          const double dx = kp.pt.x - uv.x(), dy = kp.pt.y - uv.y(), e2 = dx * dx + dy * dy;
          const double s = kf.sigma(kp.octave);
          if (e2 > r * r || e2 > kChi2TwoDof * s * s) continue;
          const int d = hammingDistance(lp.desc.data(), kf.descriptors.ptr<uint8_t>(j));
          if (d < best) {
            best = d;
            best_kp = j;
          }
        }
    if (best_kp >= 0 && best < best_dist[best_kp]) {
      best_dist[best_kp] = best;
      best_point[best_kp] = static_cast<int>(c);
    }
  }
  for (int j = 0; j < n; ++j)
    if (best_point[j] >= 0) out.push_back({kf.id, j, target.candidates[best_point[j]].id});
  return out;
}

}  // namespace iraf_vo
