// Camera model of the simulator: the sensor's noise statistics (Poisson shot noise + read noise vs the
// prediction, full-well and 8-bit clipping, quantization, seeding) and the auto-exposure controller's
// response (convergence, step limits, time before gain, hunting).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "iraf_vo/sim/auto_exposure.h"
#include "iraf_vo/sim/sensor_model.h"

namespace {

using iraf_vo::AutoExposure;
using iraf_vo::AutoExposureParams;
using iraf_vo::Exposure;
using iraf_vo::SensorModel;
using iraf_vo::SensorParams;

void meanVar(const cv::Mat& img, double* mean, double* var) {
  cv::Scalar m, s;
  cv::meanStdDev(img, m, s);
  *mean = m[0];
  *var = s[0] * s[0];
}

Exposure exposure(double time_s, double gain) {
  Exposure e;
  e.time_s = time_s, e.gain = gain;
  return e;
}

TEST(SimSensor, FlatPatchMatchesShotPlusReadNoise) {
  const SensorModel sensor{SensorParams()};
  struct Case { double irradiance, time, gain; } cases[] = {{100, 0.01, 1}, {25, 0.01, 4}, {10, 0.04, 2.5}};
  for (const auto& c : cases) {
    cv::Mat img;
    sensor.expose(cv::Mat(200, 200, CV_32F, cv::Scalar(c.irradiance)), exposure(c.time, c.gain), 7, &img);
    double mean, var;
    meanVar(img, &mean, &var);
    const double expect_mean = sensor.expectedDn(c.irradiance, exposure(c.time, c.gain));
    EXPECT_NEAR(expect_mean, 100.0, 1e-9);
    EXPECT_NEAR(mean, expect_mean, 0.15) << c.gain;
    // var = k g mean + (k g read)^2 + adc^2 + 1/12: 5.4 DN^2 at gain 1, 24.2 at gain 4.
    const double expect_var = sensor.noiseVarianceDn(expect_mean, c.gain);
    EXPECT_NEAR(var, expect_var, 0.05 * expect_var) << "gain " << c.gain;
  }
  // The noise grows with the gain at the same output level (shot noise amplified, read noise too).
  EXPECT_GT(sensor.noiseVarianceDn(100, 4), 4.0 * sensor.noiseVarianceDn(100, 1));
}

TEST(SimSensor, FewElectronsArePoisson) {
  // 10 electrons per pixel (exact Poisson draw), no read noise: var = k^2 g^2 lambda + 1/12.
  SensorParams p;
  p.read_noise_e = 0.0, p.adc_noise_dn = 0.0, p.black_level_dn = 20.0;
  const SensorModel sensor(p);
  cv::Mat img;
  sensor.expose(cv::Mat(300, 300, CV_32F, cv::Scalar(0.5f)), exposure(0.01, 8.0), 3, &img);
  double mean, var;
  meanVar(img, &mean, &var);
  const double k = p.dn_per_electron * 8.0;  // 0.4 DN per electron
  EXPECT_NEAR(mean, 20.0 + 10.0 * k, 0.05);
  EXPECT_NEAR(var, k * k * 10.0 + 1.0 / 12.0, 0.08 * (k * k * 10.0));
  // No light: no electrons (black level only).
  sensor.expose(cv::Mat(50, 50, CV_32F, cv::Scalar(0.f)), exposure(0.01, 8.0), 3, &img);
  EXPECT_EQ(cv::countNonZero(img != 20), 0);
}

TEST(SimSensor, ClipsAtFullWellAnd255) {
  const SensorModel sensor{SensorParams()};
  cv::Mat img;
  // 20000 electrons asked, the well holds 5400: at gain 0.5 that is 135 DN, not 500.
  sensor.expose(cv::Mat(100, 100, CV_32F, cv::Scalar(1000.f)), exposure(0.01, 0.5), 1, &img);
  double mean, var;
  meanVar(img, &mean, &var);
  EXPECT_NEAR(mean, 135.0, 0.6);
  EXPECT_LT(var, 0.5) << "a full well has no shot noise left";
  // At unity gain the full well is 270 DN: the ADC clips first, saturated pixels are exactly 255.
  sensor.expose(cv::Mat(100, 100, CV_32F, cv::Scalar(1000.f)), exposure(0.01, 1.0), 1, &img);
  EXPECT_EQ(cv::countNonZero(img != 255), 0);
  // Twice the time, same irradiance 200: 400 DN -> 255.
  sensor.expose(cv::Mat(100, 100, CV_32F, cv::Scalar(200.f)), exposure(0.02, 1.0), 1, &img);
  EXPECT_EQ(cv::countNonZero(img != 255), 0);
}

TEST(SimSensor, QuantizesToNearestDn) {
  // Huge well, tiny conversion gain: shot noise <= 0.016 DN; no read noise -> output = round(irradiance).
  SensorParams p;
  p.dn_per_electron = 1e-6, p.full_well_e = 1e9, p.read_noise_e = 0.0, p.adc_noise_dn = 0.0;
  const SensorModel sensor(p);
  cv::Mat ramp(1, 600, CV_32F);
  for (int c = 0; c < ramp.cols; ++c) ramp.at<float>(0, c) = 0.3f + 0.5f * c;  // 0.3 .. 299.8
  cv::Mat img;
  sensor.expose(ramp, exposure(0.01, 1.0), 5, &img);
  int off = 0;
  for (int c = 0; c < ramp.cols; ++c) {
    const double want = std::min(255.0, std::round(static_cast<double>(ramp.at<float>(0, c))));
    // Values exactly half-way may go either way under the 0.01 DN shot noise.
    if (std::abs(img.at<uint8_t>(0, c) - want) > (std::abs(std::fmod(ramp.at<float>(0, c), 1.f) - 0.5f) < 0.05f ? 1 : 0)) {
      ++off;
    }
  }
  EXPECT_EQ(off, 0);
}

TEST(SimSensor, SameSeedSameImage) {
  const SensorModel sensor{SensorParams()};
  const cv::Mat irr(60, 80, CV_32F, cv::Scalar(80.f));
  cv::Mat a, b, c;
  sensor.expose(irr, exposure(0.01, 2.0), 42, &a);
  sensor.expose(irr, exposure(0.01, 2.0), 42, &b);
  sensor.expose(irr, exposure(0.01, 2.0), 43, &c);
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  EXPECT_GT(cv::countNonZero(a != c), 1000);
}

TEST(SimSensor, BadInputNamed) {
  SensorParams p;
  p.full_well_e = 0.0;
  EXPECT_THROW(SensorModel{p}, std::invalid_argument);
  const SensorModel sensor{SensorParams()};
  cv::Mat out;
  EXPECT_THROW(sensor.expose(cv::Mat(), exposure(0.01, 1.0), 1, &out), std::invalid_argument);
  EXPECT_THROW(sensor.expose(cv::Mat(4, 4, CV_8UC1), exposure(0.01, 1.0), 1, &out), std::invalid_argument);
}

/// A camera looking at a scene whose right exposure (mean grey = target) is `right_total` (time x gain):
/// the metered grey is target * total / right_total, clipped at 255.
std::vector<Exposure> runPlant(AutoExposure* ae, double right_total, int frames, double target = 110.0) {
  std::vector<Exposure> out;
  for (int i = 0; i < frames; ++i) {
    const Exposure e = ae->next();
    out.push_back(e);
    ae->meter(std::min(255.0, target * e.time_s * e.gain / right_total));
  }
  return out;
}

AutoExposureParams aeParams() {
  AutoExposureParams p;
  p.initial = exposure(0.01, 1.0);
  return p;
}

TEST(SimAutoExposure, StepResponseConvergesWithinStepLimits) {
  AutoExposureParams p = aeParams();
  AutoExposure ae(p);
  // The light drops 6x: the right exposure is 60 ms-equivalent (30 ms at gain 2).
  const std::vector<Exposure> seq = runPlant(&ae, 0.06, 30);
  for (size_t i = 1; i < seq.size(); ++i) {
    const double ratio = seq[i].time_s * seq[i].gain / (seq[i - 1].time_s * seq[i - 1].gain);
    EXPECT_LE(ratio, p.max_step + 1e-9) << "frame " << i;
    EXPECT_GE(ratio, 1.0 / p.max_step - 1e-9) << "frame " << i;
  }
  // The lag: frame 1 still uses the first exposure (metered frame 0 decides frame 2).
  EXPECT_DOUBLE_EQ(seq[1].time_s, 0.01);
  // Converged within 15 frames (ln 6 / ln 1.6 = 3.8 steps at the limit, then the loop gain 0.5).
  const Exposure e = seq[15];
  EXPECT_NEAR(e.time_s * e.gain / 0.06, 1.0, 0.08);
  // Time first, then gain: the time is at its 30 ms maximum, the gain makes up the rest.
  EXPECT_DOUBLE_EQ(e.time_s, p.max_time_s);
  EXPECT_GT(e.gain, 1.8);
  for (const Exposure& x : seq) {
    if (x.time_s < p.max_time_s) {
      EXPECT_DOUBLE_EQ(x.gain, 1.0);
    }
  }
}

TEST(SimAutoExposure, RecoversFromSaturation) {
  // The light comes back 20x: the image is clipped (metered 255), the controller still comes down.
  AutoExposureParams p = aeParams();
  p.initial = exposure(0.02, 1.0);
  AutoExposure ae(p);
  const std::vector<Exposure> seq = runPlant(&ae, 0.001, 40);
  EXPECT_NEAR(seq.back().time_s * seq.back().gain / 0.001, 1.0, 0.08);
}

TEST(SimAutoExposure, HuntsWithAggressiveDelayedLoop) {
  AutoExposureParams p = aeParams();
  p.loop_gain = 1.6, p.delay_frames = 2, p.max_step = 1.5, p.dead_band = 0.0;
  p.initial = exposure(0.012, 1.0);  // 20 % off
  AutoExposure hunting(p);
  const std::vector<Exposure> h = runPlant(&hunting, 0.01, 80);
  // After the start: a sustained oscillation of at least 0.5x..1.8x around the right exposure, with
  // a period under 20 frames (1 s at 20 Hz): >= 3 peaks in the last 40 frames.
  double lo = 1e9, hi = 0.0;
  int peaks = 0;
  for (size_t i = 40; i < h.size(); ++i) {
    const double r = h[i].time_s / 0.01;
    lo = std::min(lo, r), hi = std::max(hi, r);
    if (i + 1 < h.size() && h[i].time_s > h[i - 1].time_s && h[i].time_s >= h[i + 1].time_s) ++peaks;
  }
  EXPECT_LT(lo, 0.5);
  EXPECT_GT(hi, 1.8);
  EXPECT_GE(peaks, 3);
  // The same start with the default loop settles.
  AutoExposureParams q = aeParams();
  q.initial = p.initial;
  AutoExposure calm2(q);
  const std::vector<Exposure> c = runPlant(&calm2, 0.01, 80);
  for (size_t i = 40; i < c.size(); ++i) EXPECT_NEAR(c[i].time_s / 0.01, 1.0, 0.08) << i;
}

TEST(SimAutoExposure, DisabledKeepsInitialAndBadParamsNamed) {
  AutoExposureParams p = aeParams();
  p.enabled = false;
  AutoExposure ae(p);
  const std::vector<Exposure> seq = runPlant(&ae, 0.05, 10);
  for (const Exposure& e : seq) EXPECT_DOUBLE_EQ(e.time_s * e.gain, 0.01);
  AutoExposureParams bad = aeParams();
  bad.max_step = 1.0;
  EXPECT_THROW(AutoExposure{bad}, std::invalid_argument);
  bad = aeParams();
  bad.max_time_s = bad.min_time_s / 2;
  EXPECT_THROW(AutoExposure{bad}, std::invalid_argument);
}

}  // namespace
