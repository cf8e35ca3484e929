// Unit tests of the enhancement's noise-sized denoising (enhance.denoise_noise): off on clean images, the noise of
// a camera at high gain brought down to about the set level, and corners that repeat across noise realizations.
#include <gtest/gtest.h>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <vector>

#include "common/test_data.h"
#include "iraf_vo/enhance/enhancer.h"

using namespace iraf_vo;
using iraf_vo_test::withNoise;

namespace {

// Random grey blocks (40-200) of side `block`: corners at every block junction.
cv::Mat blockImage(int w, int h, int block) {
  cv::Mat small((h + block - 1) / block, (w + block - 1) / block, CV_8U), big;
  cv::RNG rng(11);
  rng.fill(small, cv::RNG::UNIFORM, 40, 201);
  cv::resize(small, big, cv::Size(), block, block, cv::INTER_NEAREST);
  return big(cv::Rect(0, 0, w, h)).clone();
}

// The n strongest FAST corners (threshold 20 = ORB-SLAM's iniThFAST, non-max suppressed).
std::vector<cv::KeyPoint> strongestCorners(const cv::Mat& img, size_t n) {
  std::vector<cv::KeyPoint> kps;
  cv::FAST(img, kps, 20, true);
  cv::KeyPointsFilter::retainBest(kps, static_cast<int>(n));
  return kps;
}

// Share of a's corners with a corner of b within 2 px.
double repeatability(const std::vector<cv::KeyPoint>& a, const std::vector<cv::KeyPoint>& b) {
  if (a.empty()) return 0.0;
  int hit = 0;
  for (const auto& p : a)
    for (const auto& q : b)
      if (std::hypot(p.pt.x - q.pt.x, p.pt.y - q.pt.y) <= 2.0) {
        ++hit;
        break;
      }
  return static_cast<double>(hit) / static_cast<double>(a.size());
}

}  // namespace

TEST(Denoise, SigmaFollowsThePixelNoise) {
  EnhanceParams p;
  p.denoise_noise = 0.0;  // off
  EXPECT_EQ(denoiseSigma(24.0, p), 0.0);
  p.denoise_noise = 5.0;
  EXPECT_EQ(denoiseSigma(2.0, p), 0.0);
  EXPECT_EQ(denoiseSigma(5.0, p), 0.0);
  EXPECT_NEAR(denoiseSigma(24.0, p), 24.0 / (2.0 * std::sqrt(M_PI) * 5.0), 1e-12);
  EXPECT_GT(denoiseSigma(30.0, p), denoiseSigma(24.0, p));
}

TEST(Denoise, BringsHighGainNoiseDownToTheSetLevel) {
  // A flat grey image under 24 grey levels of noise (a camera at gain ~40): the output's noise is about
  // denoise_noise; the default amount 1 without denoising passes all of it.
  const cv::Mat noisy = withNoise(cv::Mat(240, 376, CV_8U, cv::Scalar(110)), 24.0, 4);
  EnhanceParams p;
  p.mu_expected = 110.0;  // normal: no gamma term
  p.denoise_noise = 5.0;
  Enhancer e;
  const EnhanceResult r = e.enhance(noisy, p);
  EXPECT_NEAR(r.pixel_noise, 24.0, 3.0);
  EXPECT_GT(r.denoise_sigma, 1.0);
  cv::Scalar mean, sd;
  cv::meanStdDev(r.image, mean, sd);
  EXPECT_NEAR(sd[0], p.denoise_noise, 0.25 * p.denoise_noise);
  p.denoise_noise = 0.0;
  cv::meanStdDev(e.enhance(noisy, p).image, mean, sd);
  EXPECT_GT(sd[0], 20.0);
}

TEST(Denoise, LeavesCleanImagesByteIdentical) {
  const cv::Mat tex = iraf_vo_test::texturedImage(376, 240);
  const cv::Mat mild = withNoise(tex, 2.0, 6);  // EuRoC's own noise level
  EnhanceParams on, off;
  on.denoise_noise = 5.0;
  off.denoise_noise = 0.0;
  Enhancer e;
  for (const cv::Mat* img : {&tex, &mild}) {
    const EnhanceResult r = e.enhance(*img, on);
    EXPECT_EQ(r.denoise_sigma, 0.0);
    EXPECT_EQ(cv::norm(r.image, e.enhance(*img, off).image, cv::NORM_INF), 0.0);
  }
}

TEST(Denoise, CornersRepeatAcrossNoiseRealizations) {
  // The same view (grey blocks: a corner at every junction) under two draws of high-gain noise, as two frames of a
  // still camera: the strongest FAST corners of the enhanced images land on the same places far more often with
  // the denoising (0.71 vs 0.45 of them within 2 px).
  const cv::Mat tex = blockImage(376, 240, 12);
  const cv::Mat a = withNoise(tex, 24.0, 7), b = withNoise(tex, 24.0, 8);
  EnhanceParams p;
  p.mu_expected = cv::mean(a)[0];
  Enhancer e;
  auto rep = [&](double denoise_noise) {
    p.denoise_noise = denoise_noise;
    const cv::Mat ea = e.enhance(a, p).image.clone(), eb = e.enhance(b, p).image.clone();
    return repeatability(strongestCorners(ea, 300), strongestCorners(eb, 300));
  };
  const double off = rep(0.0), on = rep(5.0);
  EXPECT_GT(on, 1.3 * off) << "repeatability off " << off << ", on " << on;
  EXPECT_GT(on, 0.6);
}
