#include "iraf_vo/enhance/enhancer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/common/enum_names.h"
#include "iraf_vo/common/wall_clock.h"

namespace iraf_vo {

namespace {
constexpr EnumName<BrightnessClass> kBrightnessNames[] = {
    {BrightnessClass::kDim, "dim"}, {BrightnessClass::kNormal, "normal"}, {BrightnessClass::kBright, "bright"}};
}  // namespace

const char* toString(BrightnessClass c) { return nameOf(kBrightnessNames, c, "normal"); }

std::array<double, 256> histogram256(const cv::Mat& gray) {
  CV_Assert(gray.type() == CV_8UC1);
  std::array<int, 256> counts{};
  for (int r = 0; r < gray.rows; ++r) {
    const uint8_t* p = gray.ptr<uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c) ++counts[p[c]];
  }
  std::array<double, 256> h{};
  for (int i = 0; i < 256; ++i) h[i] = counts[i];  // eq. (3): H(i)
  return h;
}

std::array<double, 256> textureWeightedHistogram(const cv::Mat& gray) {
  CV_Assert(gray.type() == CV_8UC1);
  std::array<double, 256> h{};
  cv::Mat half;
  cv::resize(gray, half, cv::Size((gray.cols + 1) / 2, (gray.rows + 1) / 2), 0, 0, cv::INTER_AREA);
  std::array<int64_t, 256> acc{};
  for (int r = 1; r + 1 < half.rows; ++r) {
    const uint8_t* up = half.ptr<uint8_t>(r - 1);
    const uint8_t* p = half.ptr<uint8_t>(r);
    const uint8_t* dn = half.ptr<uint8_t>(r + 1);
    for (int c = 1; c + 1 < half.cols; ++c)
      acc[p[c]] += std::abs(p[c + 1] - p[c - 1]) + std::abs(dn[c] - up[c]);
  }
  for (int i = 0; i < 256; ++i) h[i] = static_cast<double>(acc[i]);
  return h;
}

double histogramMean(const std::array<double, 256>& h, double fallback) {
  double sum = 0.0, total = 0.0;
  for (int i = 0; i < 256; ++i) {
    sum += i * h[i];
    total += h[i];
  }
  return total > 0.0 ? sum / total : fallback;
}

std::array<uint8_t, 256> agcwdLut(const std::array<double, 256>& histogram, double lambda, double tau) {
  double total = 0.0;
  for (double v : histogram) total += v;
  std::array<uint8_t, 256> lut{};
  if (!(total > 0.0)) {
    for (int i = 0; i < 256; ++i) lut[i] = static_cast<uint8_t>(i);
    return lut;
  }
  // eq. (4): P(i) = H(i) / sum_j H(j)
  std::array<double, 256> P{};
  for (int i = 0; i < 256; ++i) P[i] = histogram[i] / total;
  const double p_max = *std::max_element(P.begin(), P.end());
  const double p_min = *std::min_element(P.begin(), P.end());
  // eq. (5): P_w(i) = P_max * ((P(i) - P_min) / (P_max - P_min))^lambda
  // (a flat histogram, P_max == P_min, gives P_w(i) = P_max for every i)
  std::array<double, 256> Pw{};
  double pw_sum = 0.0;
  for (int i = 0; i < 256; ++i) {
    const double range = p_max - p_min;
    Pw[i] = range > 0.0 ? p_max * std::pow((P[i] - p_min) / range, lambda) : p_max;
    pw_sum += Pw[i];
  }
  // eq. (6): C_w(i) = sum_{j<=i} P_w(j) / sum_k P_w(k);  eq. (7): gamma(i) = max(tau, 1 - C_w(i))
  // eq. (8): I_gamma = 255 * (I / 255)^gamma(I)
  double cdf = 0.0;
  for (int i = 0; i < 256; ++i) {
    cdf += Pw[i] / pw_sum;
    const double gamma = std::max(tau, 1.0 - cdf);
    const double v = 255.0 * std::pow(i / 255.0, gamma);
    lut[i] = cv::saturate_cast<uint8_t>(v);
  }
  return lut;
}

BrightnessClass classifyBrightness(double mu, const EnhanceParams& cfg, double* t) {
  // eq. (10): t = (mu - mu_expected) / mu_expected
  const double tt = (mu - cfg.mu_expected) / cfg.mu_expected;
  if (t) *t = tt;
  if (std::abs(tt) <= cfg.brightness_threshold) return BrightnessClass::kNormal;
  return tt < 0.0 ? BrightnessClass::kDim : BrightnessClass::kBright;
}

double gammaWeight(double t, const EnhanceParams& cfg) {
  const double over = std::abs(t) - cfg.brightness_threshold;
  if (over <= 0.0) return 0.0;
  return cfg.brightness_ramp > 0.0 ? std::min(1.0, over / cfg.brightness_ramp) : 1.0;
}

double unsharpAmount(double snr, const EnhanceParams& cfg) {
  if (cfg.unsharp_full_snr <= 0.0 || snr >= cfg.unsharp_full_snr) return cfg.eta;
  if (snr <= cfg.unsharp_min_snr) return 1.0;
  return 1.0 + (cfg.eta - 1.0) * (snr - cfg.unsharp_min_snr) / (cfg.unsharp_full_snr - cfg.unsharp_min_snr);
}

double unsharpAmountForNoise(double noise, const EnhanceParams& cfg) {
  if (cfg.unsharp_noise_none <= 0.0 || noise <= cfg.unsharp_noise_full) return cfg.eta;
  if (noise >= cfg.unsharp_noise_none) return 1.0;
  const double span = cfg.unsharp_noise_none - cfg.unsharp_noise_full;
  return cfg.eta + (1.0 - cfg.eta) * (noise - cfg.unsharp_noise_full) / span;
}

double denoiseSigma(double noise, const EnhanceParams& cfg) {
  if (cfg.denoise_noise <= 0.0 || noise <= cfg.denoise_noise) return 0.0;
  // A Gaussian of sigma s (>= ~0.7 px) scales white noise by 1 / (2 sqrt(pi) s).
  return noise / (2.0 * std::sqrt(M_PI) * cfg.denoise_noise);
}

#if defined(IRAF_VO_AVX512_KERNELS)
namespace blend_avx512 {
int blendRow(const uint8_t* pi, const uint8_t* pb, const uint8_t* pg, float wi, float wb, float wg, int n,
             uint8_t* po);
}  // namespace blend_avx512
#endif

namespace {

#if defined(IRAF_VO_AVX512_KERNELS)
bool g_blend_avx512 = __builtin_cpu_supports("avx512bw");
#endif

void applyLut(const cv::Mat& src, const std::array<uint8_t, 256>& lut, bool inverted, cv::Mat& dst) {
  // For bright images the LUT was built on the inverted histogram: dst = 255 - lut[255 - src].
  std::array<uint8_t, 256> full{};
  for (int i = 0; i < 256; ++i) full[i] = inverted ? static_cast<uint8_t>(255 - lut[255 - i]) : lut[i];
  cv::LUT(src, cv::Mat(1, 256, CV_8U, full.data()), dst);
}

// One row of eqs. (11)-(12): out = sat(wi * I + wb * B + wg * G + 0.5), truncated. The vector part does the same
// float operations in the same order as the scalar tail (no fused multiply-add), so both give identical bytes.
void blendRow(const uint8_t* pi, const uint8_t* pb, const uint8_t* pg, float wi, float wb, float wg, int n,
              uint8_t* po) {
  int c = 0;
#if defined(IRAF_VO_AVX512_KERNELS)
  if (g_blend_avx512) c = blend_avx512::blendRow(pi, pb, pg, wi, wb, wg, n, po);
#endif
#if CV_SIMD128
  const cv::v_float32x4 vwi = cv::v_setall_f32(wi), vwb = cv::v_setall_f32(wb), vwg = cv::v_setall_f32(wg);
  const cv::v_float32x4 half = cv::v_setall_f32(0.5f), lo = cv::v_setzero_f32(), hi = cv::v_setall_f32(255.f);
  auto blend4 = [&](const cv::v_uint32x4& i, const cv::v_uint32x4& b, const cv::v_uint32x4& g) {
    const cv::v_float32x4 fi = cv::v_cvt_f32(cv::v_reinterpret_as_s32(i));
    const cv::v_float32x4 fb = cv::v_cvt_f32(cv::v_reinterpret_as_s32(b));
    const cv::v_float32x4 fg = cv::v_cvt_f32(cv::v_reinterpret_as_s32(g));
    const cv::v_float32x4 v = vwi * fi + vwb * fb + vwg * fg + half;
    return cv::v_trunc(cv::v_min(hi, cv::v_max(lo, v)));
  };
  for (; c + 16 <= n; c += 16) {
    cv::v_uint16x8 i16[2], b16[2], g16[2];
    cv::v_expand(cv::v_load(pi + c), i16[0], i16[1]);
    cv::v_expand(cv::v_load(pb + c), b16[0], b16[1]);
    cv::v_expand(cv::v_load(pg + c), g16[0], g16[1]);
    cv::v_int32x4 out[4];
    for (int h = 0; h < 2; ++h) {
      cv::v_uint32x4 i32[2], b32[2], g32[2];
      cv::v_expand(i16[h], i32[0], i32[1]);
      cv::v_expand(b16[h], b32[0], b32[1]);
      cv::v_expand(g16[h], g32[0], g32[1]);
      out[2 * h] = blend4(i32[0], b32[0], g32[0]);
      out[2 * h + 1] = blend4(i32[1], b32[1], g32[1]);
    }
    cv::v_store(po + c, cv::v_pack_u(cv::v_pack(out[0], out[1]), cv::v_pack(out[2], out[3])));
  }
#endif
  for (; c < n; ++c) {
    const float v = wi * pi[c] + wb * pb[c] + wg * pg[c];
    po[c] = static_cast<uint8_t>(std::min(255.f, std::max(0.f, v + 0.5f)));
  }
}

}  // namespace

bool enhanceBlendUseAvx512(bool allowed) {
#if defined(IRAF_VO_AVX512_KERNELS)
  g_blend_avx512 = allowed && __builtin_cpu_supports("avx512bw");
  return g_blend_avx512;
#else
  (void)allowed;
  return false;
#endif
}

EnhanceResult Enhancer::enhance(const cv::Mat& gray, const EnhanceParams& cfg) {
  const auto t0 = SteadyClock::now();
  if (gray.empty()) throw std::invalid_argument("enhance: empty image");
  if (gray.type() != CV_8UC1)
    throw std::invalid_argument("enhance: expected an 8-bit single-channel image (CV_8UC1), got type " +
                                std::to_string(gray.type()));
  const std::string err = validate(cfg);
  if (!err.empty()) throw std::invalid_argument("enhance: bad config: " + err);

  EnhanceResult res;
  // eq. (9): mu = mean intensity. With texture_weighted_brightness an image bright by that mean is bright only as
  // far as its textured pixels are (the lower of the two means): a flat sky or blown-out area does not make it
  // over-exposed. Dim stays as printed: texture in the dark has small gradients, a gradient weight would hide it.
  res.mu = cv::mean(gray)[0];
  res.brightness = classifyBrightness(res.mu, cfg, &res.t);
  std::array<double, 256> texture_hist{};
  bool by_texture = false;
  if (cfg.texture_weighted_brightness && cfg.method == EnhanceMethod::kIraf &&
      res.brightness == BrightnessClass::kBright) {  // only a bright frame is judged again (dim: as printed)
    texture_hist = textureWeightedHistogram(gray);
    res.mu_texture = histogramMean(texture_hist, -1.0);
    by_texture = res.mu_texture >= 0.0 && res.mu_texture < res.mu;  // a flat image has no texture: as printed
    if (by_texture) res.brightness = classifyBrightness(res.mu_texture, cfg, &res.t);
    else res.mu_texture = 0.0;
  }

  switch (cfg.method) {
    case EnhanceMethod::kNone:
      res.image = gray.clone();
      break;
    case EnhanceMethod::kHe:
      cv::equalizeHist(gray, res.image);
      break;
    case EnhanceMethod::kClahe:
      if (!clahe_ || clahe_clip_ != cfg.clahe_clip_limit || clahe_tiles_ != cfg.clahe_tiles) {
        clahe_ = cv::createCLAHE(cfg.clahe_clip_limit, cv::Size(cfg.clahe_tiles, cfg.clahe_tiles));
        clahe_clip_ = cfg.clahe_clip_limit;
        clahe_tiles_ = cfg.clahe_tiles;
      }
      clahe_->apply(gray, res.image);
      break;
    case EnhanceMethod::kIraf: {
      const bool noise_needed = cfg.denoise_noise > 0.0 || (cfg.unsharp_noise_none > 0.0 && cfg.eta != 1.0);
      if (noise_needed) res.pixel_noise = estimatePixelNoise(gray);
      const cv::Mat* src = &gray;
      res.denoise_sigma = denoiseSigma(res.pixel_noise, cfg);
      if (res.denoise_sigma > 0.0) {
        cv::GaussianBlur(gray, denoised_, cv::Size(), res.denoise_sigma, res.denoise_sigma,
                         cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);
        src = &denoised_;
      }
      // eqs. (1)-(2)
      const int k = cfg.gaussian_kernel_size;
      if (k > 1)
        cv::GaussianBlur(*src, blurred_, cv::Size(k, k), cfg.gaussian_sigma, cfg.gaussian_sigma,
                         cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);  // an ROI is its own image
      else
        src->copyTo(blurred_);

      // eqs. (3)-(8): only for images classified dim or bright; a normal image keeps I_gamma = I_gauss.
      const cv::Mat* gamma_img = &blurred_;
      if (res.brightness != BrightnessClass::kNormal) {
        const bool bright = res.brightness == BrightnessClass::kBright;
        std::array<double, 256> h = by_texture ? texture_hist : histogram256(blurred_);
        if (bright) std::reverse(h.begin(), h.end());  // histogram of 255 - I_blurred
        const auto lut = agcwdLut(h, bright ? cfg.bright_lambda : cfg.dim_lambda, bright ? cfg.bright_tau : cfg.dim_tau);
        applyLut(blurred_, lut, bright, gamma_);
        gamma_img = &gamma_;
        res.gamma_weight = gammaWeight(res.t, cfg);
      }

      // eqs. (11)-(12) in float, saturated once, with the gamma term weighted by w = res.gamma_weight (1 unless
      // brightness_ramp > 0; G = B for a normal image, where w does not matter):
      //   I' = B + w epsilon * (G - B) + eta * (I - B) = eta*I + (1 - w epsilon - eta)*B + w epsilon*G
      // eta is lowered toward 1 on a noisy image (unsharpAmount): the mask would sharpen the noise.
      res.unsharp_amount = cfg.eta;
      if (cfg.unsharp_full_snr > 0.0 && cfg.eta != 1.0) {
        res.signal = measureImageSignal(gray);
        if (res.signal.measured) res.unsharp_amount = unsharpAmount(res.signal.snr, cfg);
      }
      if (cfg.unsharp_noise_none > 0.0 && cfg.eta != 1.0) {
        const double by_noise = unsharpAmountForNoise(res.pixel_noise, cfg);
        if (std::abs(by_noise - 1.0) < std::abs(res.unsharp_amount - 1.0)) res.unsharp_amount = by_noise;
      }
      const double eps = cfg.epsilon * (gamma_img == &gamma_ ? res.gamma_weight : 1.0);
      const float wi = static_cast<float>(res.unsharp_amount);
      const float wb = static_cast<float>(1.0 - eps - res.unsharp_amount);
      const float wg = static_cast<float>(eps);
      res.image.create(gray.size(), CV_8UC1);
      for (int r = 0; r < gray.rows; ++r)
        blendRow(src->ptr<uint8_t>(r), blurred_.ptr<uint8_t>(r), gamma_img->ptr<uint8_t>(r), wi, wb, wg, gray.cols,
                 res.image.ptr<uint8_t>(r));
      break;
    }
  }
  res.ms = msSince(t0);
  return res;
}

}  // namespace iraf_vo
