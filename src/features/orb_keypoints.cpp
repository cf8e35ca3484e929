// ORB-SLAM's building blocks of the feature stage: per-level quota, quad-tree distribution,
// intensity-centroid orientation (declared in feature_extractor.h). ROS-free.
#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <queue>

#include "iraf_vo/features/feature_extractor.h"

namespace iraf_vo {

namespace {

constexpr int kHalfPatch = 15;      // radius of the intensity-centroid disc


struct QNode {
  float x0, y0, x1, y1;
  int begin, end;  // range of the index array
  int count() const { return end - begin; }
  float area() const { return (x1 - x0) * (y1 - y0); }
  // max-heap: largest node first (= ORB-SLAM's breadth-first expansion), then the most populated
  bool operator<(const QNode& o) const { return area() < o.area() || (area() == o.area() && count() < o.count()); }
};

}  // namespace

namespace {

// libstdc++'s std::partition (bidirectional algorithm) swaps the k-th failing element from the left with
// the k-th passing element from the right while the former lies left of the latter, and returns
// first + (number passing). The same swaps, found by two branch-free compactions instead of its
// data-dependent scans (the quad-tree's partitions mispredicted on about every other keypoint).
// at_pass[i]: the predicate of first[i].
template <class T>
T* partitionByFlags(T* first, T* last, const uint8_t* at_pass, std::vector<int>* scratch) {
  const int n = static_cast<int>(last - first);
  scratch->resize(2 * static_cast<size_t>(n) + 2);
  int* fail = scratch->data();
  int* hit = fail + n + 1;
  int nf = 0, np = 0;
  for (int i = 0; i < n; ++i) {
    fail[nf] = i;
    nf += !at_pass[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    hit[np] = i;
    np += at_pass[i] != 0;
  }
  for (int k = 0; k < nf && k < np && fail[k] < hit[k]; ++k) std::swap(first[fail[k]], first[hit[k]]);
  return first + np;
}

// A candidate as the quad-tree moves it: position, FAST score, index.
struct QItem {
  float x, y, response;
  int k;
};

}  // namespace

int* partitionLikeStd(int* first, int* last, const uint8_t* pass, std::vector<int>* scratch) {
  std::vector<uint8_t> at_pass(static_cast<size_t>(last - first));
  for (size_t i = 0; i < at_pass.size(); ++i) at_pass[i] = pass[first[i]];
  return partitionByFlags(first, last, at_pass.data(), scratch);
}

std::vector<int> featuresPerLevel(int n_features, double scale_factor, int n_levels) {
  std::vector<int> n(std::max(1, n_levels), 0);
  const double f = 1.0 / scale_factor;
  double per = n_features * (1.0 - f) / (1.0 - std::pow(f, n_levels));
  int sum = 0;
  for (int l = 0; l + 1 < n_levels; ++l) {
    n[l] = static_cast<int>(std::lround(per));
    sum += n[l];
    per *= f;
  }
  n[n_levels - 1] = std::max(n_features - sum, 0);
  return n;
}

std::vector<cv::KeyPoint> distributeQuadTree(const std::vector<cv::KeyPoint>& candidates, float x0, float y0, float x1,
                                             float y1, int n_desired) {
  std::vector<cv::KeyPoint> out;
  if (candidates.empty() || n_desired <= 0) return out;
  // The candidates in the order std::partition would leave their indices (QItem carries the coordinates
  // along so each partition reads them sequentially).
  std::vector<QItem> items(candidates.size());
  for (size_t i = 0; i < items.size(); ++i)
    items[i] = {candidates[i].pt.x, candidates[i].pt.y, candidates[i].response, static_cast<int>(i)};
  std::vector<int> scratch;
  std::vector<uint8_t> at_pass(candidates.size());
  // Same partitions as std::partition with the predicates x < split / y < split (partitionLikeStd).
  auto partition = [&](QItem* b, QItem* e, bool by_y, float split) {
    uint8_t* f = at_pass.data();
    for (const QItem* it = b; it != e; ++it) *f++ = (by_y ? it->y : it->x) < split;
    return partitionByFlags(b, e, at_pass.data(), &scratch);
  };
  QItem* const idx = items.data();
  const size_t n_items = items.size();

  // Initial nodes as in ORB-SLAM: round(w / h) square-ish nodes side by side.
  const int n_ini = std::max(1, static_cast<int>(std::lround((x1 - x0) / (y1 - y0))));
  const float h_x = (x1 - x0) / n_ini;
  std::priority_queue<QNode> open;  // nodes with > 1 keypoint, largest first
  std::vector<QNode> done;          // nodes with exactly one keypoint, or too small to split
  {
    int b = 0;
    for (int i = 0; i < n_ini; ++i) {
      const float nx0 = x0 + i * h_x, nx1 = (i + 1 == n_ini) ? x1 : x0 + (i + 1) * h_x;
      QItem* first = idx + b;
      QItem* mid = (i + 1 == n_ini) ? idx + n_items : partition(first, idx + n_items, false, nx1);
      const int e = static_cast<int>(mid - idx);
      if (e > b) {
        QNode q{nx0, y0, nx1, y1, b, e};
        if (q.count() > 1) open.push(q); else done.push_back(q);
      }
      b = e;
    }
  }
  // Split the largest node holding > 1 keypoint until there are n_desired nodes: the same order as
  // ORB-SLAM's level-by-level expansion, one node at a time so the target is met exactly (+ <= 3).
  while (!open.empty() && static_cast<int>(open.size() + done.size()) < n_desired) {
    const QNode n = open.top();
    open.pop();
    const float xm = 0.5f * (n.x0 + n.x1), ym = 0.5f * (n.y0 + n.y1);
    if (n.x1 - n.x0 < 1.f && n.y1 - n.y0 < 1.f) {  // cannot separate further
      done.push_back(n);
      continue;
    }
    QItem* b = idx + n.begin;
    QItem* e = idx + n.end;
    QItem* my = partition(b, e, true, ym);
    QItem* mt = partition(b, my, false, xm);
    QItem* mb = partition(my, e, false, xm);
    const int imt = static_cast<int>(mt - idx), imy = static_cast<int>(my - idx), imb = static_cast<int>(mb - idx);
    const QNode kids[4] = {{n.x0, n.y0, xm, ym, n.begin, imt},
                           {xm, n.y0, n.x1, ym, imt, imy},
                           {n.x0, ym, xm, n.y1, imy, imb},
                           {xm, ym, n.x1, n.y1, imb, n.end}};
    for (const QNode& k : kids) {
      if (k.count() > 1) open.push(k);
      else if (k.count() == 1) done.push_back(k);
    }
  }
  // Keep the strongest keypoint (FAST score) of each node.
  out.reserve(open.size() + done.size());
  auto best_of = [&](const QNode& n) {
    int best = n.begin;  // the first strongest in the partitions' order
    for (int i = n.begin + 1; i < n.end; ++i)
      if (idx[i].response > idx[best].response) best = i;
    out.push_back(candidates[idx[best].k]);
  };
  for (const QNode& n : done) best_of(n);
  while (!open.empty()) {
    best_of(open.top());
    open.pop();
  }
  return out;
}

namespace {

// umax[v] = half width of the intensity-centroid disc (radius 15) at row offset v; built from the disc
// u^2 + v^2 <= 15.5^2, which is symmetric in u and v.
std::vector<int> makeUmax() {
  std::vector<int> umax(kHalfPatch + 1);
  const double r2 = (kHalfPatch + 0.5) * (kHalfPatch + 0.5);
  for (int v = 0; v <= kHalfPatch; ++v) umax[v] = static_cast<int>(std::floor(std::sqrt(r2 - v * v)));
  return umax;
}

// The moments m10 = sum u I(u, v), m01 = sum v I(u, v) over the disc |u| <= umax[|v|] (integers, so any
// summation order gives the same values and the same angle).
void icMomentsScalar(const uint8_t* center, int step, const std::vector<int>& umax, int* m01_out, int* m10_out) {
  int m01 = 0, m10 = 0;
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
  for (int v = 1; v <= kHalfPatch; ++v) {
    int v_sum = 0;
    const int d = umax[v];
    for (int u = -d; u <= d; ++u) {
      const int plus = center[u + v * step], minus = center[u - v * step];
      v_sum += plus - minus;
      m10 += u * (plus + minus);
    }
    m01 += v * v_sum;
  }
  *m01_out = m01;
  *m10_out = m10;
}

#if CV_SIMD128
// The same moments with int16 dot products: per row pair +-v, lanes u = -15..0 (block A) and 0..15 (block B,
// u = 0 counted in A only), weights u (for m10) and v (for m01) zeroed outside the disc. Reads only the disc's
// bounding box.
struct IcWeights {
  // [v][block][half]: weights of the 8 int16 lanes of each half of a 16-pixel block.
  int16_t wu[kHalfPatch + 1][2][2][8];
  int16_t wv[kHalfPatch + 1][2][2][8];
  explicit IcWeights(const std::vector<int>& umax) {
    for (int v = 0; v <= kHalfPatch; ++v)
      for (int blk = 0; blk < 2; ++blk)
        for (int lane = 0; lane < 16; ++lane) {
          const int u = blk == 0 ? lane - kHalfPatch : lane;
          const bool in = std::abs(u) <= umax[v] && !(blk == 1 && u == 0);
          wu[v][blk][lane / 8][lane % 8] = static_cast<int16_t>(in ? u : 0);
          wv[v][blk][lane / 8][lane % 8] = static_cast<int16_t>(in ? v : 0);
        }
  }
};

void icMomentsSimd(const uint8_t* center, int step, const IcWeights& w, int* m01_out, int* m10_out) {
  cv::v_int32x4 m10 = cv::v_setzero_s32(), m01 = cv::v_setzero_s32();
  for (int v = 0; v <= kHalfPatch; ++v) {
    for (int blk = 0; blk < 2; ++blk) {
      const int x = blk == 0 ? -kHalfPatch : 0;
      cv::v_uint16x8 p0, p1, q0 = cv::v_setzero_u16(), q1 = q0;
      cv::v_expand(cv::v_load(center + v * step + x), p0, p1);
      if (v > 0) cv::v_expand(cv::v_load(center - v * step + x), q0, q1);
      const cv::v_int16x8 s0 = cv::v_reinterpret_as_s16(p0 + q0), s1 = cv::v_reinterpret_as_s16(p1 + q1);
      const cv::v_int16x8 d0 = cv::v_reinterpret_as_s16(p0) - cv::v_reinterpret_as_s16(q0);
      const cv::v_int16x8 d1 = cv::v_reinterpret_as_s16(p1) - cv::v_reinterpret_as_s16(q1);
      m10 += cv::v_dotprod(s0, cv::v_load(w.wu[v][blk][0])) + cv::v_dotprod(s1, cv::v_load(w.wu[v][blk][1]));
      m01 += cv::v_dotprod(d0, cv::v_load(w.wv[v][blk][0])) + cv::v_dotprod(d1, cv::v_load(w.wv[v][blk][1]));
    }
  }
  *m01_out = cv::v_reduce_sum(m01);
  *m10_out = cv::v_reduce_sum(m10);
}
#endif

}  // namespace

float intensityCentroidAngle(const cv::Mat& level, cv::Point2f pt) {
  static const std::vector<int> umax = makeUmax();
  CV_Assert(level.type() == CV_8UC1);
  CV_Assert(pt.x >= kHalfPatch && pt.y >= kHalfPatch && pt.x < level.cols - kHalfPatch &&
            pt.y < level.rows - kHalfPatch);
  const uint8_t* center = level.ptr<uint8_t>(cvRound(pt.y)) + cvRound(pt.x);
  const int step = static_cast<int>(level.step1());
  int m01 = 0, m10 = 0;
#if CV_SIMD128
  static const IcWeights weights(umax);
  icMomentsSimd(center, step, weights, &m01, &m10);
#else
  icMomentsScalar(center, step, umax, &m01, &m10);
#endif
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));  // degrees [0, 360)
}

float intensityCentroidAngleScalar(const cv::Mat& level, cv::Point2f pt) {
  static const std::vector<int> umax = makeUmax();
  CV_Assert(level.type() == CV_8UC1);
  CV_Assert(pt.x >= kHalfPatch && pt.y >= kHalfPatch && pt.x < level.cols - kHalfPatch &&
            pt.y < level.rows - kHalfPatch);
  int m01 = 0, m10 = 0;
  icMomentsScalar(level.ptr<uint8_t>(cvRound(pt.y)) + cvRound(pt.x), static_cast<int>(level.step1()), umax, &m01, &m10);
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
}

}  // namespace iraf_vo
