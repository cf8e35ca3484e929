// Light profiles through the camera model: each preset produces what it says (night: long exposure and
// high gain, noisier; ae_hunting: exposure oscillating with clipping; light_switch and blackout: dark
// frames then an auto-exposure recovery; flashlight: falls off from the centre and with distance^2;
// glare: saturated regions), today's presets at fixed exposure, determinism per seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "iraf_vo/sim/image_formation.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/sequence.h"

namespace {

using iraf_vo::FrameGeometry;
using iraf_vo::FrameLight;
using iraf_vo::ImageFormation;
using iraf_vo::LightProfile;

constexpr int kW = 188, kH = 120;

/// Textured radiance (DN at the reference exposure, mean ~100).
cv::Mat texture() {
  cv::Mat small(kH / 6, kW / 6, CV_32F), img;
  cv::RNG rng(9);
  rng.fill(small, cv::RNG::UNIFORM, 40.0, 160.0);
  cv::resize(small, img, cv::Size(kW, kH), 0, 0, cv::INTER_CUBIC);
  return img;
}

iraf_vo::CameraModelPtr camera() {
  std::string err;
  return iraf_vo::makeSimCamera("pinhole", kW, kH, &err);
}

LightProfile profile(const std::string& name, int frames, uint64_t seed = 1) {
  LightProfile p;
  EXPECT_TRUE(iraf_vo::lightProfile(name, frames, 20.0, 0.01, false, seed, &p)) << name;
  return p;
}

/// Runs a profile over a still view of `radiance` (wall at `depth_m`): one record (and image) per frame.
std::vector<FrameLight> run(const LightProfile& p, int frames, std::vector<cv::Mat>* images = nullptr,
                            double depth_m = 2.0, const cv::Mat& radiance = texture()) {
  ImageFormation f(p, camera());
  FrameGeometry g;
  g.depth = cv::Mat(kH, kW, CV_32F, cv::Scalar(static_cast<float>(depth_m)));
  f.setGlareLamps({Eigen::Vector3d(0.0, 0.0, depth_m)});
  f.settle(radiance, &g);
  std::vector<FrameLight> out;
  for (int i = 0; i < frames; ++i) {
    cv::Mat img;
    FrameLight rec;
    f.capture(i, radiance, &g, &img, &rec);
    out.push_back(rec);
    if (images) images->push_back(img);
  }
  return out;
}

/// Noise estimate: std of the image minus its 5x5 median (texture mostly removed).
double localNoise(const cv::Mat& img) {
  cv::Mat med, d;
  cv::medianBlur(img, med, 5);
  cv::absdiff(img, med, d);
  return cv::mean(d)[0];
}

TEST(SimLightPresets, EveryNameIsUsableOnRealAndSimulatedImages) {
  for (bool real : {false, true})
    for (const char* name : {"clean", "dark", "overexposed", "flicker", "mixed", "night", "ae_hunting", "light_switch",
                             "blackout", "flashlight", "glare"}) {
      LightProfile p;
      ASSERT_TRUE(iraf_vo::lightProfile(name, 300, 20.0, 0.01, real, 1, &p)) << name;
      EXPECT_EQ(iraf_vo::validate(p), "") << name;
      EXPECT_NE(iraf_vo::lightProfileNames().find(name), std::string::npos);
    }
  LightProfile p;
  EXPECT_FALSE(iraf_vo::lightProfile("sunny", 300, 20.0, 0.01, false, 1, &p));
}

TEST(SimLightPresets, TodaysPresetsKeepExposureFixed) {
  const std::vector<FrameLight> dark = run(profile("dark", 100), 100);
  for (const FrameLight& r : dark) EXPECT_DOUBLE_EQ(r.exposure.time_s * r.exposure.gain, 0.01);
  EXPECT_LT(dark[50].mean_grey, 0.15 * dark[5].mean_grey) << "the dark ramp shows as it is";
}

TEST(SimLightPresets, NightIsLongExposureHighGainAndNoisy) {
  std::vector<cv::Mat> night_img, clean_img;
  const std::vector<FrameLight> night = run(profile("night", 20), 20, &night_img);
  run(profile("clean", 20), 20, &clean_img);
  EXPECT_DOUBLE_EQ(night[10].exposure.time_s, 0.04);
  EXPECT_GE(night[10].exposure.gain, 8.0);
  EXPECT_GT(night[10].mean_grey, 60.0) << "the auto-exposure brings the image up";
  EXPECT_GT(localNoise(night_img[10]), 2.5 * localNoise(clean_img[10]));
}

TEST(SimLightPresets, NightOnRealImagesHasTheNoiseOfTheirSensorAtGain48) {
  // A flat real image (grey 100) through the night profile: the camera ends at 4x the exposure and gain 48; the
  // output's mean and variance are the sensor model's at that gain with EuRoC's 0.05 DN/e- and 10 e- read noise
  // (2.4 DN/e-: var = 2.4 * mean + 576 + ...), within 10 %.
  LightProfile p;
  ASSERT_TRUE(iraf_vo::lightProfile("night", 8, 20.0, 0.01, true, 1, &p));
  EXPECT_DOUBLE_EQ(p.sensor.dn_per_electron, 0.05);
  const cv::Mat flat(kH, kW, CV_32F, cv::Scalar(100.f));
  ImageFormation f(p, nullptr);
  f.settle(flat, nullptr);
  cv::Mat img;
  FrameLight rec;
  f.capture(0, flat, nullptr, &img, &rec);
  EXPECT_DOUBLE_EQ(rec.exposure.gain, 48.0);
  EXPECT_DOUBLE_EQ(rec.exposure.time_s, 0.04);
  const double expected_mean = 100.0 * 0.0023 * 4.0 * 48.0;
  cv::Scalar mean, sd;
  cv::meanStdDev(img, mean, sd);
  EXPECT_NEAR(mean[0], expected_mean, 0.05 * expected_mean);
  const double var = iraf_vo::SensorModel(p.sensor).noiseVarianceDn(expected_mean, 48.0);
  EXPECT_NEAR(sd[0] * sd[0], var, 0.1 * var);
}

TEST(SimLightPresets, AeHuntingOscillatesWithClipping) {
  const std::vector<FrameLight> h = run(profile("ae_hunting", 60), 60);
  const double right = run(profile("light_switch", 5), 5)[0].exposure.time_s;  // settled, calm controller
  double lo = 1e9, hi = 0.0, clipped = 0.0;
  int peaks = 0;
  for (size_t i = 20; i + 1 < h.size(); ++i) {
    lo = std::min(lo, h[i].exposure.time_s / right), hi = std::max(hi, h[i].exposure.time_s / right);
    clipped = std::max(clipped, h[i].saturated);
    if (h[i].exposure.time_s > h[i - 1].exposure.time_s && h[i].exposure.time_s >= h[i + 1].exposure.time_s) ++peaks;
  }
  EXPECT_LT(lo, 0.55);
  EXPECT_GT(hi, 1.8);
  EXPECT_GE(peaks, 2) << "period under 1 s (20 frames)";
  EXPECT_GT(clipped, 0.05) << "over-exposed peaks clip";
}

TEST(SimLightPresets, LightSwitchShowsTransientAndRecovery) {
  const int n = 200;
  const LightProfile p = profile("light_switch", n);
  const std::vector<FrameLight> r = run(p, n);
  const int first_off = static_cast<int>(std::lround(0.25 * n)), first_on = static_cast<int>(std::lround(0.40 * n));
  EXPECT_LT(r[first_off].mean_grey, 0.15 * r[first_off - 1].mean_grey) << "lights off: dark before the AE reacts";
  EXPECT_GT(r[first_off + 15].mean_grey, 0.7 * r[first_off - 1].mean_grey) << "recovered by the gain";
  EXPECT_GT(r[first_on].saturated, 0.5) << "lights on: clipped";
  EXPECT_NEAR(r[first_on + 15].mean_grey, r[first_off - 1].mean_grey, 0.15 * r[first_off - 1].mean_grey);
}

TEST(SimLightPresets, BlackoutHasNoSignalThenRecovers) {
  const int n = 200;
  const LightProfile p = profile("blackout", n);
  const std::vector<FrameLight> r = run(p, n);
  const int start = static_cast<int>(std::lround(0.4 * n)), len = 20;  // 1 s at 20 Hz
  for (int i = start; i < start + len; ++i) EXPECT_LT(r[i].mean_grey, 5.0) << "frame " << i;
  EXPECT_GT(r[start - 1].mean_grey, 60.0);
  EXPECT_GT(r[start + len].saturated, 0.5) << "the light returns onto a maxed exposure";
  EXPECT_GT(r[start + len + 20].mean_grey, 60.0);
  EXPECT_LT(r[start + len + 20].saturated, 0.02);
}

TEST(SimLightPresets, FlashlightFallsOffFromCentreAndWithDistance) {
  LightProfile p = profile("flashlight", 4);
  p.ae.enabled = false;  // fixed exposure: compare the light itself
  p.flashlight.intensity = 1.0;  // well above the quantization at the reference exposure
  const cv::Mat flat(kH, kW, CV_32F, cv::Scalar(100.f));
  std::vector<cv::Mat> near_img, far_img;
  run(p, 1, &near_img, 2.0, flat);
  run(p, 1, &far_img, 4.0, flat);
  const cv::Rect centre(kW / 2 - 10, kH / 2 - 10, 20, 20), corner(0, 0, 20, 20);
  const double c2 = cv::mean(near_img[0](centre))[0], k2 = cv::mean(near_img[0](corner))[0];
  const double c4 = cv::mean(far_img[0](centre))[0];
  EXPECT_GT(c2, 3.0 * k2) << "cone: the centre is lit, the corner much less";
  EXPECT_NEAR(c2 / c4, 4.0, 0.6) << "twice as far: a quarter of the light";
}

TEST(SimLightPresets, GlareSaturatesAndDarkensTheRest) {
  std::vector<cv::Mat> img;
  const std::vector<FrameLight> g = run(profile("glare", 10), 10, &img);
  const std::vector<FrameLight> c = run(profile("clean", 10), 10);
  EXPECT_GT(g[5].saturated, 0.03);
  EXPECT_EQ(img[5].at<uint8_t>(kH / 2, kW / 2), 255) << "the lamp is in the middle of the view";
  EXPECT_LT(g[5].exposure.time_s, c[5].exposure.time_s) << "the auto-exposure meters the lamp";
}

TEST(SimLightPresets, DeterministicPerSeed) {
  std::vector<cv::Mat> a, b, c;
  run(profile("night", 6, 11), 6, &a);
  run(profile("night", 6, 11), 6, &b);
  run(profile("night", 6, 12), 6, &c);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(cv::countNonZero(a[i] != b[i]), 0) << i;
    EXPECT_GT(cv::countNonZero(a[i] != c[i]), kW * kH / 4) << i;
  }
  EXPECT_GT(cv::countNonZero(a[0] != a[1]), kW * kH / 4) << "noise differs frame to frame";
}

}  // namespace
