#include "iraf_vo/features/feature_culling.h"

#include "iraf_vo/features/feature_extractor.h"  // partitionLikeStd

#include <opencv2/core/hal/intrin.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace iraf_vo {

double stabilityScore(double density, double c_light, const FeatureParams& p) {
  // eq. (23): S = w1 * sigmoid(k (D - D_opt)) + w2 * (1 - C_light)   (as printed)
  // The text says low C_light marks lighting-unstable regions, so the default follows that intent and
  // uses w2 * C_light (well-lit, contrasted keypoints score higher); eq23_literal = true keeps the print.
  const double light = p.eq23_literal ? (1.0 - c_light) : c_light;
  return p.w1 * sigmoid(p.k * (density - p.d_opt)) + p.w2 * light;
}

namespace {

// Sum and sum of squares of the window's pixels (integers: any order gives the same values).
void windowSumsScalar(const cv::Mat& level, int x0, int x1, int y0, int y1, uint32_t* s_out, uint64_t* s2_out) {
  uint32_t s = 0;
  uint64_t s2 = 0;
  for (int r = y0; r <= y1; ++r) {
    const uint8_t* p = level.ptr<uint8_t>(r);
    uint32_t rs = 0, rs2 = 0;
    for (int c = x0; c <= x1; ++c) {
      rs += p[c];
      rs2 += static_cast<uint32_t>(p[c]) * p[c];
    }
    s += rs;
    s2 += rs2;
  }
  *s_out = s;
  *s2_out = s2;
}

}  // namespace

double localContrast(const cv::Mat& level, float x, float y, int patch) {
  return localContrastImpl(level, x, y, patch, true);
}

double localContrastImpl(const cv::Mat& level, float x, float y, int patch, bool simd) {
  CV_Assert(level.type() == CV_8UC1);
  const int h = patch / 2;
  const int cx = cvRound(x), cy = cvRound(y);
  const int x0 = std::max(0, cx - h), x1 = std::min(level.cols - 1, cx + h);
  const int y0 = std::max(0, cy - h), y1 = std::min(level.rows - 1, cy + h);
  if (x0 > x1 || y0 > y1) return 0.0;
  uint32_t s = 0;
  uint64_t s2 = 0;
  const int w = x1 - x0 + 1;
  // 16 bytes per row, from x0 or ending at x1, must stay inside the row.
  const int start = x0 + 16 <= level.cols ? x0 : x1 - 15;
#if CV_SIMD128
  if (simd && w <= 16 && y1 - y0 < 64 && start >= 0) {
    // Rows of <= 16 pixels as int16 dot products with a 0/1 lane mask (pixel) and with themselves (square);
    // <= 64 rows keep the int32 lanes exact.
    int16_t m[16];
    for (int k = 0; k < 16; ++k) m[k] = static_cast<int16_t>(start + k >= x0 && start + k <= x1);
    const cv::v_int16x8 m0 = cv::v_load(m), m1 = cv::v_load(m + 8);
    cv::v_int32x4 vs = cv::v_setzero_s32(), vs2 = vs;
    for (int r = y0; r <= y1; ++r) {
      cv::v_uint16x8 a, b;
      cv::v_expand(cv::v_load(level.ptr<uint8_t>(r) + start), a, b);
      const cv::v_int16x8 pa = cv::v_reinterpret_as_s16(a) * m0, pb = cv::v_reinterpret_as_s16(b) * m1;
      vs += cv::v_dotprod(pa, m0) + cv::v_dotprod(pb, m1);
      vs2 += cv::v_dotprod(pa, pa) + cv::v_dotprod(pb, pb);
    }
    s = static_cast<uint32_t>(cv::v_reduce_sum(vs));
    s2 = static_cast<uint64_t>(cv::v_reduce_sum(vs2));
  } else {
    windowSumsScalar(level, x0, x1, y0, y1, &s, &s2);
  }
#else
  (void)simd;
  (void)start;
  windowSumsScalar(level, x0, x1, y0, y1, &s, &s2);
#endif
  (void)w;
  const double n = static_cast<double>(x1 - x0 + 1) * (y1 - y0 + 1);
  const double mean = s / n;
  return std::sqrt(std::max(0.0, s2 / n - mean * mean));  // H_c
}

namespace {

struct QuadNode {
  int x0, y0, x1, y1;  // [x0, x1) x [y0, y1), level-0 pixels
  int begin, end;      // range in the index array
};

}  // namespace

std::vector<float> quadTreeDensity(const std::vector<cv::KeyPoint>& kps, cv::Size image_size, int min_node_size) {
  std::vector<float> density(kps.size(), 0.f);
  if (kps.empty() || image_size.area() <= 0) return density;
  std::vector<int> idx(kps.size()), scratch;
  std::iota(idx.begin(), idx.end(), 0);
  std::vector<uint8_t> pass(kps.size());
  // Mean density of the frame: D values are reported relative to it (see header).
  const double mean_density = static_cast<double>(kps.size()) / image_size.area();
  std::vector<QuadNode> stack;
  stack.push_back({0, 0, image_size.width, image_size.height, 0, static_cast<int>(idx.size())});
  while (!stack.empty()) {
    const QuadNode n = stack.back();
    stack.pop_back();
    const int count = n.end - n.begin;
    const int w = n.x1 - n.x0, h = n.y1 - n.y0;
    const bool split = count > 1 && w / 2 >= min_node_size && h / 2 >= min_node_size;
    if (!split) {
      // eq. (21): D = N_keypoint / A_region (divided by the frame's mean density)
      const double d = count / (static_cast<double>(w) * h) / mean_density;
      for (int i = n.begin; i < n.end; ++i) density[idx[i]] = static_cast<float>(d);
      continue;
    }
    const int xm = n.x0 + w / 2, ym = n.y0 + h / 2;
    // A leaf's density does not depend on the order inside the index array: branch-free partitions.
    int* b = idx.data() + n.begin;
    int* e = idx.data() + n.end;
    for (const int* k = b; k != e; ++k) pass[*k] = kps[*k].pt.y < ym;
    int* mid_y = partitionLikeStd(b, e, pass.data(), &scratch);
    for (const int* k = b; k != e; ++k) pass[*k] = kps[*k].pt.x < xm;
    int* mid_t = partitionLikeStd(b, mid_y, pass.data(), &scratch);
    int* mid_b = partitionLikeStd(mid_y, e, pass.data(), &scratch);
    const int ib = n.begin, it = static_cast<int>(mid_t - idx.data()), iy = static_cast<int>(mid_y - idx.data()),
              ibb = static_cast<int>(mid_b - idx.data());
    stack.push_back({n.x0, n.y0, xm, ym, ib, it});
    stack.push_back({xm, n.y0, n.x1, ym, it, iy});
    stack.push_back({n.x0, ym, xm, n.y1, iy, ibb});
    stack.push_back({xm, ym, n.x1, n.y1, ibb, n.end});
  }
  return density;
}

CullResult cullKeypoints(const std::vector<cv::KeyPoint>& kps, const std::vector<cv::Mat>& pyramid,
                         cv::Size image_size, const FeatureParams& p) {
  CullResult res;
  const size_t n = kps.size();
  res.keep.assign(n, 1);
  res.stability.assign(n, 1.f);
  if (!p.culling || n == 0) return res;

  res.density = quadTreeDensity(kps, image_size, p.min_node_size);
  res.contrast.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const int l = std::min<int>(std::max(kps[i].octave, 0), static_cast<int>(pyramid.size()) - 1);
    const double inv = 1.0 / std::pow(p.scale_factor, l);
    const double h_c = localContrast(pyramid[l], static_cast<float>(kps[i].pt.x * inv),
                                     static_cast<float>(kps[i].pt.y * inv), p.contrast_patch_size);
    res.contrast[i] = static_cast<float>(h_c);
    const double c_light = lightingStability(h_c, p.h_th, p.rho);  // eq. (22)
    res.stability[i] = static_cast<float>(stabilityScore(res.density[i], c_light, p));  // eq. (23)
  }
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    res.keep[i] = res.stability[i] >= p.s_min;
    kept += res.keep[i];
  }
  const size_t min_keep = std::min(n, static_cast<size_t>(std::max(0, p.min_features)));
  if (kept < min_keep) {
    // Never below min_features: keep the min_keep highest-S keypoints.
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::nth_element(order.begin(), order.begin() + (min_keep - 1), order.end(),
                     [&](int a, int b) { return res.stability[a] > res.stability[b]; });
    std::fill(res.keep.begin(), res.keep.end(), 0);
    for (size_t i = 0; i < min_keep; ++i) res.keep[order[i]] = 1;
    kept = min_keep;
  }
  res.culled = static_cast<int>(n - kept);
  return res;
}

}  // namespace iraf_vo
