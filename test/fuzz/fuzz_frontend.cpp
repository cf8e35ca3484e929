// libFuzzer target: bytes -> image size / content + EnhanceParams + FeatureParams -> Enhancer::enhance and
// FeatureExtractor::extract. Contract checked: params that validate() rejects make enhance()/extract() throw
// std::invalid_argument; params that validate() accepts never throw, crash or trip ASan/UBSan, and the
// outputs are well formed. Built and run by scripts/fuzz.sh.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/features/feature_params.h"

namespace {

#include "fuzz_check.h"

// Mostly plausible values, sometimes anything (NaN, inf, negative, huge). Each field keeps its default with
// probability 2/3, so valid parameter sets (which reach the deep code) stay frequent.
double pickDouble(FuzzedDataProvider& in, double lo, double hi) {
  switch (in.ConsumeIntegralInRange<int>(0, 7)) {
    case 0: return in.ConsumeFloatingPoint<double>();
    case 1: return std::numeric_limits<double>::quiet_NaN();
    case 2: return std::numeric_limits<double>::infinity();
    default: return in.ConsumeFloatingPointInRange<double>(lo, hi);
  }
}
int pickInt(FuzzedDataProvider& in, int lo, int hi) {
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) return in.ConsumeIntegral<int>();
  return in.ConsumeIntegralInRange<int>(lo, hi);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  const int w = in.ConsumeIntegralInRange<int>(1, 200);
  const int h = in.ConsumeIntegralInRange<int>(1, 160);

  iraf_vo::EnhanceParams ep;
  ep.method = static_cast<iraf_vo::EnhanceMethod>(in.ConsumeIntegralInRange<int>(0, 3));
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.gaussian_kernel_size = pickInt(in, -1, 15);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.gaussian_sigma = pickDouble(in, -1.0, 10.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.mu_expected = pickDouble(in, -10.0, 300.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.brightness_threshold = pickDouble(in, -1.0, 2.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.dim_lambda = pickDouble(in, -1.0, 3.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.dim_tau = pickDouble(in, -0.5, 1.5);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.bright_lambda = pickDouble(in, -1.0, 3.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.bright_tau = pickDouble(in, -0.5, 1.5);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.epsilon = pickDouble(in, -5.0, 5.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.eta = pickDouble(in, -5.0, 5.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.clahe_clip_limit = pickDouble(in, -1.0, 50.0);
  if (in.ConsumeIntegralInRange<int>(0, 2) == 0) ep.clahe_tiles = pickInt(in, -1, 32);

  iraf_vo::FeatureParams fp;
  const bool run_features = in.ConsumeBool();
  if (run_features) {
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.n_features = pickInt(in, -1, 2000);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.scale_factor = pickDouble(in, 0.5, 5.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.n_levels = pickInt(in, 0, 12);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.cell_size = pickInt(in, 0, 100);
    fp.adaptive_threshold = in.ConsumeBool();
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.ini_th_fast = pickInt(in, 0, 260);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.min_th_fast = pickInt(in, 0, 260);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.alpha = pickDouble(in, -1.0, 5.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.beta = pickDouble(in, -1.0, 2.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.delta = pickDouble(in, -1.0, 5.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.ft_min = pickDouble(in, 0.0, 260.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.center_window = pickInt(in, 0, 40);
    fp.culling = in.ConsumeBool();
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.min_node_size = pickInt(in, 0, 100);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.contrast_patch_size = pickInt(in, 0, 60);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.rho = pickDouble(in, -2.0, 5.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.h_th = pickDouble(in, -10.0, 50.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.k = pickDouble(in, -5.0, 20.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.d_opt = pickDouble(in, -1.0, 5.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.w1 = pickDouble(in, -1.0, 2.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.w2 = pickDouble(in, -1.0, 2.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.s_min = pickDouble(in, -1.0, 2.0);
    if (in.ConsumeIntegralInRange<int>(0, 2) == 0) fp.min_features = pickInt(in, -1, 3000);
    fp.eq23_literal = in.ConsumeBool();
  }

  // Image: the remaining bytes, repeated (an empty remainder gives a constant image).
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(in.ConsumeIntegral<uint8_t>()));
  const std::vector<uint8_t> pix = in.ConsumeRemainingBytes<uint8_t>();
  if (!pix.empty())
    for (int i = 0; i < w * h; ++i) img.data[i] = pix[static_cast<size_t>(i) % pix.size()];

  iraf_vo::Enhancer enhancer;
  cv::Mat enhanced;
  if (!iraf_vo::validate(ep).empty()) {
    bool threw = false;
    try {
      enhancer.enhance(img, ep);
    } catch (const std::invalid_argument&) {
      threw = true;
    }
    FUZZ_CHECK(threw);
    enhanced = img;
  } else {
    const iraf_vo::EnhanceResult r = enhancer.enhance(img, ep);  // must not throw
    FUZZ_CHECK(r.image.type() == CV_8UC1 && r.image.size() == img.size());
    FUZZ_CHECK(r.image.data != img.data);
    enhanced = r.image;
  }

  if (run_features) {
    iraf_vo::FeatureExtractor fx;
    if (!iraf_vo::validate(fp).empty()) {
      bool threw = false;
      try {
        fx.extract(enhanced, 1.0, fp);
      } catch (const std::invalid_argument&) {
        threw = true;
      }
      FUZZ_CHECK(threw);
    } else {
      iraf_vo::CulledFeatures culled;
      const iraf_vo::FeatureFrame f = fx.extract(enhanced, 1.0, fp, &culled);  // must not throw
      FUZZ_CHECK(f.descriptors.rows == static_cast<int>(f.keypoints.size()));
      for (const cv::KeyPoint& k : f.keypoints)
        FUZZ_CHECK(k.pt.x >= 0 && k.pt.y >= 0 && k.pt.x < w && k.pt.y < h);
    }
  }
  return 0;
}
