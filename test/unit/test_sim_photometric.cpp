// Photometric events: each one does what it says, presets, determinism, bad input.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <opencv2/imgproc.hpp>

#include "iraf_vo/sim/photometric.h"

namespace {

using iraf_vo::PhotometricEvent;
using iraf_vo::PhotometricEventType;
using iraf_vo::PhotometricParams;

/// A textured radiance-like image (CV_32F, 8-bit units, mean ~120).
cv::Mat texturedImage(int w = 160, int h = 120) {
  cv::Mat small(h / 8, w / 8, CV_32F), img;
  cv::RNG rng(5);
  rng.fill(small, cv::RNG::UNIFORM, 60.0, 180.0);
  cv::resize(small, img, cv::Size(w, h), 0, 0, cv::INTER_CUBIC);
  return img;
}

double meanOf(const cv::Mat& m) { return cv::mean(m)[0]; }

PhotometricParams single(const PhotometricEvent& e) {
  PhotometricParams p;
  p.events.push_back(e);
  return p;
}

TEST(SimPhotometric, DarkPresetReachesFifteenPercent) {
  const int n = 400;
  PhotometricParams clean, dark;
  ASSERT_TRUE(iraf_vo::photometricPreset("clean", n, false, 1, &clean));
  ASSERT_TRUE(iraf_vo::photometricPreset("dark", n, false, 1, &dark));
  const cv::Mat img = texturedImage();
  cv::Mat c, d;
  // Ramp bottom (middle of the event) <= 15 % of clean; before the event it equals clean.
  iraf_vo::applyPhotometric(img, n / 2, clean, &c);
  iraf_vo::applyPhotometric(img, n / 2, dark, &d);
  EXPECT_LE(meanOf(d), 0.15 * meanOf(c));
  EXPECT_GT(meanOf(d), 0.02 * meanOf(c)) << "dark, not black";
  iraf_vo::applyPhotometric(img, 10, clean, &c);
  iraf_vo::applyPhotometric(img, 10, dark, &d);
  EXPECT_NEAR(meanOf(d), meanOf(c), 0.5);
  // The ramp is gradual: brightness decreases monotonically over the ramp-down frames.
  double prev = 1e9;
  for (int f = 60; f <= 120; f += 10) {
    const double g = iraf_vo::globalGain(dark, f);
    EXPECT_LT(g, prev) << "frame " << f;
    prev = g;
  }
  EXPECT_NEAR(iraf_vo::globalGain(dark, n - 1), 1.0, 1e-9) << "light back at the end";
}

TEST(SimPhotometric, OverexposedClips) {
  const int n = 200;
  PhotometricParams over, clean;
  ASSERT_TRUE(iraf_vo::photometricPreset("overexposed", n, false, 1, &over));
  ASSERT_TRUE(iraf_vo::photometricPreset("clean", n, false, 1, &clean));
  const cv::Mat img = texturedImage();
  cv::Mat o, c;
  iraf_vo::applyPhotometric(img, n / 2, over, &o);
  iraf_vo::applyPhotometric(img, n / 2, clean, &c);
  const double clipped = cv::countNonZero(o == 255) / static_cast<double>(o.total());
  EXPECT_GT(clipped, 0.3);
  EXPECT_LT(cv::countNonZero(c == 255) / static_cast<double>(c.total()), 0.01);
}

TEST(SimPhotometric, FlickerAlternates) {
  const int n = 100;
  PhotometricParams p;
  ASSERT_TRUE(iraf_vo::photometricPreset("flicker", n, false, 1, &p));
  const cv::Mat img = texturedImage();
  std::vector<double> m;
  for (int f = 20; f < 40; ++f) {
    cv::Mat o;
    iraf_vo::applyPhotometric(img, f, p, &o);
    m.push_back(meanOf(o));
  }
  for (size_t i = 1; i < m.size(); ++i) EXPECT_GT(std::abs(m[i] - m[i - 1]), 0.3 * std::max(m[i], m[i - 1])) << i;
  for (size_t i = 2; i < m.size(); ++i) EXPECT_NEAR(m[i], m[i - 2], 1.0) << i;
  // Outside the event: steady.
  cv::Mat a, b;
  iraf_vo::applyPhotometric(img, 2, p, &a);
  iraf_vo::applyPhotometric(img, 3, p, &b);
  EXPECT_NEAR(meanOf(a), meanOf(b), 0.5);
}

TEST(SimPhotometric, NoiseStdAsConfigured) {
  const cv::Mat flat(200, 200, CV_32F, cv::Scalar(100.f));
  PhotometricEvent e;
  e.type = PhotometricEventType::kNoise;
  e.amplitude = 5.0;  // read noise
  cv::Mat o;
  iraf_vo::applyPhotometric(flat, 0, single(e), &o);
  cv::Scalar mean, sd;
  cv::meanStdDev(o, mean, sd);
  EXPECT_NEAR(sd[0], 5.0, 0.3);
  EXPECT_NEAR(mean[0], 100.0, 0.3);
  e.amplitude = 0.0;
  e.shot_noise = 0.5;  // variance = 0.5 * 100
  iraf_vo::applyPhotometric(flat, 0, single(e), &o);
  cv::meanStdDev(o, mean, sd);
  EXPECT_NEAR(sd[0], std::sqrt(50.0), 0.4);
  // Seeded per frame: same frame identical, another frame different.
  cv::Mat a, b, c;
  iraf_vo::applyPhotometric(flat, 3, single(e), &a);
  iraf_vo::applyPhotometric(flat, 3, single(e), &b);
  iraf_vo::applyPhotometric(flat, 4, single(e), &c);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
}

TEST(SimPhotometric, LightSwitchIsAbrupt) {
  PhotometricEvent e;
  e.type = PhotometricEventType::kLightSwitch;
  e.start_frame = 10, e.end_frame = 20, e.amplitude = 0.3;
  const cv::Mat img = texturedImage();
  cv::Mat a, b, c, d;
  iraf_vo::applyPhotometric(img, 9, single(e), &a);
  iraf_vo::applyPhotometric(img, 10, single(e), &b);
  iraf_vo::applyPhotometric(img, 19, single(e), &c);
  iraf_vo::applyPhotometric(img, 20, single(e), &d);
  EXPECT_NEAR(meanOf(b) / meanOf(a), 0.3, 0.01);
  EXPECT_NEAR(meanOf(c) / meanOf(a), 0.3, 0.01);
  EXPECT_NEAR(meanOf(d), meanOf(a), 0.01);
}

TEST(SimPhotometric, SpotlightAndShadowMove) {
  const cv::Mat flat(120, 160, CV_32F, cv::Scalar(80.f));
  for (PhotometricEventType t : {PhotometricEventType::kSpotlight, PhotometricEventType::kShadow}) {
    PhotometricEvent e;
    e.type = t;
    e.start_frame = 0, e.end_frame = 10, e.amplitude = t == PhotometricEventType::kSpotlight ? 1.0 : 0.7;
    e.radius = 0.15;
    double prev_x = -1e9;
    for (int f : {2, 5, 8}) {
      cv::Mat o, col;
      iraf_vo::applyPhotometric(flat, f, single(e), &o);
      cv::reduce(o, col, 0, cv::REDUCE_AVG, CV_32F);
      double mn, mx;
      cv::Point pmin, pmax;
      cv::minMaxLoc(col, &mn, &mx, &pmin, &pmax);
      const int x = t == PhotometricEventType::kSpotlight ? pmax.x : pmin.x;
      if (t == PhotometricEventType::kSpotlight) EXPECT_GT(mx, 80 * 1.3);
      else EXPECT_LT(mn, 80 * 0.7);
      EXPECT_GT(x, prev_x + 10) << toString(t) << " frame " << f << " moves left to right";
      prev_x = x;
    }
  }
}

TEST(SimPhotometric, VignettingAndMotionBlur) {
  const cv::Mat flat(120, 160, CV_32F, cv::Scalar(100.f));
  PhotometricEvent v;
  v.type = PhotometricEventType::kVignetting;
  v.amplitude = 0.4;
  cv::Mat o;
  iraf_vo::applyPhotometric(flat, 0, single(v), &o);
  EXPECT_NEAR(o.at<uchar>(60, 80), 100, 1);
  EXPECT_NEAR(o.at<uchar>(0, 0), 60, 1);

  // Horizontal motion blur smooths x-gradients much more than y-gradients.
  cv::Mat tex(120, 160, CV_32F);
  cv::RNG(3).fill(tex, cv::RNG::UNIFORM, 0.0, 255.0);
  PhotometricEvent b;
  b.type = PhotometricEventType::kMotionBlur;
  b.amplitude = 9;
  b.angle_deg = 0;
  cv::Mat blurred, src8, gx0, gy0, gx1, gy1;
  iraf_vo::applyPhotometric(tex, 0, single(b), &blurred);
  tex.convertTo(src8, CV_8U);
  cv::Sobel(src8, gx0, CV_32F, 1, 0);
  cv::Sobel(src8, gy0, CV_32F, 0, 1);
  cv::Sobel(blurred, gx1, CV_32F, 1, 0);
  cv::Sobel(blurred, gy1, CV_32F, 0, 1);
  EXPECT_LT(cv::norm(gx1), 0.3 * cv::norm(gx0));
  EXPECT_GT(cv::norm(gy1) / cv::norm(gy0), 1.5 * cv::norm(gx1) / cv::norm(gx0));
}

TEST(SimPhotometric, MixedPresetAndEventsCsv) {
  const int n = 400;
  PhotometricParams p;
  ASSERT_TRUE(iraf_vo::photometricPreset("mixed", n, true, 1, &p));
  EXPECT_TRUE(iraf_vo::validate(p).empty()) << iraf_vo::validate(p);
  // Each kind of event appears, and segments are separated by normal light (gain 1 somewhere between).
  for (PhotometricEventType t : {PhotometricEventType::kGainRamp, PhotometricEventType::kLightSwitch,
                                 PhotometricEventType::kFlicker, PhotometricEventType::kSpotlight,
                                 PhotometricEventType::kOverExposure}) {
    bool found = false;
    for (const auto& e : p.events) found |= e.type == t;
    EXPECT_TRUE(found) << toString(t);
  }
  int normal_runs = 0;
  bool in_normal = false;
  for (int f = 0; f < n; ++f) {
    const bool normal = std::abs(iraf_vo::globalGain(p, f) - 1.0) < 1e-9;
    if (normal && !in_normal) ++normal_runs;
    in_normal = normal;
  }
  EXPECT_GE(normal_runs, 5);
  const std::string path = ::testing::TempDir() + "/iraf_vo_" + std::to_string(::getpid()) + "_events.csv";
  std::string err;
  ASSERT_TRUE(iraf_vo::writeEventsCsv(path, p, n, &err)) << err;
  std::ifstream f(path);
  std::string line;
  int rows = 0;
  while (std::getline(f, line))
    if (!line.empty() && line[0] != '#') ++rows;
  EXPECT_EQ(rows, static_cast<int>(p.events.size()));
  std::remove(path.c_str());
  EXPECT_FALSE(iraf_vo::photometricPreset("sunny", n, false, 1, &p));
}

TEST(SimPhotometric, BadInput) {
  PhotometricParams p;
  EXPECT_THROW(iraf_vo::applyPhotometric(cv::Mat(), 0, p, nullptr), std::invalid_argument);
  cv::Mat out;
  EXPECT_THROW(iraf_vo::applyPhotometric(cv::Mat(4, 4, CV_8UC3), 0, p, &out), std::invalid_argument);
  PhotometricEvent e;
  e.type = PhotometricEventType::kFlicker;
  e.period_frames = 1;
  EXPECT_NE(iraf_vo::validate(single(e)).find("period_frames"), std::string::npos);
  e.type = PhotometricEventType::kGainRamp;
  e.amplitude = -1;
  EXPECT_FALSE(iraf_vo::validate(single(e)).empty());
  // 8-bit input works and an empty event list is the identity.
  cv::Mat u8(10, 10, CV_8UC1, cv::Scalar(77));
  iraf_vo::applyPhotometric(u8, 0, PhotometricParams(), &out);
  EXPECT_EQ(cv::norm(u8, out, cv::NORM_INF), 0.0);
}

}  // namespace
