// The fast building blocks of the adaptive threshold (eqs. 13-19) against their simple references, bit for bit:
// the cell thresholds decide the FAST corners, so they must not change by one grey level.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>

#include "common/test_data.h"
#include "iraf_vo/features/adaptive_threshold.h"
#include "iraf_vo/features/feature_extractor.h"

using namespace iraf_vo;

namespace {

// Histograms of every level-0..7 cell of the frame's pyramid (the estimator's inputs on real data).
std::vector<Histogram256> cellHistograms(const cv::Mat& gray) {
  std::vector<Histogram256> out;
  std::vector<cv::Mat> pyr;
  FeatureExtractor::buildPyramid(gray, 1.2, 8, &pyr);
  for (const cv::Mat& level : pyr) {
    const CellGrid g = cellGridOfLevel(level.cols, level.rows, 35);
    for (int i = 0; i < g.n_rows; ++i)
      for (int j = 0; j < g.n_cols; ++j) {
        const int x0 = g.x0(j), y0 = g.y0(i);
        const int x1 = std::min(x0 + g.w_cell, g.max_x), y1 = std::min(y0 + g.h_cell, g.max_y);
        if (x1 <= x0 || y1 <= y0) continue;
        Histogram256 h{};
        accumulateHistogram(level(cv::Rect(x0, y0, x1 - x0, y1 - y0)), &h);
        out.push_back(h);
      }
  }
  return out;
}

}  // namespace

TEST(AdaptiveThreshold, HistogramCountsEveryPixelOfAnRoi) {
  // accumulateHistogram (4 sub-histograms, 8 pixels per load, column tails) against a plain count, on ROIs of
  // every width 1..40 (tails 0..7) of noise and of flat images (long runs of one value), added to a prior count.
  cv::RNG rng(7);
  cv::Mat noise(60, 80, CV_8U), flat(60, 80, CV_8U, cv::Scalar(17));
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  flat(cv::Rect(30, 10, 20, 20)).setTo(250);
  for (const cv::Mat& img : {noise, flat}) {
    for (int w = 1; w <= 40; ++w) {
      const cv::Rect r(rng.uniform(0, img.cols - w + 1), rng.uniform(0, 20), w, rng.uniform(1, 40));
      Histogram256 ours{}, ref{};
      for (int b = 0; b < 256; ++b) ours[b] = ref[b] = static_cast<uint32_t>(b % 5);
      accumulateHistogram(img(r), &ours);
      for (int y = r.y; y < r.y + r.height; ++y)
        for (int x = r.x; x < r.x + r.width; ++x) ++ref[img.at<uint8_t>(y, x)];
      ASSERT_EQ(ours, ref) << "ROI " << r;
    }
  }
}

TEST(AdaptiveThreshold, OtsuEqualsReference) {
  cv::RNG rng(12);
  int checked = 0;
  auto check = [&](const Histogram256& h) {
    ASSERT_EQ(otsuThreshold(h), otsuThresholdReference(h));
    ++checked;
  };
  // One non-empty bin anywhere (no split: that value).
  for (int a = 0; a < 256; ++a) {
    Histogram256 h{};
    h[a] = 1 + a;
    check(h);
    EXPECT_EQ(otsuThreshold(h), a);
  }
  // Two spikes, every pair of bins and a few count ratios: flat maxima over the empty bins between them.
  for (int a = 0; a < 256; ++a)
    for (int b = a + 1; b < 256; ++b) {
      Histogram256 h{};
      h[a] = 1 + static_cast<uint32_t>(rng.uniform(0, 3000));
      h[b] = (b - a) % 5 == 0 ? h[a] : 1 + static_cast<uint32_t>(rng.uniform(0, 3000));
      check(h);
    }
  // Symmetric histograms: sigma_c^2 has two exactly equal maxima at different t.
  for (int trial = 0; trial < 2000; ++trial) {
    Histogram256 h{};
    const int half = rng.uniform(1, 60), centre = rng.uniform(half, 256 - half);
    for (int d = 0; d < half; ++d) {
      const uint32_t c = rng.uniform(0, 4) == 0 ? 0 : static_cast<uint32_t>(rng.uniform(1, 200));
      h[centre - 1 - d] = c;
      if (centre + d < 256) h[centre + d] = c;
    }
    check(h);
  }
  // Sparse spikes, Gaussian mixtures (cell-like, 1 .. 20000 pixels), uniform noise, saturated ends.
  for (int trial = 0; trial < 20000; ++trial) {
    Histogram256 h{};
    const int kind = trial % 4;
    if (kind == 0) {
      for (int s = rng.uniform(1, 7); s > 0; --s) h[rng.uniform(0, 256)] += rng.uniform(1, 500);
    } else if (kind == 1) {
      const int n = rng.uniform(1, 20000), modes = rng.uniform(1, 4);
      for (int i = 0; i < n; ++i) {
        const double mu = 40.0 + 80.0 * (i % modes), sd = 1.0 + 3.0 * (trial % 7);
        h[cv::saturate_cast<uint8_t>(mu + rng.gaussian(sd))]++;
      }
    } else if (kind == 2) {
      const int lo = rng.uniform(0, 256), hi = rng.uniform(lo, 256);
      for (int i = rng.uniform(1, 3000); i > 0; --i) h[rng.uniform(lo, hi + 1)]++;
    } else {
      h[0] = rng.uniform(0, 1000);
      h[255] = rng.uniform(0, 1000);
      for (int i = rng.uniform(0, 500); i > 0; --i) h[rng.uniform(0, 256)]++;
    }
    check(h);
  }
  // Beyond the fast path's size limit (4e6 pixels) the reference is used.
  Histogram256 big{};
  big[10] = 3000000;
  big[200] = 2500000;
  big[90] = 7;
  check(big);
  check(Histogram256{});
  // Real cells: EuRoC frames, raw and equalized.
  for (int index : {0, 150, 400}) {
    cv::Mat img = iraf_vo_test::eurocFrame(index);
    if (img.empty()) break;
    for (const Histogram256& h : cellHistograms(img)) check(h);
    cv::equalizeHist(img, img);
    for (const Histogram256& h : cellHistograms(img)) check(h);
  }
  RecordProperty("histograms", checked);
}

TEST(AdaptiveThreshold, GradientKernelsEqualReferenceBitForBit) {
  // F_g feeds F_t^g (eq. 15), the upper clip of every cell threshold: the AVX2 and the baseline row kernels must
  // both give meanGradientMagnitudeReference's double exactly, for every row length (vector steps and tails).
  cv::RNG rng(21);
  std::vector<cv::Mat> images;
  for (int cols = 1; cols <= 80; ++cols) {
    cv::Mat img(rng.uniform(1, 12), cols + 2, CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    if (cols % 3 == 0) cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
    images.push_back(img.colRange(1, cols + 1));  // non-contiguous rows
  }
  for (int index : {0, 300}) {
    const cv::Mat real = iraf_vo_test::eurocFrame(index);
    if (!real.empty()) images.push_back(real);
  }
  cv::Mat big(480, 752, CV_8U);
  rng.fill(big, cv::RNG::UNIFORM, 0, 256);
  images.push_back(big);
  const bool had_avx2 = gradientUseAvx2(true);
  for (bool avx2 : {true, false}) {
    if (avx2 && !had_avx2) continue;  // CPU without AVX2: the baseline kernel only
    gradientUseAvx2(avx2);
    cv::Mat scratch;
    for (const cv::Mat& img : images)
      ASSERT_EQ(meanGradientMagnitude(img, &scratch), meanGradientMagnitudeReference(img))
          << img.size() << (avx2 ? " avx2" : " baseline");
  }
  gradientUseAvx2(true);
}

namespace {

// A scene-like texture: random grey rectangles on a grey background, slightly blurred.
cv::Mat rectangleTexture(cv::Size size, unsigned seed) {
  cv::RNG rng(seed);
  cv::Mat img(size, CV_8UC1, cv::Scalar(110));
  for (int k = 0; k < 900; ++k) {
    const int x = rng.uniform(0, size.width), y = rng.uniform(0, size.height);
    const int w = rng.uniform(3, 40), h = rng.uniform(3, 40);
    cv::rectangle(img, cv::Rect(x, y, w, h), cv::Scalar(rng.uniform(30, 220)), cv::FILLED);
  }
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.2);
  return img;
}

// The level-0 cell thresholds F_t of eq. (20), with its clips opened so the local term of eq. (19) alone decides.
std::vector<double> openCellThresholds(const cv::Mat& img, bool cell_mean) {
  FeatureParams p;
  p.cell_mean_contrast = cell_mean;
  p.alpha = 10.0;
  p.ft_min = 1.0;
  CellThresholdEstimator est;
  FeatureStats st;
  std::vector<double> t;
  est.estimate(img, cellGridOfLevel(img.cols, img.rows, p.cell_size), p, true, &st, &t);
  return t;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Median over the level-0 cells of |F_t(b) - F_t(a)| / max(F_t(a), F_t(b)).
double medianRelativeThresholdChange(const cv::Mat& a, const cv::Mat& b, bool cell_mean) {
  const std::vector<double> ta = openCellThresholds(a, cell_mean), tb = openCellThresholds(b, cell_mean);
  std::vector<double> rel;
  for (size_t c = 0; c < ta.size(); ++c) rel.push_back(std::abs(tb[c] - ta[c]) / std::max({ta[c], tb[c], 1.0}));
  return median(rel);
}

}  // namespace

TEST(AdaptiveThreshold, MeanDeviationIsTheCellAverageOfTheCentreContrast) {
  // meanDeviationFrom(h, t_o) = |I_m - t_o| of eq. (19) averaged over every pixel of the cell taken as I_m.
  const cv::Mat img = rectangleTexture(cv::Size(70, 50), 3);
  Histogram256 h{};
  accumulateHistogram(img, &h);
  const int t_o = otsuThreshold(h);
  double sum = 0.0;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) sum += std::abs(img.at<uint8_t>(r, c) - t_o);
  EXPECT_NEAR(meanDeviationFrom(h, t_o), sum / img.total(), 1e-9);
  EXPECT_EQ(meanDeviationFrom(Histogram256{}, 7), 0.0);
}

TEST(AdaptiveThreshold, CellThresholdsFollowTheCellNotTheContentUnderItsCentre) {
  // The camera moves 2 px right, 1 px down between two frames: the cells' content barely changes, so their FAST
  // thresholds should not either. The centre patch's |I_m - t_o| jumps wherever an edge crosses the centre
  // (median change 14 % of the threshold on this texture); the cell average moves by 2 %.
  const cv::Mat scene = rectangleTexture(cv::Size(760, 490), 11);
  const cv::Mat a = scene(cv::Rect(4, 4, 752, 480)), b = scene(cv::Rect(2, 3, 752, 480));
  const double cell = medianRelativeThresholdChange(a, b, true);
  const double centre = medianRelativeThresholdChange(a, b, false);
  EXPECT_LT(cell, 0.08);
  EXPECT_GT(centre, 3.0 * cell);
  // An exposure step (x1.6, no clipping) scales the cell contrast with the gain, as FAST scores scale.
  cv::Mat dim, bright;
  a.convertTo(dim, CV_8U, 0.5);
  a.convertTo(bright, CV_8U, 0.8);
  const std::vector<double> td = openCellThresholds(dim, true), tb = openCellThresholds(bright, true);
  std::vector<double> ratio;
  for (size_t c = 0; c < td.size(); ++c)
    if (td[c] > 2.0) ratio.push_back(tb[c] / td[c]);
  ASSERT_GT(ratio.size(), td.size() / 2);
  EXPECT_NEAR(median(ratio), 1.6, 0.1);
}
