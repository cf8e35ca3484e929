#include "iraf_vo/features/feature_extractor.h"

#include "iraf_vo/common/cpu_clock.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <queue>
#include <stdexcept>

namespace iraf_vo {

namespace {

constexpr int kEdgeThreshold = 19;  // ORB-SLAM EDGE_THRESHOLD: keypoints stay >= 19 px from the level border
constexpr int kPatchSize = 31;      // ORB patch (descriptor) size
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

FeatureExtractor::FeatureExtractor() : umax_(makeUmax()) {
  // Only ORB's rotated-BRIEF descriptor computation is used (keypoints are provided, one level at a time).
  orb_ = cv::ORB::create(500, 1.2f, 1, kEdgeThreshold, 0, 2, cv::ORB::FAST_SCORE, kPatchSize, 20);
}

void FeatureExtractor::buildPyramid(const cv::Mat& gray8, double scale_factor, int n_levels,
                                    std::vector<cv::Mat>* pyramid) {
  pyramid->resize(n_levels);
  (*pyramid)[0] = gray8;
  double scale = 1.0;
  for (int l = 1; l < n_levels; ++l) {
    scale *= scale_factor;
    const cv::Size sz(static_cast<int>(std::lround(gray8.cols / scale)),
                      static_cast<int>(std::lround(gray8.rows / scale)));
    if (sz.width < 1 || sz.height < 1) {
      (*pyramid)[l] = cv::Mat();
      continue;
    }
    cv::resize((*pyramid)[l - 1], (*pyramid)[l], sz, 0, 0, cv::INTER_LINEAR);
  }
}

FeatureFrame FeatureExtractor::extract(const cv::Mat& gray8, double stamp, const FeatureParams& p,
                                       CulledFeatures* culled) {
  if (gray8.empty()) throw std::invalid_argument("FeatureExtractor: empty image");
  if (gray8.type() != CV_8UC1)
    throw std::invalid_argument("FeatureExtractor: expected CV_8UC1 image, got type " + std::to_string(gray8.type()));
  const std::string err = validate(p);
  if (!err.empty()) throw std::invalid_argument("FeatureExtractor: invalid parameters: " + err);

  FeatureFrame frame;
  frame.stamp = stamp;
  frame.width = gray8.cols;
  frame.scale_factor = p.scale_factor;
  frame.height = gray8.rows;
  FeatureStats& st = frame.stats;
  if (culled) {
    culled->keypoints.clear();
    culled->stability.clear();
  }

  auto t_detect = threadCpuMs();
  double ms_threshold = 0.0;
  // Level 0 is copied so the frame never aliases caller memory kept in pyramid().
  gray8.copyTo(level0_);
  buildPyramid(level0_, p.scale_factor, p.n_levels, &pyramid_);
  const std::vector<int> quota = featuresPerLevel(p.n_features, p.scale_factor, p.n_levels);

  std::vector<double> cell_thresholds;
  std::vector<std::vector<cv::KeyPoint>> level_kps(p.n_levels);  // level coordinates
  std::vector<cv::KeyPoint> all_kps;                              // level-0 coordinates
  all_kps.reserve(p.n_features + 16);
  std::vector<cv::KeyPoint> candidates, cell_kps;
  candidates.reserve(4 * p.n_features);

  double scale = 1.0;
  for (int l = 0; l < p.n_levels; ++l, scale *= p.scale_factor) {
    const cv::Mat& img = pyramid_[l];
    const int min_border = kEdgeThreshold - 3;
    const int max_bx = img.cols - kEdgeThreshold + 3, max_by = img.rows - kEdgeThreshold + 3;
    const int width = max_bx - min_border, height = max_by - min_border;
    if (img.empty() || width < 8 || height < 8) continue;
    const int n_cols = std::max(1, width / p.cell_size), n_rows = std::max(1, height / p.cell_size);
    const int w_cell = (width + n_cols - 1) / n_cols, h_cell = (height + n_rows - 1) / n_rows;

    // ---- thresholds per cell ----
    auto t_th = threadCpuMs();
    const int n_cells = n_rows * n_cols;
    thresholds_.assign(n_cells, static_cast<double>(p.ini_th_fast));
    double retry_th = p.min_th_fast;
    if (p.adaptive_threshold) {
      Histogram256 level_hist{};
      otsu_.resize(n_cells);
      center_.resize(n_cells);
      const int hw = p.center_window / 2;
      for (int i = 0; i < n_rows; ++i) {
        const int y0 = min_border + i * h_cell, y1 = std::min(y0 + h_cell, max_by);
        for (int j = 0; j < n_cols; ++j) {
          const int x0 = min_border + j * w_cell, x1 = std::min(x0 + w_cell, max_bx);
          const int c = i * n_cols + j;
          if (y1 <= y0 || x1 <= x0) {
            otsu_[c] = 0;
            center_[c] = 0;
            continue;
          }
          Histogram256 h{};
          accumulateHistogram(img(cv::Rect(x0, y0, x1 - x0, y1 - y0)), &h);
          if (l == 0)
            for (int b = 0; b < 256; ++b) level_hist[b] += h[b];
          otsu_[c] = otsuThreshold(h);  // eqs. (16)-(18): t_o of the subregion
          // I_m of eq. (19). The paper uses the single centre pixel G(size/2, size/2); here the mean of a
          // center_window^2 patch at the centre (center_window = 1 gives the paper's pixel), because one
          // pixel makes F_t^l follow sensor noise.
          const int cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
          const cv::Rect win = cv::Rect(cx - hw, cy - hw, 2 * hw + 1, 2 * hw + 1) & cv::Rect(0, 0, img.cols, img.rows);
          int sum = 0;
          for (int r = win.y; r < win.y + win.height; ++r) {
            const uint8_t* row = img.ptr<uint8_t>(r);
            for (int x = win.x; x < win.x + win.width; ++x) sum += row[x];
          }
          center_[c] = static_cast<double>(sum) / win.area();
        }
      }
      // The global metrics (eqs. 13-15) are computed once, on level 0 (the enhanced image, as in the paper):
      // F_h over the detection area (the union of the level-0 cells), F_g over the whole image. Every level
      // uses this F_t^g as the upper clip; the per-cell F_t^l adapts to each level.
      if (l == 0) {
        st.entropy = histogramEntropy(level_hist);                          // eq. (13): F_h
        st.gradient = meanGradientMagnitude(img, &dx_, &dy_, &mag_);        // eq. (14): F_g
        st.global_threshold = globalThreshold(st.entropy, st.gradient, p.alpha, p.beta);  // eq. (15): F_t^g
      }
      const double ft_g = st.global_threshold;
      for (int c = 0; c < n_cells; ++c) {
        const double ft_l = localThreshold(center_[c], otsu_[c], p.delta);  // eq. (19): F_t^l
        thresholds_[c] = clipThreshold(ft_l, p.ft_min, ft_g);               // eq. (20): F_t
      }
      retry_th = p.ft_min;
    } else if (l == 0) {
      st.global_threshold = p.ini_th_fast;
    }
    ms_threshold += threadCpuMsSince(t_th);

    // ---- FAST with a threshold per cell ----
    // ORB-SLAM runs cv::FAST once per cell (ROI = cell + 3 px each side). cv::FAST on 41-px-wide ROIs is
    // ~3x slower per pixel than on full rows (SIMD tails, per-call setup), so each row of cells ("strip")
    // is scanned in one call at the strip's threshold T_s and every corner is kept iff its FAST score
    // >= its cell's threshold. This is exactly FAST at the cell threshold: a corner at threshold t is a
    // corner at any t' < t with score >= t, and non-max suppression only compares corners' scores.
    // T_s is chosen per strip (cost model below) so a few low-threshold cells do not make FAST scan the
    // whole strip at a low threshold; runs of cells below T_s get their own call.
    // Empty cells are retried at retry_th (ORB-SLAM's minThFAST retry). Each pixel belongs to one cell,
    // so unlike ORB-SLAM's overlapping ROIs no corner is reported twice.
    candidates.clear();
    const int th_retry = std::max(1, static_cast<int>(std::lround(retry_th)));
    cell_th_.resize(n_cols);
    cell_count_.resize(n_cols);
    sorted_th_.resize(n_cols);
    auto fast_cell = [&](int ini_x, int ini_y, int max_y, int th, int* count) {
      const int max_x = std::min(ini_x + w_cell + 6, max_bx);
      cv::FAST(img(cv::Rect(ini_x, ini_y, max_x - ini_x, max_y - ini_y)), cell_kps, th, true);
      for (cv::KeyPoint& kp : cell_kps) {
        kp.pt.x += ini_x;
        kp.pt.y += ini_y;
        kp.class_id = th;
        candidates.push_back(kp);
      }
      *count = static_cast<int>(cell_kps.size());
    };
    for (int i = 0; i < n_rows; ++i) {
      const int ini_y = min_border + i * h_cell;
      if (ini_y >= max_by - 3) continue;
      const int max_y = std::min(ini_y + h_cell + 6, max_by);
      int n_valid = 0;
      for (int j = 0; j < n_cols; ++j) {
        cell_count_[j] = 0;
        if (min_border + j * w_cell >= max_bx - 3) {
          cell_th_[j] = -1;  // no pixel left for this cell (ORB-SLAM skips it too)
          continue;
        }
        cell_th_[j] = std::max(1, static_cast<int>(std::lround(thresholds_[i * n_cols + j])));
        cell_thresholds.push_back(thresholds_[i * n_cols + j]);
        sorted_th_[n_valid++] = cell_th_[j];
        ++st.cells;
      }
      if (n_valid == 0) continue;
      // T_s: the cell threshold minimising a cost model of cv::FAST measured on EuRoC (per cell, us):
      // scanning a cell inside a strip at threshold T ~ 0.5 + 60 / T, its own call ~ 5 + 1.2 (0.5 + 60 / T).
      // (Always scanning at the strip minimum was 13 % slower on EuRoC, constants 1 / 1.0 or 20 / 2 2-6 %.)
      std::sort(sorted_th_.begin(), sorted_th_.begin() + n_valid);
      int t_strip = sorted_th_[0];
      {
        double best = 1e30, below = 0.0;
        for (int k = 0; k < n_valid; ++k) {
          const double t = sorted_th_[k];
          if (k == 0 || sorted_th_[k] != sorted_th_[k - 1]) {
            const double cost = n_valid * (0.5 + 60.0 / t) + below;
            if (cost < best) {
              best = cost;
              t_strip = sorted_th_[k];
            }
          }
          below += 5.0 + 1.2 * (0.5 + 60.0 / t);
        }
      }
      // Strip scan: detection area x in [min_border + 3, max_bx - 3), the union of the cells' areas.
      cv::FAST(img(cv::Rect(min_border, ini_y, max_bx - min_border, max_y - ini_y)), strip_kps_, t_strip, true);
      for (cv::KeyPoint& kp : strip_kps_) {
        kp.pt.x += min_border;
        kp.pt.y += ini_y;
        const int j = std::min(n_cols - 1, std::max(0, static_cast<int>(kp.pt.x - min_border - 3) / w_cell));
        if (cell_th_[j] < t_strip || kp.response < cell_th_[j]) continue;
        kp.class_id = cell_th_[j];
        candidates.push_back(kp);
        ++cell_count_[j];
      }
      // Cells below T_s: one call per run of adjacent such cells, at the run's lowest threshold, every
      // corner again filtered by its own cell's threshold.
      for (int j = 0; j < n_cols;) {
        if (cell_th_[j] < 0 || cell_th_[j] >= t_strip) {
          ++j;
          continue;
        }
        int j1 = j, t_run = cell_th_[j];
        while (j1 + 1 < n_cols && cell_th_[j1 + 1] >= 0 && cell_th_[j1 + 1] < t_strip) t_run = std::min(t_run, cell_th_[++j1]);
        const int ini_x = min_border + j * w_cell;
        const int max_x = std::min(min_border + (j1 + 1) * w_cell + 6, max_bx);
        cv::FAST(img(cv::Rect(ini_x, ini_y, max_x - ini_x, max_y - ini_y)), cell_kps, t_run, true);
        for (cv::KeyPoint& kp : cell_kps) {
          kp.pt.x += ini_x;
          kp.pt.y += ini_y;
          const int jj = std::min(j1, std::max(j, static_cast<int>(kp.pt.x - min_border - 3) / w_cell));
          if (kp.response < cell_th_[jj]) continue;
          kp.class_id = cell_th_[jj];
          candidates.push_back(kp);
          ++cell_count_[jj];
        }
        j = j1 + 1;
      }
      for (int j = 0; j < n_cols; ++j) {
        const int th = cell_th_[j];
        if (th < 0) continue;
        const int ini_x = min_border + j * w_cell;
        if (cell_count_[j] > 0 || th_retry >= th) continue;
        ++st.cells_retried;
        if (t_strip <= th_retry) {  // the strip scan already holds the retry corners of this cell
          for (const cv::KeyPoint& kp : strip_kps_) {
            const int jj = std::min(n_cols - 1, std::max(0, static_cast<int>(kp.pt.x - min_border - 3) / w_cell));
            if (jj != j || kp.response < th_retry) continue;
            cv::KeyPoint k = kp;
            k.class_id = th_retry;
            candidates.push_back(k);
          }
        } else {
          fast_cell(ini_x, ini_y, max_y, th_retry, &cell_count_[j]);
        }
      }
    }
    st.candidates += static_cast<int>(candidates.size());

    // ---- quad-tree distribution with the level's quota, orientation, level-0 coordinates ----
    std::vector<cv::KeyPoint>& kps = level_kps[l];
    kps = distributeQuadTree(candidates, static_cast<float>(min_border), static_cast<float>(min_border),
                             static_cast<float>(max_bx), static_cast<float>(max_by), quota[l]);
    const float size = static_cast<float>(kPatchSize * scale);
    for (cv::KeyPoint& kp : kps) {
      kp.angle = icAngle(img, kp.pt, umax_);
      kp.octave = l;
      kp.size = size;
      cv::KeyPoint k0 = kp;
      k0.pt *= static_cast<float>(scale);
      all_kps.push_back(k0);
    }
  }
  st.detected = static_cast<int>(all_kps.size());
  double ms_detect = threadCpuMsSince(t_detect) - ms_threshold;

  // ---- culling (eqs. 21-23) ----
  auto t_cull = threadCpuMs();
  const CullResult cr = cullKeypoints(all_kps, pyramid_, gray8.size(), p);
  st.culled = cr.culled;
  st.ms_cull = threadCpuMsSince(t_cull);

  // ---- descriptors of the kept keypoints (rotated BRIEF), level by level ----
  auto t_desc = threadCpuMs();
  frame.keypoints.reserve(all_kps.size() - cr.culled);
  frame.stability.reserve(all_kps.size() - cr.culled);
  frame.descriptors.create(static_cast<int>(all_kps.size()) - cr.culled, 32, CV_8U);
  size_t g = 0;  // index into all_kps (same order as level_kps concatenated)
  int row = 0;
  std::vector<cv::KeyPoint> lk;
  std::vector<size_t> lk_idx;
  for (int l = 0; l < p.n_levels; ++l) {
    lk.clear();
    lk_idx.clear();
    for (size_t i = 0; i < level_kps[l].size(); ++i, ++g) {
      if (cr.keep[g]) {
        cv::KeyPoint k = level_kps[l][i];
        k.octave = 0;  // ORB sees the level image as a single-level pyramid
        lk.push_back(k);
        lk_idx.push_back(g);
      } else if (culled) {
        culled->keypoints.push_back(all_kps[g]);
        culled->stability.push_back(cr.stability[g]);
      }
    }
    if (lk.empty()) continue;
    const size_t n_in = lk.size();
    orb_->compute(pyramid_[l], lk, desc_);
    if (lk.size() != n_in || desc_.rows != static_cast<int>(n_in))
      throw std::logic_error("FeatureExtractor: ORB descriptor computation dropped keypoints (border)");
    desc_.copyTo(frame.descriptors.rowRange(row, row + desc_.rows));
    row += desc_.rows;
    for (size_t i : lk_idx) {
      frame.keypoints.push_back(all_kps[i]);
      frame.stability.push_back(cr.stability[i]);
    }
  }
  st.ms_describe = threadCpuMsSince(t_desc);
  ms_detect += st.ms_describe;

  st.ms_threshold = ms_threshold;
  st.ms_detect = ms_detect;
  if (!cell_thresholds.empty()) {
    auto mm = std::minmax_element(cell_thresholds.begin(), cell_thresholds.end());
    st.cell_threshold_min = *mm.first;
    st.cell_threshold_max = *mm.second;
    auto mid = cell_thresholds.begin() + cell_thresholds.size() / 2;
    std::nth_element(cell_thresholds.begin(), mid, cell_thresholds.end());
    st.cell_threshold_median = *mid;
  }
  return frame;
}

}  // namespace iraf_vo
