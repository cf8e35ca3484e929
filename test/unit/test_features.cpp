// Feature stage building blocks on synthetic data: eqs. (13)-(20) adaptive threshold, (21)-(23) culling,
// the ORB-SLAM quota / quad-tree, the extractor's contract and the YAML loader.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/test_data.h"
#include "iraf_vo/features/feature_extractor.h"

using namespace iraf_vo;

namespace {

Histogram256 histOf(const cv::Mat& img) {
  Histogram256 h{};
  accumulateHistogram(img, &h);
  return h;
}

}  // namespace

TEST(AdaptiveThreshold, OtsuOfBimodalImageLiesBetweenModes) {
  cv::Mat img(100, 200, CV_8U);
  cv::RNG rng(3);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      img.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>((c < 80 ? 60 : 170) + rng.gaussian(8.0));
  const int t = otsuThreshold(histOf(img));
  EXPECT_GT(t, 60 + 16);
  EXPECT_LT(t, 170 - 16);
  // Two spikes: any t in [60, 169] separates them; the middle of the flat maximum is returned.
  Histogram256 h{};
  h[60] = 500;
  h[170] = 300;
  const int t2 = otsuThreshold(h);
  EXPECT_GE(t2, 60);
  EXPECT_LT(t2, 170);
  EXPECT_NEAR(t2, 115, 1);
  // Degenerate histograms.
  Histogram256 one{};
  one[42] = 10;
  EXPECT_EQ(otsuThreshold(one), 42);
  EXPECT_EQ(otsuThreshold(Histogram256{}), 0);
}

TEST(AdaptiveThreshold, EntropyInBits) {
  const cv::Mat flat(50, 50, CV_8U, cv::Scalar(77));
  EXPECT_DOUBLE_EQ(histogramEntropy(histOf(flat)), 0.0);
  Histogram256 uniform;
  uniform.fill(13);
  EXPECT_NEAR(histogramEntropy(uniform), 8.0, 1e-9);  // log2(256): F_h is in bits
  Histogram256 two{};
  two[0] = 5;
  two[255] = 5;
  EXPECT_NEAR(histogramEntropy(two), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(histogramEntropy(Histogram256{}), 0.0);
}

TEST(AdaptiveThreshold, MeanGradientMagnitude) {
  EXPECT_DOUBLE_EQ(meanGradientMagnitude(cv::Mat(40, 60, CV_8U, cv::Scalar(90))), 0.0);
  // A vertical step of 100: the 3x3 Sobel gives |I_x| = 4 * 100 on the two columns next to the step.
  cv::Mat step(40, 60, CV_8U, cv::Scalar(20));
  step.colRange(30, 60).setTo(120);
  EXPECT_NEAR(meanGradientMagnitude(step), 2.0 * 400.0 / 60.0, 1e-9);
  // eq. (15)
  EXPECT_DOUBLE_EQ(globalThreshold(7.0, 60.0, 1.5, 0.2), 1.5 * 7.0 + 0.2 * 60.0);
}

TEST(AdaptiveThreshold, RowSobelGradientEqualsSpatialGradientBitForBit) {
  // F_g feeds F_t^g (eq. 15), the upper clip of every cell threshold: it must not move by one ulp.
  cv::RNG rng(9);
  for (int trial = 0; trial < 8; ++trial) {
    cv::Mat img(rng.uniform(1, 60), rng.uniform(1, 90), CV_8U);
    rng.fill(img, cv::RNG::UNIFORM, 0, 256);
    if (trial % 2) cv::GaussianBlur(img, img, cv::Size(3, 3), 0);
    const cv::Mat roi = img.cols > 4 ? img.colRange(1, img.cols - 1) : img;  // non-contiguous rows
    EXPECT_EQ(meanGradientMagnitude(roi), meanGradientMagnitudeReference(roi)) << roi.size();
  }
  const std::string euroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/1403636584763555584.png";
  const cv::Mat real = cv::imread(euroc, cv::IMREAD_GRAYSCALE);
  if (!real.empty()) {
    EXPECT_EQ(meanGradientMagnitude(real), meanGradientMagnitudeReference(real));
  }
}

TEST(AdaptiveThreshold, LocalThresholdAndClip) {
  EXPECT_DOUBLE_EQ(localThreshold(100.0, 70.0, 0.5), 15.0);  // eq. (19)
  EXPECT_DOUBLE_EQ(localThreshold(70.0, 100.0, 0.5), 15.0);
  // eq. (20): F_t = clip(F_t^l, F_t,min, F_t^g), always within the bounds
  for (double ft_l : {-3.0, 0.0, 4.0, 7.0, 12.5, 20.0, 55.0}) {
    const double ft = clipThreshold(ft_l, 7.0, 20.0);
    EXPECT_GE(ft, 7.0);
    EXPECT_LE(ft, 20.0);
    if (ft_l >= 7.0 && ft_l <= 20.0) {
      EXPECT_DOUBLE_EQ(ft, ft_l);
    }
  }
  EXPECT_DOUBLE_EQ(clipThreshold(3.0, 7.0, 20.0), 7.0);
  EXPECT_DOUBLE_EQ(clipThreshold(30.0, 7.0, 20.0), 20.0);
  // A global ceiling below the floor: the floor wins.
  EXPECT_DOUBLE_EQ(clipThreshold(30.0, 7.0, 4.0), 7.0);
  EXPECT_DOUBLE_EQ(clipThreshold(1.0, 7.0, 4.0), 7.0);
}

TEST(Distribution, QuotaIsGeometricAndSumsToTotal) {
  const std::vector<int> n = featuresPerLevel(1000, 1.2, 8);
  ASSERT_EQ(n.size(), 8u);
  int sum = 0;
  for (int v : n) sum += v;
  EXPECT_EQ(sum, 1000);
  for (int l = 1; l + 1 < 8; ++l) EXPECT_NEAR(n[l] / static_cast<double>(n[l - 1]), 1.0 / 1.2, 0.02);
  EXPECT_EQ(featuresPerLevel(10, 1.2, 1)[0], 10);
}

TEST(Distribution, QuadTreeSpreadsAndKeepsStrongest) {
  std::vector<cv::KeyPoint> c;
  cv::RNG rng(5);
  // A dense cluster in the top-left corner plus a sparse grid elsewhere.
  for (int i = 0; i < 400; ++i) c.emplace_back(rng.uniform(0.f, 40.f), rng.uniform(0.f, 40.f), 7.f, -1.f, 100.f + i);
  for (int y = 20; y < 200; y += 40)
    for (int x = 60; x < 300; x += 40) c.emplace_back(static_cast<float>(x), static_cast<float>(y), 7.f, -1.f, 1.f);
  const std::vector<cv::KeyPoint> out = distributeQuadTree(c, 0, 0, 300, 200, 60);
  EXPECT_GE(out.size(), 60u);
  EXPECT_LE(out.size(), 63u);
  int outside_cluster = 0;
  for (const cv::KeyPoint& k : out) outside_cluster += (k.pt.x >= 40 || k.pt.y >= 40);
  EXPECT_GE(outside_cluster, 25);  // the grid points are not drowned by the cluster
  // With a quota of 1 only the initial nodes (round(w / h) = 2) remain; the strongest keypoint is among them.
  const std::vector<cv::KeyPoint> one = distributeQuadTree(c, 0, 0, 300, 200, 1);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_FLOAT_EQ(std::max(one[0].response, one[1].response), 499.f);
  EXPECT_TRUE(distributeQuadTree({}, 0, 0, 10, 10, 5).empty());
}

TEST(Distribution, PartitionLikeStdIsStdPartitionsPermutation) {
  // The quad-tree's tie-break (first strongest in index order) depends on the exact permutation.
  cv::RNG rng(3);
  std::vector<int> scratch;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = trial % 50 == 0 ? 0 : rng.uniform(1, 300);
    const double density = rng.uniform(0.0, 1.0);
    std::vector<uint8_t> pass(n + 5);
    for (uint8_t& p : pass) p = rng.uniform(0.0, 1.0) < density;
    std::vector<int> a(n);
    for (int i = 0; i < n; ++i) a[i] = rng.uniform(0, n + 5);  // indices into pass, repeats allowed
    std::vector<int> b = a;
    const auto ref = std::partition(a.begin(), a.end(), [&](int k) { return pass[k] != 0; });
    int* ours = partitionLikeStd(b.data(), b.data() + n, pass.data(), &scratch);
    ASSERT_EQ(ours - b.data(), ref - a.begin()) << "trial " << trial;
    ASSERT_EQ(b, a) << "trial " << trial;
  }
}

TEST(Orientation, IntensityCentroidPointsToBrightSide) {
  cv::Mat img(64, 64, CV_8U, cv::Scalar(0));
  img.colRange(32, 64).setTo(200);  // bright to the right: angle ~ 0 deg
  EXPECT_NEAR(intensityCentroidAngle(img, cv::Point2f(32, 32)), 0.0, 2.0);
  cv::Mat img2(64, 64, CV_8U, cv::Scalar(0));
  img2.rowRange(33, 64).setTo(200);  // bright below: +y is 90 deg in image coordinates
  EXPECT_NEAR(intensityCentroidAngle(img2, cv::Point2f(32, 32)), 90.0, 2.0);
}

namespace {

// Uniform random grey levels with a saturated block, seen through an ROI (rows not contiguous): the SIMD-vs-scalar
// tests' image.
cv::Mat randomRoiWithSaturatedBlock(int seed, const cv::Size& size, const cv::Rect& block, const cv::Rect& roi) {
  cv::RNG rng(seed);
  cv::Mat img(size, CV_8U);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::rectangle(img, block, cv::Scalar(255), cv::FILLED);
  return img(roi);
}

}  // namespace

TEST(Orientation, SimdMomentsEqualScalarSums) {
  // intensityCentroidAngle (int16 dot products) against the plain sums, bit for bit: random and saturated
  // images, every position of an ROI (non-contiguous rows) down to the 15-px border.
  const cv::Mat roi = randomRoiWithSaturatedBlock(5, cv::Size(120, 90), cv::Rect(40, 30, 30, 30), cv::Rect(3, 2, 110, 80));
  int n = 0;
  for (int y = 15; y < roi.rows - 15; ++y)
    for (int x = 15; x < roi.cols - 15; ++x, ++n) {
      const cv::Point2f pt(static_cast<float>(x), static_cast<float>(y));
      ASSERT_EQ(intensityCentroidAngle(roi, pt), intensityCentroidAngleScalar(roi, pt)) << x << ", " << y;
    }
  EXPECT_GT(n, 3000);
}

namespace {

// Left half: bright, strongly textured, dense keypoints. Right half: flat dark, sparse keypoints.
struct CullScene {
  cv::Mat img;
  std::vector<cv::KeyPoint> kps;
  int n_left = 0;
};

CullScene makeCullScene() {
  CullScene s;
  s.img = cv::Mat(240, 320, CV_8U, cv::Scalar(15));
  iraf_vo_test::texturedImage(160, 240).copyTo(s.img.colRange(0, 160));
  cv::RNG rng(11);
  for (int y = 8; y < 236; y += 12)
    for (int x = 8; x < 156; x += 12) {
      s.kps.emplace_back(static_cast<float>(x), static_cast<float>(y), 31.f, 0.f, 50.f, 0);
      ++s.n_left;
    }
  for (int y = 30; y < 240; y += 70)
    for (int x = 190; x < 320; x += 60) s.kps.emplace_back(static_cast<float>(x), static_cast<float>(y), 31.f, 0.f, 5.f, 0);
  return s;
}

}  // namespace

TEST(Culling, LocalContrastSimdEqualsScalarBitForBit) {
  // H_c (eq. 22) from int16 dot products against the plain sums: every position of an ROI, including windows
  // clipped by the border, patch sizes up to and beyond the 16-px SIMD width.
  const cv::Mat roi = randomRoiWithSaturatedBlock(21, cv::Size(80, 60), cv::Rect(10, 10, 20, 20), cv::Rect(2, 1, 70, 55));
  for (int patch : {3, 7, 15, 17, 31})
    for (int y = 0; y < roi.rows; ++y)
      for (int x = 0; x < roi.cols; ++x)
        ASSERT_EQ(localContrastImpl(roi, static_cast<float>(x), static_cast<float>(y), patch, true),
                  localContrastImpl(roi, static_cast<float>(x), static_cast<float>(y), patch, false))
            << "patch " << patch << " at " << x << ", " << y;
}

TEST(Culling, FlatDarkRegionIsCulledTexturedRegionKept) {
  const CullScene s = makeCullScene();
  FeatureParams p;
  p.min_features = 0;
  // The score's order at s_min 0.4 (s_min 0.75 also culls the sparser ~20 % of this synthetic textured half;
  // test_features_real checks 0.75 on EuRoC).
  p.s_min = 0.4;
  const CullResult r = cullKeypoints(s.kps, {s.img}, s.img.size(), p);
  ASSERT_EQ(r.stability.size(), s.kps.size());
  int kept_left = 0, kept_right = 0;
  float min_left = 1e9f, max_right = -1e9f;
  for (size_t i = 0; i < s.kps.size(); ++i) {
    const bool left = static_cast<int>(i) < s.n_left;
    (left ? kept_left : kept_right) += r.keep[i];
    if (left) min_left = std::min(min_left, r.stability[i]);
    else max_right = std::max(max_right, r.stability[i]);
    EXPECT_EQ(r.keep[i] != 0, r.stability[i] >= p.s_min);
  }
  EXPECT_EQ(kept_right, 0) << "keypoints in the flat dark region must be culled";
  EXPECT_GE(kept_left, 0.95 * s.n_left) << "the textured well-lit region keeps its keypoints";
  EXPECT_GT(min_left, max_right);
  EXPECT_EQ(r.culled, static_cast<int>(s.kps.size()) - kept_left - kept_right);
  EXPECT_GT(r.culled, 0);
}

TEST(Culling, PrintedEq23RewardsLowContrast) {
  // With the printed w2 * (1 - C_light), at equal density the low-contrast keypoint scores higher;
  // the default (stated intent) is the opposite.
  FeatureParams p;
  const double lo = lightingStability(1.0, p.h_th, p.rho), hi = lightingStability(30.0, p.h_th, p.rho);
  EXPECT_LT(lo, 0.1);
  EXPECT_GT(hi, 0.9);
  EXPECT_GT(stabilityScore(1.0, hi, p), stabilityScore(1.0, lo, p));
  p.eq23_literal = true;
  EXPECT_LT(stabilityScore(1.0, hi, p), stabilityScore(1.0, lo, p));
  // Density term: denser leaves score higher.
  p.eq23_literal = false;
  EXPECT_GT(stabilityScore(2.0, 0.5, p), stabilityScore(0.1, 0.5, p));
}

TEST(Culling, NeverBelowMinimumKeepsHighestScores) {
  const CullScene s = makeCullScene();
  FeatureParams p;
  p.s_min = 2.0;  // would cull everything
  p.min_features = 40;
  const CullResult r = cullKeypoints(s.kps, {s.img}, s.img.size(), p);
  int kept = 0;
  float min_kept = 1e9f, max_dropped = -1e9f;
  for (size_t i = 0; i < s.kps.size(); ++i) {
    kept += r.keep[i];
    if (r.keep[i]) min_kept = std::min(min_kept, r.stability[i]);
    else max_dropped = std::max(max_dropped, r.stability[i]);
  }
  EXPECT_EQ(kept, 40);
  EXPECT_EQ(r.culled, static_cast<int>(s.kps.size()) - 40);
  EXPECT_GE(min_kept, max_dropped);
  // Fewer keypoints than the minimum: nothing is culled.
  p.min_features = 100000;
  EXPECT_EQ(cullKeypoints(s.kps, {s.img}, s.img.size(), p).culled, 0);
}

TEST(Culling, OffReturnsInputUnchanged) {
  const CullScene s = makeCullScene();
  FeatureParams p;
  p.culling = false;
  p.min_features = 0;
  const CullResult r = cullKeypoints(s.kps, {s.img}, s.img.size(), p);
  EXPECT_EQ(r.culled, 0);
  ASSERT_EQ(r.keep.size(), s.kps.size());
  for (size_t i = 0; i < s.kps.size(); ++i) {
    EXPECT_EQ(r.keep[i], 1);
    EXPECT_EQ(r.stability[i], 1.f);
  }
  // Through the extractor: culling off -> every detected keypoint is returned.
  FeatureExtractor fx;
  const FeatureFrame f = fx.extract(iraf_vo_test::texturedImage(), 0.0, p);
  EXPECT_EQ(f.stats.culled, 0);
  EXPECT_EQ(static_cast<int>(f.keypoints.size()), f.stats.detected);
  for (float v : f.stability) EXPECT_EQ(v, 1.f);
}

TEST(Culling, QuadTreeDensityIsRelative) {
  // Uniform grid: every leaf has the frame's mean density (D = 1).
  std::vector<cv::KeyPoint> kps;
  for (int y = 0; y < 256; y += 32)
    for (int x = 0; x < 256; x += 32) kps.emplace_back(x + 16.f, y + 16.f, 7.f);
  const std::vector<float> d = quadTreeDensity(kps, cv::Size(256, 256), 8);
  for (float v : d) EXPECT_NEAR(v, 1.0, 1e-5);
}

TEST(Extractor, CulledOutputAndConsistency) {
  const CullScene s = makeCullScene();
  FeatureExtractor fx;
  FeatureParams p;
  p.n_features = 300;
  p.min_features = 0;
  CulledFeatures culled;
  const FeatureFrame f = fx.extract(s.img, 2.0, p, &culled);
  EXPECT_EQ(static_cast<int>(culled.keypoints.size()), f.stats.culled);
  EXPECT_EQ(culled.stability.size(), culled.keypoints.size());
  EXPECT_EQ(static_cast<int>(f.keypoints.size()) + f.stats.culled, f.stats.detected);
  EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  EXPECT_EQ(f.stability.size(), f.keypoints.size());
  for (float v : f.stability) EXPECT_GE(v, p.s_min);
  for (float v : culled.stability) EXPECT_LT(v, p.s_min);
  for (const cv::KeyPoint& k : f.keypoints) EXPECT_GE(k.class_id, static_cast<int>(p.ft_min));
  EXPECT_GE(f.stats.cell_threshold_min, p.ft_min);
  EXPECT_LE(f.stats.cell_threshold_min, f.stats.cell_threshold_median);
  EXPECT_LE(f.stats.cell_threshold_median, f.stats.cell_threshold_max);
  EXPECT_LE(f.stats.cell_threshold_max, std::max(f.stats.global_threshold, p.ft_min) + 1e-9);
  // Deterministic.
  const FeatureFrame g = fx.extract(s.img, 2.0, p);
  ASSERT_EQ(g.keypoints.size(), f.keypoints.size());
  EXPECT_EQ(cv::norm(f.descriptors, g.descriptors, cv::NORM_L1), 0.0);
}

TEST(Extractor, RejectsBadInput) {
  FeatureExtractor fx;
  FeatureParams p;
  EXPECT_THROW(fx.extract(cv::Mat(), 0, p), std::invalid_argument);
  EXPECT_THROW(fx.extract(cv::Mat(50, 50, CV_8UC3, cv::Scalar(1, 2, 3)), 0, p), std::invalid_argument);
  EXPECT_THROW(fx.extract(cv::Mat(50, 50, CV_32F, cv::Scalar(1)), 0, p), std::invalid_argument);
  p.scale_factor = 0.9;
  EXPECT_THROW(fx.extract(iraf_vo_test::texturedImage(), 0, p), std::invalid_argument);
  // Tiny images give no keypoints but no crash.
  FeatureParams ok;
  const FeatureFrame f = fx.extract(cv::Mat(20, 20, CV_8U, cv::Scalar(5)), 0, ok);
  EXPECT_TRUE(f.keypoints.empty());
  EXPECT_EQ(f.descriptors.rows, 0);
}

TEST(FeatureParamsYaml, LoadsValidatesAndNamesUnknownKeys) {
  FeatureParams p;
  std::string err;
  ASSERT_TRUE(featureParamTable().load(YAML::Load("{n_features: 1500, adaptive_threshold: false, alpha: 2.5}"), &p, &err)) << err;
  EXPECT_EQ(p.n_features, 1500);
  EXPECT_FALSE(p.adaptive_threshold);
  EXPECT_DOUBLE_EQ(p.alpha, 2.5);
  EXPECT_DOUBLE_EQ(p.beta, FeatureParams().beta);

  FeatureParams q;
  EXPECT_FALSE(featureParamTable().load(YAML::Load("{n_featurez: 10}"), &q, &err));
  EXPECT_NE(err.find("n_featurez"), std::string::npos) << err;
  EXPECT_FALSE(featureParamTable().load(YAML::Load("{n_features: many}"), &q, &err));
  EXPECT_NE(err.find("n_features"), std::string::npos) << err;
  EXPECT_FALSE(featureParamTable().load(YAML::Load("{scale_factor: 0.5}"), &q, &err));
  EXPECT_NE(err.find("scale_factor"), std::string::npos) << err;
  EXPECT_FALSE(featureParamTable().load(YAML::Load("[1, 2]"), &q, &err));
  EXPECT_EQ(q.n_features, FeatureParams().n_features);  // untouched on failure
  EXPECT_TRUE(validate(FeatureParams()).empty());
}
