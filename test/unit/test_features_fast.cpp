// The fast detection path (FeatureParams::fast_path, detectFast9) against cv::FAST and the reference path:
// same corners, scores and keypoints where they must be the same. Speed is measured by iraf_vo_bench_frontend.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <set>
#include <string>
#include <utility>

#include "common/test_data.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/cell_fast_detector.h"
#include "iraf_vo/features/fast9.h"
#include "iraf_vo/features/feature_extractor.h"

using namespace iraf_vo;

namespace {

using Corner = std::pair<std::pair<int, int>, int>;  // ((x, y), score)

std::set<Corner> cornerSet(const std::vector<cv::KeyPoint>& kps, int x_begin = 0, int x_end = 1 << 30) {
  std::set<Corner> s;
  for (const cv::KeyPoint& k : kps) {
    const int x = cvRound(k.pt.x);
    if (x >= x_begin && x < x_end) s.insert({{x, cvRound(k.pt.y)}, cvRound(k.response)});
  }
  return s;
}

// Noise, blobs and a gradient: corners of every score from 1 to > 100, and saturated areas.
cv::Mat cornerRichImage() {
  cv::Mat img = iraf_vo_test::texturedImage(333, 211);
  cv::Mat noise(img.size(), CV_8U);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 60);
  cv::add(img, noise, img);
  cv::rectangle(img, cv::Rect(20, 20, 40, 30), cv::Scalar(255), cv::FILLED);
  cv::rectangle(img, cv::Rect(200, 150, 50, 40), cv::Scalar(0), cv::FILLED);
  return img;
}

// The frame of `img` on the fast path (first) and on the reference path (second), culling off.
std::pair<FeatureFrame, FeatureFrame> bothPaths(const cv::Mat& img, FeatureParams p) {
  p.culling = false;
  FeatureExtractor fx;
  p.fast_path = true;
  FeatureFrame fast = fx.extract(img, 0, p);
  p.fast_path = false;
  return {fast, fx.extract(img, 0, p)};
}

// The reference path as it was written with cv::FAST (ORB-SLAM's calls): per row of cells one call over the
// strip at T_s, one per run of adjacent cells below T_s, every corner kept iff score >= its cell's threshold,
// then the retry of empty cells (from the strip call when T_s <= retry_th, else one call on the cell).
std::vector<cv::KeyPoint> cvFastReference(const cv::Mat& img, const CellGrid& g, const std::vector<double>& thr,
                                          int th_retry) {
  std::vector<cv::KeyPoint> out, strip_kps, kps;
  for (int i = 0; i < g.n_rows; ++i) {
    if (g.y0(i) >= g.max_y - 3) continue;
    std::vector<int> th(g.n_cols, -1), count(g.n_cols, 0), sorted;
    for (int j = 0; j < g.n_cols; ++j) {
      if (g.x0(j) >= g.max_x - 3) continue;
      th[j] = std::max(1, static_cast<int>(std::lround(thr[i * g.n_cols + j])));
      sorted.push_back(th[j]);
    }
    std::sort(sorted.begin(), sorted.end());
    const int t_strip = CellFastDetector::stripThreshold(sorted, static_cast<int>(sorted.size()));
    const int ini_y = g.y0(i), max_y = std::min(ini_y + g.h_cell + 6, g.max_y);
    cv::FAST(img(cv::Rect(g.min_border, ini_y, g.max_x - g.min_border, max_y - ini_y)), strip_kps, t_strip, true);
    for (cv::KeyPoint& kp : strip_kps) {
      kp.pt += cv::Point2f(static_cast<float>(g.min_border), static_cast<float>(ini_y));
      const int j = g.colOf(kp.pt.x);
      if (th[j] < t_strip || kp.response < th[j]) continue;
      kp.class_id = th[j];
      out.push_back(kp);
      ++count[j];
    }
    for (int j = 0; j < g.n_cols;) {
      if (th[j] < 0 || th[j] >= t_strip) {
        ++j;
        continue;
      }
      int j1 = j, t_run = th[j];
      while (j1 + 1 < g.n_cols && th[j1 + 1] >= 0 && th[j1 + 1] < t_strip) t_run = std::min(t_run, th[++j1]);
      const int max_x = std::min(g.x0(j1 + 1) + 6, g.max_x);
      cv::FAST(img(cv::Rect(g.x0(j), ini_y, max_x - g.x0(j), max_y - ini_y)), kps, t_run, true);
      for (cv::KeyPoint& kp : kps) {
        kp.pt += cv::Point2f(static_cast<float>(g.x0(j)), static_cast<float>(ini_y));
        const int jj = std::min(j1, std::max(j, static_cast<int>(kp.pt.x - g.min_border - 3) / g.w_cell));
        if (kp.response < th[jj]) continue;
        kp.class_id = th[jj];
        out.push_back(kp);
        ++count[jj];
      }
      j = j1 + 1;
    }
    for (int j = 0; j < g.n_cols; ++j) {
      if (th[j] < 0 || count[j] > 0 || th_retry >= th[j]) continue;
      if (t_strip <= th_retry) {
        for (cv::KeyPoint kp : strip_kps)
          if (g.colOf(kp.pt.x) == j && kp.response >= th_retry) out.push_back(kp), out.back().class_id = th_retry;
        continue;
      }
      const int max_x = std::min(g.x0(j) + g.w_cell + 6, g.max_x);
      cv::FAST(img(cv::Rect(g.x0(j), ini_y, max_x - g.x0(j), max_y - ini_y)), kps, th_retry, true);
      for (cv::KeyPoint& kp : kps) {
        kp.pt += cv::Point2f(static_cast<float>(g.x0(j)), static_cast<float>(ini_y));
        kp.class_id = th_retry;
        out.push_back(kp);
      }
    }
  }
  return out;
}

}  // namespace

TEST(CellFast, ReferencePathEqualsCvFastCallsBitForBit) {
  // CellFastDetector's reference path (one detectFast9 pass per strip with NMS walls and lowered column
  // thresholds) against the cv::FAST calls it replaces, in order: random cell thresholds with runs, cells
  // high enough to be empty (retries from the strip call and from their own call), on real and noise images.
  std::vector<cv::Mat> images{cornerRichImage()};
  const std::string euroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/1403636584763555584.png";
  const cv::Mat real = cv::imread(euroc, cv::IMREAD_GRAYSCALE);
  if (!real.empty()) images.push_back(real);
  cv::RNG rng(2024);
  int retried = 0, compared = 0;
  for (size_t m = 0; m < images.size(); ++m) {
    for (int trial = 0; trial < 12; ++trial) {
      fast9UseAvx512(trial / 4 == 2);  // every row kernel: baseline, AVX2, AVX-512BW
      fast9UseAvx2(trial / 4 != 0);
      const CellGrid g = cellGridOfLevel(images[m].cols, images[m].rows, 35);
      std::vector<double> thr(g.cells());
      for (double& t : thr) {
        const double u = rng.uniform(0.0, 1.0);
        t = u < 0.15 ? 7.0 : (u < 0.25 ? rng.uniform(60.0, 120.0) : rng.uniform(1.0, 40.0));
      }
      const int th_retry = trial % 3 == 0 ? 30 : 7;  // 30: T_s <= retry_th in most rows
      CellFastDetector det;
      std::vector<cv::KeyPoint> ours;
      std::vector<double> cell_th;
      FeatureStats st;
      det.detect(images[m], g, thr, th_retry, false, &ours, &cell_th, &st);
      const std::vector<cv::KeyPoint> ref = cvFastReference(images[m], g, thr, th_retry);
      retried += st.cells_retried;
      ASSERT_EQ(ours.size(), ref.size()) << "image " << m << " trial " << trial;
      for (size_t k = 0; k < ref.size(); ++k) {
        ASSERT_EQ(ours[k].pt, ref[k].pt) << "image " << m << " trial " << trial << " candidate " << k;
        ASSERT_EQ(ours[k].response, ref[k].response) << "image " << m << " trial " << trial << " candidate " << k;
        ASSERT_EQ(ours[k].class_id, ref[k].class_id) << "image " << m << " trial " << trial << " candidate " << k;
        ASSERT_EQ(ours[k].size, ref[k].size);
      }
      compared += static_cast<int>(ref.size());
    }
  }
  fast9UseAvx512(true);
  fast9UseAvx2(true);
  EXPECT_GT(retried, 20) << "the retries must be exercised";
  EXPECT_GT(compared, 5000);
}

TEST(Fast9, EqualsCvFastForOneThreshold) {
  const cv::Mat img = cornerRichImage();
  Fast9Buffers buf;
  for (int t : {1, 5, 7, 12, 20, 40, 90}) {
    std::vector<cv::KeyPoint> ref, ours;
    cv::FAST(img, ref, t, true);
    const std::vector<uint8_t> th(img.cols, static_cast<uint8_t>(t));
    detectFast9(img, th.data(), &ours, &buf);
    ASSERT_FALSE(ref.empty()) << "t = " << t;
    ASSERT_EQ(ours.size(), ref.size()) << "t = " << t;
    for (size_t i = 0; i < ref.size(); ++i) {  // same order, positions and scores
      EXPECT_EQ(ours[i].pt, ref[i].pt) << "t = " << t << " corner " << i;
      EXPECT_EQ(ours[i].response, ref[i].response) << "t = " << t << " corner " << i;
    }
  }
  // An ROI (non-contiguous rows) and an image narrower than one SIMD block.
  const cv::Mat roi = img(cv::Rect(13, 9, 150, 60)), narrow = img(cv::Rect(0, 0, 18, 50)).clone();
  for (const cv::Mat& m : {roi, narrow}) {
    std::vector<cv::KeyPoint> ref, ours;
    cv::FAST(m, ref, 9, true);
    const std::vector<uint8_t> th(m.cols, 9);
    detectFast9(m, th.data(), &ours, &buf);
    EXPECT_EQ(cornerSet(ours), cornerSet(ref));
  }
}

TEST(Fast9, EqualsCvFastOnCellSizedRoisOfRandomImages) {
  // The reference path calls detectFast9 with one threshold where it used cv::FAST: strips (full width,
  // 41 rows) and runs / cells (41 + k * 35 columns) of random smoothed-noise images, every threshold.
  Fast9Buffers buf;
  for (int kernel : {0, 1, 2}) {  // all row kernels: baseline, AVX2, AVX-512BW (where the CPU has them)
  const bool avx512 = fast9UseAvx512(kernel == 2);
  const bool used = fast9UseAvx2(kernel > 0);
  SCOPED_TRACE(avx512 ? "AVX-512BW kernel" : used ? "AVX2 kernel" : "baseline kernel");
  cv::RNG rng(12);
  for (int trial = 0; trial < 6; ++trial) {
    cv::Mat img(120, 200 + trial * 7, CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    cv::GaussianBlur(img, img, cv::Size(), 0.6 + 0.3 * trial);
    for (const cv::Rect& r : {cv::Rect(16, 16, img.cols - 32, 41), cv::Rect(51, 30, 41, 41), cv::Rect(3, 50, 111, 41)}) {
      for (int t = 1; t <= 64; t += 3) {
        std::vector<cv::KeyPoint> ref, ours;
        cv::FAST(img(r), ref, t, true);
        const std::vector<uint8_t> th(r.width, static_cast<uint8_t>(t));
        detectFast9(img(r), th.data(), &ours, &buf);
        ASSERT_EQ(ours.size(), ref.size()) << "trial " << trial << " t = " << t;
        for (size_t i = 0; i < ref.size(); ++i) {
          ASSERT_EQ(ours[i].pt, ref[i].pt) << "trial " << trial << " t = " << t;
          ASSERT_EQ(ours[i].response, ref[i].response) << "trial " << trial << " t = " << t;
          ASSERT_EQ(ours[i].size, ref[i].size);
          ASSERT_EQ(ours[i].angle, ref[i].angle);
        }
      }
    }
  }
  }
  fast9UseAvx512(true);
  fast9UseAvx2(true);
}

TEST(Fast9, PerColumnThresholdIsCvFastOfEachColumnRange) {
  // Left half at 8, right half at 30: away from the border column (where non-max suppression looks at the
  // other half's corners) the corners are cv::FAST's at that half's threshold.
  const cv::Mat img = cornerRichImage();
  const int split = 160;
  std::vector<uint8_t> th(img.cols, 8);
  for (int x = split; x < img.cols; ++x) th[x] = 30;
  Fast9Buffers buf;
  std::vector<cv::KeyPoint> ours, lo, hi;
  detectFast9(img, th.data(), &ours, &buf);
  cv::FAST(img, lo, 8, true);
  cv::FAST(img, hi, 30, true);
  const std::set<Corner> left = cornerSet(lo, 0, split - 1), right = cornerSet(hi, split + 1);
  EXPECT_EQ(cornerSet(ours, 0, split - 1), left);
  EXPECT_EQ(cornerSet(ours, split + 1), right);
  EXPECT_GT(left.size(), 2 * right.size()) << "the lower threshold must find more corners";
}

TEST(FastPath, IdenticalToReferenceWithFixedThresholds) {
  const cv::Mat img = cornerRichImage();
  FeatureParams p;
  p.adaptive_threshold = false;
  p.n_features = 400;
  const auto frames = bothPaths(img, p);
  const FeatureFrame &a = frames.first, &b = frames.second;
  ASSERT_GT(a.keypoints.size(), 100u);
  ASSERT_EQ(a.keypoints.size(), b.keypoints.size());
  for (size_t i = 0; i < a.keypoints.size(); ++i) {
    EXPECT_EQ(a.keypoints[i].pt, b.keypoints[i].pt);
    EXPECT_EQ(a.keypoints[i].response, b.keypoints[i].response);
    EXPECT_EQ(a.keypoints[i].class_id, b.keypoints[i].class_id);
  }
  EXPECT_EQ(cv::norm(a.descriptors, b.descriptors, cv::NORM_L1), 0.0);
  EXPECT_EQ(a.stats.candidates, b.stats.candidates);
}

TEST(FastPath, SameKeypointsAsReferenceWithAdaptiveThresholds) {
  // Per-cell thresholds: the paths differ only by non-max suppression across the ROI border of a run of
  // low-threshold cells (reference), so nearly all candidates and keypoints coincide.
  const std::string euroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/1403636584763555584.png";
  cv::Mat img = cv::imread(euroc, cv::IMREAD_GRAYSCALE);
  if (img.empty()) img = cornerRichImage();
  Enhancer enhancer;
  const cv::Mat enhanced = enhancer.enhance(img, EnhanceParams()).image;
  const auto frames = bothPaths(enhanced, FeatureParams());
  const FeatureFrame &a = frames.first, &b = frames.second;
  ASSERT_GT(b.keypoints.size(), 300u);
  const std::set<Corner> sa = cornerSet(a.keypoints), sb = cornerSet(b.keypoints);
  size_t common = 0;
  for (const Corner& c : sa) common += sb.count(c);
  std::printf("fast path: %zu of %zu keypoints identical, candidates %d vs %d\n", common, sb.size(), a.stats.candidates, b.stats.candidates);
  EXPECT_GE(common, 0.95 * sb.size()) << common << " of " << sb.size();
  // Candidates within 2 %: the EuRoC frame differs by 0.4 % (13132 vs 13180), the synthetic fallback (333 x 211,
  // where the run borders hold a larger share of the corners) by 1.2 % (1320 vs 1305).
  EXPECT_NEAR(a.stats.candidates, b.stats.candidates, 0.02 * b.stats.candidates);
  EXPECT_EQ(a.stats.cells, b.stats.cells);
}
