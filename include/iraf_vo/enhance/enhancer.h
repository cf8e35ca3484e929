// Image enhancement stage of IRAF-SLAM (paper section II-A, eqs. 1-12). ROS-free.
//
//   I_blurred = I * G_gauss                                        eqs. (1)-(2)
//   mu, t = (mu - mu_expected) / mu_expected -> dim / normal / bright  eqs. (9)-(10)
//   AGCWD LUT on I_blurred (inverted first for bright images)      eqs. (3)-(8)
//   G_mask = I - I_blurred                                         eq. (11)
//   I' = I_blurred + epsilon * (I_gamma - I_gauss) + eta * G_mask  eq. (12)
//
// I_gauss in eq. (12) is the same Gaussian-filtered image as I_blurred (the paper uses both names).
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <array>
#include <string>

#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/enhance/pixel_noise.h"
#include "iraf_vo/features/image_signal.h"

namespace iraf_vo {

enum class BrightnessClass { kDim = -1, kNormal = 0, kBright = 1 };
const char* toString(BrightnessClass c);

struct EnhanceResult {
  cv::Mat image;  // CV_8UC1, same size as the input
  BrightnessClass brightness = BrightnessClass::kNormal;
  double mu = 0.0;  // eq. (9): mean intensity
  double mu_texture = 0.0;  // texture_weighted_brightness: the texture-weighted mean that sets t instead (else 0)
  double t = 0.0;   // eq. (10)
  double gamma_weight = 0.0;  // weight of the gamma correction actually applied (0 for a normal image; brightness_ramp)
  double unsharp_amount = 0.0;  // eq. (12) eta actually applied (iraf): eta, lowered toward 1 at a low SNR
  ImageSignal signal;           // of the input, when the unsharp amount needed it (measured = false otherwise)
  double pixel_noise = 0.0;     // of the input [grey levels] (enhance/pixel_noise.h), when the amount or the denoising needed it
  double denoise_sigma = 0.0;   // of the Gaussian that denoised the input before eqs. (1)-(12) (0 = none)
  double ms = 0.0;  // wall time spent in enhance()
};

/// eq. (12)'s unsharp amount at an image's estimated SNR: cfg.eta at or above cfg.unsharp_full_snr (or when it is
/// 0), 1 (no sharpening) at or below cfg.unsharp_min_snr, linear in between.
double unsharpAmount(double snr, const EnhanceParams& cfg);

/// eq. (12)'s unsharp amount at an image's pixel noise [grey levels]: cfg.eta at or below cfg.unsharp_noise_full
/// (or when cfg.unsharp_noise_none is 0), 1 at or above cfg.unsharp_noise_none, linear in between.
double unsharpAmountForNoise(double noise, const EnhanceParams& cfg);

/// Sigma [px] of the denoising Gaussian at an image's pixel noise [grey levels]: 0 (none) at or below
/// cfg.denoise_noise (or when it is 0), else noise / (2 sqrt(pi) cfg.denoise_noise), which brings white noise
/// of that level down to about cfg.denoise_noise.
double denoiseSigma(double noise, const EnhanceParams& cfg);

/// Lets the iraf blend (eqs. 11-12) use AVX-512 (where the CPU has AVX-512BW; the default) or 128-bit SIMD:
/// the same bytes. For tests; returns whether AVX-512 is now in use.
bool enhanceBlendUseAvx512(bool allowed);

/// eqs. (3)-(7): the 256-entry gamma-correction LUT of a histogram (counts per intensity level).
/// lut[i] = round(255 * (i / 255)^gamma(i)), gamma(i) = max(tau, 1 - C_w(i)).
std::array<uint8_t, 256> agcwdLut(const std::array<double, 256>& histogram, double lambda, double tau);

/// Histogram of a CV_8UC1 image as doubles (eq. 3).
std::array<double, 256> histogram256(const cv::Mat& gray);

/// Histogram of a CV_8UC1 image with each pixel weighted by its gradient (|dx| + |dy| of central differences on
/// the image halved by area averaging; the halved image's levels). All zeros on a flat image.
std::array<double, 256> textureWeightedHistogram(const cv::Mat& gray);

/// Mean level of a histogram; `fallback` when it is empty.
double histogramMean(const std::array<double, 256>& h, double fallback);

/// eqs. (9)-(10).
BrightnessClass classifyBrightness(double mu, const EnhanceParams& cfg, double* t);

/// Weight of the gamma correction at eq. (10)'s t: 0 for |t| <= brightness_threshold, then
/// min(1, (|t| - brightness_threshold) / brightness_ramp) (1 when brightness_ramp is 0).
double gammaWeight(double t, const EnhanceParams& cfg);

/// Stateless apart from a CLAHE object reused between frames; one instance per thread.
class Enhancer {
 public:
  /// `gray` must be a non-empty CV_8UC1 image; throws std::invalid_argument otherwise, or when the
  /// config does not validate. The result never aliases the input.
  EnhanceResult enhance(const cv::Mat& gray, const EnhanceParams& cfg);

 private:
  cv::Mat denoised_, blurred_, gamma_;
  cv::Ptr<cv::CLAHE> clahe_;
  double clahe_clip_ = -1.0;
  int clahe_tiles_ = -1;
};

}  // namespace iraf_vo
