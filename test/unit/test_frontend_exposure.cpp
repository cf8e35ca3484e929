// Front-end consistency under exposure changes (an auto-exposure camera): the same EuRoC frame at two exposures,
// geometry unchanged, so a keypoint is repeated when the other exposure has one within 2 px (measureRepeatability
// with the identity). Skips with a message when the EuRoC frames are absent.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <string>

#include "iraf_vo/eval/keypoint_repeatability.h"
#include "iraf_vo/pipeline/front_end.h"

using namespace iraf_vo;

namespace {

const std::string kEuroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/data/";
const char* const kFrames[] = {"1403636586263555584.png", "1403636590763555584.png", "1403636597763555584.png"};

cv::Mat loadEuroc(const std::string& name) { return cv::imread(kEuroc + name, cv::IMREAD_GRAYSCALE); }

/// The image with its grey levels multiplied by g (saturating at 255, as a sensor clips).
cv::Mat exposed(const cv::Mat& img, double g) {
  cv::Mat out;
  img.convertTo(out, CV_8U, g);
  return out;
}

/// The gain that brings img's mean grey level to eq. (10)'s t (mean = mu_expected (1 + t)), by bisection (clipping
/// makes the mean non-linear in the gain).
double gainForT(const cv::Mat& img, double t, const EnhanceParams& cfg) {
  const double target = cfg.mu_expected * (1.0 + t);
  double lo = 0.01, hi = 20.0;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (cv::mean(exposed(img, mid))[0] < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Repeatability of `mode`'s keypoints between img at gains g_a and g_b (both frames through one FrontEnd, in order).
double repeatability(FrontEndMode mode, const cv::Mat& img, double g_a, double g_b) {
  EnhanceParams ep;
  FeatureParams fp;
  applyFrontEndMode(mode, &ep, &fp);
  FrontEnd fe(ep, fp);
  const FeatureFrame a = fe.process(exposed(img, g_a), 0.0);
  const FeatureFrame b = fe.process(exposed(img, g_b), 0.05);
  return measureRepeatability(a, {}, {}, b, detectionArea(img.cols, img.rows), 2.0).repeatability();
}

}  // namespace

// The enhancement's gamma correction switches on when |t| of eq. (10) passes brightness_threshold. A 2 % exposure
// change across that boundary must change the enhanced image about as little as it changes the input (with the
// paper's hard switch the dim side was brightened by a whole AGCWD curve: mean |difference| 37 grey levels, the
// bright side darkened by 18).
TEST(FrontEndExposure, EnhancedImageContinuousAcrossBrightnessBoundary) {
  const cv::Mat img = loadEuroc(kFrames[0]);
  if (img.empty()) GTEST_SKIP() << "EuRoC frame not found under " << kEuroc;
  const EnhanceParams cfg;
  Enhancer enhancer;
  for (const double side : {-1.0, 1.0}) {
    const double t_in = side * (cfg.brightness_threshold - 0.01), t_out = side * (cfg.brightness_threshold + 0.01);
    const cv::Mat a = exposed(img, gainForT(img, t_in, cfg)), b = exposed(img, gainForT(img, t_out, cfg));
    const EnhanceResult ea = enhancer.enhance(a, cfg), eb = enhancer.enhance(b, cfg);
    ASSERT_EQ(ea.brightness, BrightnessClass::kNormal);
    ASSERT_NE(eb.brightness, BrightnessClass::kNormal);
    cv::Mat d_in, d_out;
    cv::absdiff(a, b, d_in);
    cv::absdiff(ea.image, eb.image, d_out);
    const double in = cv::mean(d_in)[0], out = cv::mean(d_out)[0];
    std::printf("[ info ] t %.2f -> %.2f: mean |input difference| %.2f, |enhanced difference| %.2f (gamma weight %.2f)\n",
                t_in, t_out, in, out, eb.gamma_weight);
    EXPECT_LE(out, 2.0 * in + 1.0) << "side " << side;
  }
}

// Keypoints of the iraf front-end across that boundary: as repeatable as the baseline's (ORB-SLAM's fixed FAST
// thresholds on the raw image), within 5 points. With the paper's hard switch (brightness_ramp 0) it was 13-20 points
// below on these frames (iraf 0.70-0.75, baseline 0.87-0.92).
TEST(FrontEndExposure, IrafRepeatableAcrossBrightnessBoundary) {
  const EnhanceParams cfg;
  int used = 0;
  for (const char* name : kFrames) {
    const cv::Mat img = loadEuroc(name);
    if (img.empty()) continue;
    ++used;
    for (const double side : {-1.0, 1.0}) {
      const double g_a = gainForT(img, side * (cfg.brightness_threshold - 0.01), cfg);
      const double g_b = gainForT(img, side * (cfg.brightness_threshold + 0.01), cfg);
      const double r_iraf = repeatability(FrontEndMode::kIraf, img, g_a, g_b);
      const double r_base = repeatability(FrontEndMode::kBaseline, img, g_a, g_b);
      std::printf("[ info ] %s side %+.0f: repeatability iraf %.3f baseline %.3f\n", name, side, r_iraf, r_base);
      EXPECT_GE(r_iraf, r_base - 0.05) << name << " side " << side;
    }
  }
  if (used == 0) GTEST_SKIP() << "EuRoC frames not found under " << kEuroc;
}

// An auto-exposure step of 4x (0.5x -> 2x, with clipping): the iraf front-end keeps more of its keypoints than the
// baseline, whose fixed thresholds see 4x the contrast in the second frame.
TEST(FrontEndExposure, IrafRepeatableOverExposureStep) {
  int used = 0;
  for (const char* name : kFrames) {
    const cv::Mat img = loadEuroc(name);
    if (img.empty()) continue;
    ++used;
    const double r_iraf = repeatability(FrontEndMode::kIraf, img, 0.5, 2.0);
    const double r_base = repeatability(FrontEndMode::kBaseline, img, 0.5, 2.0);
    std::printf("[ info ] %s 0.5x -> 2x: repeatability iraf %.3f baseline %.3f\n", name, r_iraf, r_base);
    EXPECT_GE(r_iraf, 0.5) << name;
    EXPECT_GE(r_iraf, r_base) << name;
  }
  if (used == 0) GTEST_SKIP() << "EuRoC frames not found under " << kEuroc;
}
