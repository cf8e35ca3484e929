// ORB-SLAM's building blocks of the feature stage: per-level quota, quad-tree distribution,
// intensity-centroid orientation (declared in feature_extractor.h). ROS-free.
#include <algorithm>
#include <cmath>
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
  std::vector<int> idx(candidates.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);

  // Initial nodes as in ORB-SLAM: round(w / h) square-ish nodes side by side.
  const int n_ini = std::max(1, static_cast<int>(std::lround((x1 - x0) / (y1 - y0))));
  const float h_x = (x1 - x0) / n_ini;
  std::priority_queue<QNode> open;  // nodes with > 1 keypoint, largest first
  std::vector<QNode> done;          // nodes with exactly one keypoint, or too small to split
  {
    int b = 0;
    for (int i = 0; i < n_ini; ++i) {
      const float nx0 = x0 + i * h_x, nx1 = (i + 1 == n_ini) ? x1 : x0 + (i + 1) * h_x;
      int* first = idx.data() + b;
      int* mid = (i + 1 == n_ini) ? idx.data() + idx.size()
                                  : std::partition(first, idx.data() + idx.size(),
                                                   [&](int k) { return candidates[k].pt.x < nx1; });
      const int e = static_cast<int>(mid - idx.data());
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
    int* b = idx.data() + n.begin;
    int* e = idx.data() + n.end;
    int* my = std::partition(b, e, [&](int k) { return candidates[k].pt.y < ym; });
    int* mt = std::partition(b, my, [&](int k) { return candidates[k].pt.x < xm; });
    int* mb = std::partition(my, e, [&](int k) { return candidates[k].pt.x < xm; });
    const QNode kids[4] = {{n.x0, n.y0, xm, ym, n.begin, static_cast<int>(mt - idx.data())},
                           {xm, n.y0, n.x1, ym, static_cast<int>(mt - idx.data()), static_cast<int>(my - idx.data())},
                           {n.x0, ym, xm, n.y1, static_cast<int>(my - idx.data()), static_cast<int>(mb - idx.data())},
                           {xm, ym, n.x1, n.y1, static_cast<int>(mb - idx.data()), n.end}};
    for (const QNode& k : kids) {
      if (k.count() > 1) open.push(k);
      else if (k.count() == 1) done.push_back(k);
    }
  }
  // Keep the strongest keypoint (FAST score) of each node.
  out.reserve(open.size() + done.size());
  auto best_of = [&](const QNode& n) {
    int best = idx[n.begin];
    for (int i = n.begin + 1; i < n.end; ++i)
      if (candidates[idx[i]].response > candidates[best].response) best = idx[i];
    out.push_back(candidates[best]);
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

float icAngle(const cv::Mat& img, cv::Point2f pt, const std::vector<int>& umax) {
  const uint8_t* center = img.ptr<uint8_t>(cvRound(pt.y)) + cvRound(pt.x);
  const int step = static_cast<int>(img.step1());
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
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));  // degrees [0, 360)
}

}  // namespace

float intensityCentroidAngle(const cv::Mat& level, cv::Point2f pt) {
  static const std::vector<int> umax = makeUmax();
  CV_Assert(level.type() == CV_8UC1);
  CV_Assert(pt.x >= kHalfPatch && pt.y >= kHalfPatch && pt.x < level.cols - kHalfPatch &&
            pt.y < level.rows - kHalfPatch);
  return icAngle(level, pt, umax);
}

}  // namespace iraf_vo
