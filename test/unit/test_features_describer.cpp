// OrbDescriber: ORB's pattern read from cv::ORB, and descriptors equal to cv::ORB::compute byte for byte
// (scalar and AVX2 kernels), on synthetic textures and, when present, the shared EuRoC frames.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

#include "iraf_vo/features/cell_grid.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/features/orb_describer.h"

namespace iraf_vo {
namespace {

cv::Ptr<cv::ORB> referenceOrb() { return makeReferenceOrb(); }

// A textured test image: blurred noise plus a few rectangles and discs (corners and smooth edges).
cv::Mat texture(int cols, int rows, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat img(rows, cols, CV_8U);
  rng.fill(img, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(img, img, cv::Size(5, 5), 1.2);
  for (int i = 0; i < 30; ++i) {
    const cv::Point a(rng.uniform(0, cols), rng.uniform(0, rows));
    if (i % 2)
      cv::rectangle(img, a, a + cv::Point(rng.uniform(5, 40), rng.uniform(5, 40)), cv::Scalar(rng.uniform(0, 256)), -1);
    else
      cv::circle(img, a, rng.uniform(3, 25), cv::Scalar(rng.uniform(0, 256)), -1);
  }
  return img;
}

// FAST corners >= 19 px from the border with angles spread over [0, 360) (every 0.37 deg, then random).
std::vector<cv::KeyPoint> keypointsOf(const cv::Mat& img, int max_kps, uint64_t seed) {
  std::vector<cv::KeyPoint> kps;
  cv::FAST(img, kps, 7);
  cv::KeyPointsFilter::runByImageBorder(kps, img.size(), kEdgeThreshold + 1);
  cv::KeyPointsFilter::retainBest(kps, max_kps);
  cv::RNG rng(seed);
  for (size_t i = 0; i < kps.size(); ++i) {
    kps[i].angle = i < 973 ? 0.37f * static_cast<float>(i) : rng.uniform(0.f, 360.f);
    kps[i].octave = 0;
    kps[i].size = 31.f;
  }
  return kps;
}

// Rows of `ours` that differ from cv::ORB's descriptors of the same keypoints on `img`.
int differingRows(const cv::Mat& img, const std::vector<cv::KeyPoint>& kps, const cv::Mat& ours) {
  std::vector<cv::KeyPoint> ref_kps = kps;
  cv::Mat ref;
  referenceOrb()->compute(img, ref_kps, ref);
  EXPECT_EQ(ref_kps.size(), kps.size());
  EXPECT_EQ(ref.rows, ours.rows);
  int differ = 0;
  for (int r = 0; r < std::min(ref.rows, ours.rows); ++r) differ += cv::norm(ref.row(r), ours.row(r), cv::NORM_HAMMING) > 0;
  return differ;
}

TEST(OrbDescriber, PatternReadFromOpenCvIsTwoHundredFiftySixDistinctPairsInsideThePatch) {
  const OrbPattern& p = orbPatternFromOpenCv();
  ASSERT_TRUE(p.valid()) << "the probe could not read ORB's pattern from cv::ORB";
  std::set<std::pair<std::pair<int, int>, std::pair<int, int>>> pairs;
  for (int k = 0; k < 256; ++k) {
    EXPECT_NE(p.p0[k], p.p1[k]) << "pair " << k;
    for (const cv::Point& q : {p.p0[k], p.p1[k]}) {
      EXPECT_LE(std::abs(q.x), 15) << "pair " << k;  // a 31 x 31 patch
      EXPECT_LE(std::abs(q.y), 15) << "pair " << k;
    }
    EXPECT_EQ(p.x0[k], static_cast<float>(p.p0[k].x));
    EXPECT_EQ(p.y1[k], static_cast<float>(p.p1[k].y));
    pairs.insert({{p.p0[k].x, p.p0[k].y}, {p.p1[k].x, p.p1[k].y}});
  }
  EXPECT_EQ(pairs.size(), 256u);
}

TEST(OrbDescriber, ReadingThePatternFailsCleanlyWhenTheDescriptorIsNotOrb31) {
  // With WTA_K 3 a descriptor bit is no comparison of one point pair: no pair explains the probe's bits,
  // so the reader reports failure (and OrbDescriber would fall back to cv::ORB).
  OrbPattern p;
  EXPECT_FALSE(readOrbPattern(cv::ORB::create(500, 1.2f, 1, kEdgeThreshold, 0, 3, cv::ORB::FAST_SCORE, 31, 20), &p));
  EXPECT_FALSE(p.valid());
}

TEST(OrbDescriber, EqualsOpenCvOnSyntheticTexturesAtAllAnglesWithBothKernels) {
  OrbDescriber scalar(false), simd(true);
  ASSERT_FALSE(scalar.usesOpenCvFallback()) << "scalar kernel differed from cv::ORB at start-up";
  EXPECT_FALSE(scalar.usesSimd());
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2")) {
    EXPECT_TRUE(simd.usesSimd()) << "AVX2 kernel not in use on an AVX2 CPU";
    EXPECT_FALSE(simd.usesOpenCvFallback());
  }
#endif
  for (uint64_t seed : {1u, 2u, 3u}) {
    const cv::Mat img = texture(320 + 17 * static_cast<int>(seed), 240, seed);  // odd widths: unaligned rows
    const std::vector<cv::KeyPoint> kps = keypointsOf(img, 1500, seed);
    ASSERT_GT(kps.size(), 500u);
    cv::Mat d_scalar, d_simd;
    scalar.compute(img, kps, &d_scalar);
    simd.compute(img, kps, &d_simd);
    EXPECT_EQ(differingRows(img, kps, d_scalar), 0) << "seed " << seed;
    EXPECT_EQ(differingRows(img, kps, d_simd), 0) << "seed " << seed;
  }
}

TEST(OrbDescriber, EqualsOpenCvOnTheSharedEurocFramesAtEveryPyramidLevel) {
  const std::string file =
      std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/1403636584763555584.png";
  if (!std::ifstream(file).good()) GTEST_SKIP() << "shared EuRoC frame not found: " << file;
  const cv::Mat img = cv::imread(file, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << file;
  std::vector<cv::Mat> pyramid;
  FeatureExtractor::buildPyramid(img, 1.2, 8, &pyramid);
  OrbDescriber describer;
  ASSERT_FALSE(describer.usesOpenCvFallback()) << "would compare cv::ORB with itself";
  for (size_t l = 0; l < pyramid.size(); ++l) {
    const std::vector<cv::KeyPoint> kps = keypointsOf(pyramid[l], 600, l);
    if (kps.empty()) continue;
    cv::Mat d;
    describer.compute(pyramid[l], kps, &d);
    EXPECT_EQ(differingRows(pyramid[l], kps, d), 0) << "level " << l;
  }
}

// cv::ORB's own blur: the level inside a 23-px reflect-101 border, blurred in place as a sub-matrix.
cv::Mat opencvOrbBlur(const cv::Mat& level) {
  cv::Mat padded;
  cv::copyMakeBorder(level, padded, 23, 23, 23, 23, cv::BORDER_REFLECT_101);
  cv::Mat inner = padded(cv::Rect(23, 23, level.cols, level.rows));
  cv::GaussianBlur(inner, inner, cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
  return inner.clone();
}

TEST(OrbDescriber, BlurEqualsOpenCvsSubmatrixBlurOnEveryLevelAndOddSizes) {
  OrbDescriber describer;
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    EXPECT_TRUE(describer.usesSimdBlur()) << "AVX2 + FMA blur not in use on an AVX2 + FMA CPU";
  }
#endif
  std::vector<cv::Mat> levels;
  FeatureExtractor::buildPyramid(texture(752, 480, 11), 1.2, 8, &levels);
  for (const cv::Size& sz : {cv::Size(9, 7), cv::Size(33, 65), cv::Size(301, 199)}) {
    levels.push_back(texture(sz.width, sz.height, 12));
  }
  for (const cv::Mat& level : levels) {
    const cv::Mat ours = describer.blurLikeOrb(level).clone();
    EXPECT_EQ(cv::norm(ours, opencvOrbBlur(level), cv::NORM_INF), 0) << level.cols << "x" << level.rows;
  }
}

TEST(OrbDescriber, TheStartUpCheckRejectsAWrongPattern) {
  const OrbPattern& read = orbPatternFromOpenCv();
  ASSERT_TRUE(read.valid());
  EXPECT_TRUE(orbKernelMatchesOpenCv(false, read));
  for (int k : {0, 100, 255}) {  // one pair swapped (one bit inverted), or one point moved by a pixel
    OrbPattern swapped = read;
    std::swap(swapped.x0[k], swapped.x1[k]);
    std::swap(swapped.y0[k], swapped.y1[k]);
    EXPECT_FALSE(orbKernelMatchesOpenCv(false, swapped)) << "pair " << k << " swapped";
    OrbPattern moved = read;
    moved.x1[k] += 1.f;
    EXPECT_FALSE(orbKernelMatchesOpenCv(false, moved)) << "pair " << k << " moved";
    if (orbKernelMatchesOpenCv(true, read)) {
      EXPECT_FALSE(orbKernelMatchesOpenCv(true, swapped)) << "AVX2, pair " << k << " swapped";
    }
  }
}

TEST(OrbDescriber, AcceptsKeypointsExactlyAtTheEdgeThreshold) {
  const cv::Mat img = texture(200, 150, 8);
  OrbDescriber describer;
  const float lo = kEdgeThreshold, hi_x = 200 - kEdgeThreshold - 1, hi_y = 150 - kEdgeThreshold - 1;
  // 19 and cols - 20 are the first and last accepted positions; 19.5 rounds to 20 (accepted).
  const std::vector<cv::KeyPoint> kps = {cv::KeyPoint(lo, lo, 31.f, 30.f), cv::KeyPoint(hi_x, hi_y, 31.f, 200.f),
                                         cv::KeyPoint(lo, hi_y, 31.f, 95.f), cv::KeyPoint(hi_x, lo, 31.f, 310.f),
                                         cv::KeyPoint(lo + 0.5f, lo + 0.5f, 31.f, 1.f)};
  cv::Mat d;
  describer.compute(img, kps, &d);
  EXPECT_EQ(d.rows, 5);
  EXPECT_EQ(differingRows(img, kps, d), 0);
  for (const cv::Point2f& bad : {cv::Point2f(hi_x + 1, 75), cv::Point2f(100, hi_y + 1), cv::Point2f(lo - 0.5f, 75)}) {
    const std::vector<cv::KeyPoint> one = {cv::KeyPoint(bad, 31.f, 0.f)};  // 18.5 rounds to 18 (rejected)
    EXPECT_THROW(describer.compute(img, one, &d), std::invalid_argument) << bad;
  }
}

TEST(OrbDescriber, RejectsAKeypointCloserThanTheEdgeThresholdNamingIt) {
  const cv::Mat img = texture(200, 150, 7);
  OrbDescriber describer;
  cv::Mat d;
  std::vector<cv::KeyPoint> kps = {cv::KeyPoint(100.f, 75.f, 31.f, 10.f), cv::KeyPoint(kEdgeThreshold - 1.f, 75.f, 31.f, 0.f)};
  try {
    describer.compute(img, kps, &d);
    FAIL() << "no exception for a keypoint 18 px from the border";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keypoint 1 at (18, 75)"), std::string::npos) << e.what();
  }
  kps.pop_back();
  describer.compute(img, kps, &d);
  EXPECT_EQ(d.rows, 1);
  EXPECT_EQ(differingRows(img, kps, d), 0);
}

}  // namespace
}  // namespace iraf_vo
