#include "iraf_vo/pipeline/front_end.h"

#include "iraf_vo/common/wall_clock.h"

namespace iraf_vo {

namespace {

struct ModeSwitches {
  FrontEndMode mode;
  const char* name;
  EnhanceMethod method;
  bool adaptive_threshold;
  bool culling;
};

constexpr ModeSwitches kModes[] = {
    {FrontEndMode::kIraf, "iraf", EnhanceMethod::kIraf, true, true},
    {FrontEndMode::kBaseline, "baseline", EnhanceMethod::kNone, false, false},
    {FrontEndMode::kEnhance, "enhance", EnhanceMethod::kIraf, false, false},
    {FrontEndMode::kAdaptive, "adaptive", EnhanceMethod::kNone, true, false},
    {FrontEndMode::kCulling, "culling", EnhanceMethod::kNone, false, true},
    // Comparison front-ends of the paper's Table I: HE / CLAHE preprocessing + fixed ORB-SLAM FAST thresholds.
    {FrontEndMode::kHe, "he", EnhanceMethod::kHe, false, false},
    {FrontEndMode::kClahe, "clahe", EnhanceMethod::kClahe, false, false},
};

const ModeSwitches& switchesOf(FrontEndMode m) {
  for (const ModeSwitches& s : kModes)
    if (s.mode == m) return s;
  return kModes[0];
}

}  // namespace

const char* toString(FrontEndMode m) { return switchesOf(m).name; }

bool parseFrontEndMode(const std::string& s, FrontEndMode* m) {
  for (const ModeSwitches& x : kModes)
    if (s == x.name) return (*m = x.mode), true;
  return false;
}

const char* frontEndModeList() { return "iraf, baseline, enhance, adaptive, culling, he or clahe"; }

void applyFrontEndMode(FrontEndMode mode, EnhanceParams* enhance, FeatureParams* features) {
  const ModeSwitches& s = switchesOf(mode);
  enhance->method = s.method;
  features->adaptive_threshold = s.adaptive_threshold;
  features->culling = s.culling;
}

FrontEnd::FrontEnd(const EnhanceParams& enhance, const FeatureParams& features, bool keep_image)
    : enhance_params_(enhance), feature_params_(features), keep_image_(keep_image) {}

FeatureFrame FrontEnd::process(const cv::Mat& gray, double stamp, FrontEndTiming* timing) {
  auto t0 = SteadyClock::now();
  const EnhanceResult enhanced = enhancer_.enhance(gray, enhance_params_);
  const double ms_enhance = msSince(t0);
  t0 = SteadyClock::now();
  FeatureFrame frame = extractor_.extract(enhanced.image, stamp, feature_params_);
  if (timing) *timing = {ms_enhance, msSince(t0)};
  frame.stamp = stamp;
  frame.stats.brightness = static_cast<int>(enhanced.brightness);
  frame.signal = enhanced.signal.measured ? enhanced.signal : measureImageSignal(gray);
  if (keep_image_) frame.image = enhanced.image;  // a new buffer per call (shared, not copied)
  return frame;
}

}  // namespace iraf_vo
