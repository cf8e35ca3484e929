#include "iraf_vo/sim/photometric.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "iraf_vo/common/enum_names.h"

namespace iraf_vo {

namespace {
constexpr EnumName<PhotometricEventType> kTypeNames[] = {
    {PhotometricEventType::kGainRamp, "gain_ramp"},     {PhotometricEventType::kOverExposure, "over_exposure"},
    {PhotometricEventType::kLightSwitch, "light_switch"}, {PhotometricEventType::kFlicker, "flicker"},
    {PhotometricEventType::kSpotlight, "spotlight"},    {PhotometricEventType::kShadow, "shadow"},
    {PhotometricEventType::kVignetting, "vignetting"},  {PhotometricEventType::kNoise, "noise"},
    {PhotometricEventType::kMotionBlur, "motion_blur"}};

/// Progress in [0, 1) of `frame` inside the event range (end resolved with num_frames when open).
double progress(const PhotometricEvent& e, int frame) {
  const int end = e.end_frame < 0 ? std::max(frame + 1, e.start_frame + 1) : e.end_frame;
  return std::min(1.0, std::max(0.0, (frame - e.start_frame) / static_cast<double>(std::max(1, end - e.start_frame))));
}

/// Gain envelope of a ramp event: 1 -> amplitude over ramp_frames, hold, amplitude -> 1 before the end.
double rampGain(const PhotometricEvent& e, int frame) {
  if (e.ramp_frames <= 0) return e.amplitude;
  double w = std::min(1.0, (frame - e.start_frame + 1) / static_cast<double>(e.ramp_frames));
  if (e.end_frame >= 0) w = std::min(w, (e.end_frame - frame) / static_cast<double>(e.ramp_frames));
  w = std::max(0.0, std::min(1.0, w));
  w = w * w * (3.0 - 2.0 * w);  // smoothstep: no kink at the ends of the ramp
  // Interpolate in log space: a dark ramp looks linear to the eye / to an exposure controller.
  return std::exp(w * std::log(e.amplitude));
}

uint64_t mix64(uint64_t x) {
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return x;
}
}  // namespace

const char* toString(PhotometricEventType t) { return nameOf(kTypeNames, t, "unknown"); }

bool parsePhotometricEventType(const std::string& s, PhotometricEventType* t) { return parseName(kTypeNames, s, t); }

std::string validate(const PhotometricParams& params) {
  std::ostringstream err;
  for (size_t i = 0; i < params.events.size(); ++i) {
    const PhotometricEvent& e = params.events[i];
    const std::string name = std::string("event ") + std::to_string(i) + " (" + toString(e.type) + "): ";
    if (e.start_frame < 0) err << name << "start_frame must be >= 0; ";
    if (e.end_frame >= 0 && e.end_frame <= e.start_frame) err << name << "end_frame must be > start_frame or -1; ";
    if (!std::isfinite(e.amplitude)) err << name << "amplitude must be finite; ";
    switch (e.type) {
      case PhotometricEventType::kGainRamp:
      case PhotometricEventType::kOverExposure:
      case PhotometricEventType::kLightSwitch:
        if (!(e.amplitude > 0.0)) err << name << "amplitude (gain) must be > 0; ";
        if (e.ramp_frames < 0) err << name << "ramp_frames must be >= 0; ";
        break;
      case PhotometricEventType::kFlicker:
        if (!(e.amplitude >= 0.0 && e.amplitude <= 1.0)) err << name << "amplitude must be in [0, 1]; ";
        if (e.period_frames < 2) err << name << "period_frames must be >= 2; ";
        break;
      case PhotometricEventType::kSpotlight:
      case PhotometricEventType::kShadow:
        if (!(e.radius > 0.0)) err << name << "radius must be > 0; ";
        if (e.type == PhotometricEventType::kShadow && !(e.amplitude >= 0.0 && e.amplitude <= 1.0))
          err << name << "amplitude must be in [0, 1]; ";
        break;
      case PhotometricEventType::kVignetting:
        if (!(e.amplitude >= 0.0 && e.amplitude <= 1.0)) err << name << "amplitude must be in [0, 1]; ";
        break;
      case PhotometricEventType::kNoise:
        if (!(e.amplitude >= 0.0) || !(e.shot_noise >= 0.0)) err << name << "amplitude and shot_noise must be >= 0; ";
        break;
      case PhotometricEventType::kMotionBlur:
        if (!(e.amplitude >= 0.0 && e.amplitude <= 200.0)) err << name << "amplitude (length px) must be in [0, 200]; ";
        break;
    }
  }
  return err.str();
}

std::string photometricPresetNames() { return "clean|dark|overexposed|flicker|mixed"; }

bool photometricPreset(const std::string& name, int n, bool real_images, uint64_t seed, PhotometricParams* params) {
  if (name != "clean" && name != "dark" && name != "overexposed" && name != "flicker" && name != "mixed") return false;
  params->events.clear();
  params->seed = seed;
  n = std::max(n, 1);
  auto at = [n](double f) { return static_cast<int>(std::lround(f * n)); };
  auto ev = [](PhotometricEventType t, int s, int e, double a) {
    PhotometricEvent ev;
    ev.type = t, ev.start_frame = s, ev.end_frame = std::max(e, s + 1), ev.amplitude = a;
    return ev;
  };
  using T = PhotometricEventType;
  // Sensor model of every preset (whole sequence): the renderer's images get lens vignetting and
  // shot + read noise; real images already have both, so they only get a light extra read noise.
  PhotometricEvent noise = ev(T::kNoise, 0, n, real_images ? 1.0 : 1.5);
  noise.end_frame = -1;
  noise.shot_noise = real_images ? 0.02 : 0.05;
  if (!real_images) {
    PhotometricEvent vig = ev(T::kVignetting, 0, n, 0.3);
    vig.end_frame = -1;
    params->events.push_back(vig);
  }
  if (name == "dark") {
    // 0-15 % normal (initialization), ramp down to 10 % brightness over 15 %, hold, ramp back by 85 %.
    PhotometricEvent e = ev(T::kGainRamp, at(0.15), at(0.85), 0.10);
    e.ramp_frames = std::max(1, at(0.15));
    params->events.push_back(e);
  } else if (name == "overexposed") {
    PhotometricEvent e = ev(T::kOverExposure, at(0.15), at(0.85), 3.0);
    e.ramp_frames = std::max(1, at(0.12));
    params->events.push_back(e);
  } else if (name == "flicker") {
    PhotometricEvent e = ev(T::kFlicker, at(0.15), at(0.85), 0.45);
    e.period_frames = 2;
    params->events.push_back(e);
  } else if (name == "mixed") {
    // Segments separated by normal light: dark ramp, abrupt switch, flicker, spotlight, shadow, over-exposure.
    PhotometricEvent dark = ev(T::kGainRamp, at(0.08), at(0.28), 0.12);
    dark.ramp_frames = std::max(1, at(0.06));
    params->events.push_back(dark);
    params->events.push_back(ev(T::kLightSwitch, at(0.34), at(0.44), 0.3));
    PhotometricEvent flicker = ev(T::kFlicker, at(0.50), at(0.60), 0.45);
    flicker.period_frames = 2;
    params->events.push_back(flicker);
    PhotometricEvent spot = ev(T::kSpotlight, at(0.63), at(0.72), 1.2);
    spot.radius = 0.2;
    params->events.push_back(spot);
    PhotometricEvent shadow = ev(T::kShadow, at(0.72), at(0.79), 0.65);
    shadow.radius = 0.3;
    params->events.push_back(shadow);
    PhotometricEvent over = ev(T::kOverExposure, at(0.83), at(0.96), 3.0);
    over.ramp_frames = std::max(1, at(0.04));
    params->events.push_back(over);
    // Abrupt auto-exposure jumps (a few frames each) inside normal-light segments.
    params->events.push_back(ev(T::kLightSwitch, at(0.30), at(0.315), 1.8));
    params->events.push_back(ev(T::kLightSwitch, at(0.46), at(0.475), 0.5));
  }
  params->events.push_back(noise);
  return true;
}

double globalGain(const PhotometricParams& params, int frame) {
  double g = 1.0;
  for (const PhotometricEvent& e : params.events) {
    if (!e.activeAt(frame)) continue;
    switch (e.type) {
      case PhotometricEventType::kGainRamp:
      case PhotometricEventType::kOverExposure:
        g *= rampGain(e, frame);
        break;
      case PhotometricEventType::kLightSwitch:
        g *= e.amplitude;
        break;
      case PhotometricEventType::kFlicker: {
        const int phase = (frame - e.start_frame) % e.period_frames;
        if (phase >= e.period_frames / 2) g *= 1.0 - e.amplitude;
        break;
      }
      default: break;
    }
  }
  return g;
}

void applyIllumination(const cv::Mat& in, int frame, const PhotometricParams& params, cv::Mat* out) {
  if (in.empty()) throw std::invalid_argument("applyIllumination: empty image");
  if (in.type() != CV_8UC1 && in.type() != CV_32FC1)
    throw std::invalid_argument("applyIllumination: image must be CV_8UC1 or CV_32FC1 (got type " +
                                std::to_string(in.type()) + ")");
  const int w = in.cols, h = in.rows;
  cv::Mat img;
  in.convertTo(img, CV_32F);  // a copy: `in` may be *out

  // Spatial gains (vignetting, spotlight, shadow) multiply into one map.
  cv::Mat gain_map;
  auto map = [&]() -> cv::Mat& {
    if (gain_map.empty()) gain_map = cv::Mat(h, w, CV_32F, cv::Scalar(1.f));
    return gain_map;
  };
  for (const PhotometricEvent& e : params.events) {
    if (!e.activeAt(frame)) continue;
    if (e.type == PhotometricEventType::kVignetting && e.amplitude > 0) {
      const float cx = 0.5f * (w - 1), cy = 0.5f * (h - 1), inv_r2 = 1.f / (cx * cx + cy * cy);
      const float a = static_cast<float>(e.amplitude);
      cv::Mat& m = map();
      for (int r = 0; r < h; ++r) {
        float* g = m.ptr<float>(r);
        const float dy2 = (r - cy) * (r - cy);
        for (int c = 0; c < w; ++c) g[c] *= 1.f - a * ((c - cx) * (c - cx) + dy2) * inv_r2;
      }
    } else if (e.type == PhotometricEventType::kSpotlight) {
      const double p = progress(e, frame);
      const float sx = static_cast<float>((-0.1 + 1.2 * p) * w);
      const float sy = static_cast<float>(h * (0.5 + 0.2 * std::sin(2 * M_PI * p)));
      const float sigma = static_cast<float>(e.radius * w), k = -0.5f / (sigma * sigma);
      const float a = static_cast<float>(e.amplitude);
      cv::Mat& m = map();
      for (int r = 0; r < h; ++r) {
        float* g = m.ptr<float>(r);
        for (int c = 0; c < w; ++c) g[c] *= 1.f + a * std::exp(k * ((c - sx) * (c - sx) + (r - sy) * (r - sy)));
      }
    } else if (e.type == PhotometricEventType::kShadow) {
      const double p = progress(e, frame);
      const float bx = static_cast<float>((-0.25 + 1.5 * p) * w);
      const float half = static_cast<float>(0.5 * e.radius * w), soft = 0.4f * half;
      const float a = static_cast<float>(e.amplitude);
      cv::Mat& m = map();
      for (int r = 0; r < h; ++r) {
        float* g = m.ptr<float>(r);
        for (int c = 0; c < w; ++c) {
          const float d = std::abs(c - bx + 0.35f * (r - 0.5f * h));  // tilted band
          float s = std::min(1.f, std::max(0.f, (half - d) / soft));    // 1 inside, soft edge
          s = s * s * (3.f - 2.f * s);
          g[c] *= 1.f - a * s;
        }
      }
    }
  }
  const double g = globalGain(params, frame);
  if (!gain_map.empty()) {
    cv::multiply(img, gain_map, img, g);
  } else if (g != 1.0) {
    img *= g;
  }
  *out = img;
}

void applyPhotometric(const cv::Mat& in, int frame, const PhotometricParams& params, cv::Mat* out) {
  if (in.empty()) throw std::invalid_argument("applyPhotometric: empty image");
  if (in.type() != CV_8UC1 && in.type() != CV_32FC1)
    throw std::invalid_argument("applyPhotometric: image must be CV_8UC1 or CV_32FC1 (got type " +
                                std::to_string(in.type()) + ")");
  const int w = in.cols, h = in.rows;
  cv::Mat img;
  applyIllumination(in, frame, params, &img);

  for (const PhotometricEvent& e : params.events) {
    if (!e.activeAt(frame) || e.type != PhotometricEventType::kMotionBlur || e.amplitude < 1.0) continue;
    // Directional box blur: a line kernel of the given length and angle.
    const int len = static_cast<int>(std::lround(e.amplitude));
    const int ks = len | 1;
    cv::Mat kernel = cv::Mat::zeros(ks, ks, CV_32F);
    const double a = e.angle_deg * M_PI / 180.0, c = 0.5 * (ks - 1);
    const cv::Point2d dir(std::cos(a) * 0.5 * (len - 1), std::sin(a) * 0.5 * (len - 1));
    cv::line(kernel, cv::Point(cvRound(c - dir.x), cvRound(c - dir.y)), cv::Point(cvRound(c + dir.x), cvRound(c + dir.y)),
             cv::Scalar(1.0), 1, cv::LINE_AA);
    kernel /= cv::sum(kernel)[0];
    cv::filter2D(img, img, -1, kernel, cv::Point(-1, -1), 0, cv::BORDER_REFLECT);
  }

  for (const PhotometricEvent& e : params.events) {
    if (!e.activeAt(frame) || e.type != PhotometricEventType::kNoise) continue;
    if (e.amplitude <= 0.0 && e.shot_noise <= 0.0) continue;
    // Shot + read noise: std(I) = sqrt(shot_noise * I + read^2), one seeded generator per frame.
    cv::RNG rng(mix64(params.seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(frame) * 7919ULL + 1));
    cv::Mat n(h, w, CV_32F);
    rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    const float shot = static_cast<float>(e.shot_noise), read2 = static_cast<float>(e.amplitude * e.amplitude);
    for (int r = 0; r < h; ++r) {
      float* p = img.ptr<float>(r);
      const float* q = n.ptr<float>(r);
      for (int c = 0; c < w; ++c) p[c] += q[c] * std::sqrt(shot * std::max(0.f, p[c]) + read2);
    }
  }
  img.convertTo(*out, CV_8U);  // rounds and clips to [0, 255] (over-exposure saturates here)
}

bool writeEventsCsv(const std::string& path, const PhotometricParams& params, int num_frames, std::string* error) {
  std::ofstream f(path);
  if (!f) {
    if (error) *error = path + ": cannot write";
    return false;
  }
  f << "# type,start_frame,end_frame,amplitude,ramp_frames,period_frames,radius,shot_noise\n";
  for (const PhotometricEvent& e : params.events)
    f << toString(e.type) << ',' << e.start_frame << ',' << (e.end_frame < 0 ? num_frames : e.end_frame) << ','
      << e.amplitude << ',' << e.ramp_frames << ',' << e.period_frames << ',' << e.radius << ',' << e.shot_noise << '\n';
  if (!f) {
    if (error) *error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace iraf_vo
