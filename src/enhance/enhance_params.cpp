#include "iraf_vo/enhance/enhance_params.h"

#include "iraf_vo/common/enum_names.h"

namespace iraf_vo {

namespace {
constexpr EnumName<EnhanceMethod> kMethodNames[] = {
    {EnhanceMethod::kNone, "none"}, {EnhanceMethod::kIraf, "iraf"}, {EnhanceMethod::kHe, "he"},
    {EnhanceMethod::kClahe, "clahe"}};
}  // namespace

const char* toString(EnhanceMethod m) { return nameOf(kMethodNames, m, "iraf"); }

bool parseEnhanceMethod(const std::string& s, EnhanceMethod* m) { return parseName(kMethodNames, s, m); }

const ParamTable<EnhanceParams>& enhanceParamTable() {
  using P = EnhanceParams;
  // The ranges also bound what sizes an allocation (kernel, CLAHE tiles) or is converted to float (the weights).
  static const ParamTable<P> table(
      "enhance",
      {
          enumParam("method", &P::method, toString, parseEnhanceMethod,
                    "Preprocessing method: none | iraf | he | clahe"),
          intParam("gaussian_kernel_size", &P::gaussian_kernel_size, 1, 15,
                   "eqs. 1-2: Gaussian kernel size (odd; 1 = off). Not in the paper; 5 chosen", /*odd=*/true),
          doubleParam("gaussian_sigma", &P::gaussian_sigma, 0.1, 5.0,
                      "eqs. 1-2: Gaussian sigma [px]. Not in the paper; 1.0 chosen"),
          doubleParam("mu_expected", &P::mu_expected, 1.0, 254.0,
                      "eq. 10: expected mean intensity (112 generic; 50 used for EuRoC)"),
          doubleParam("brightness_threshold", &P::brightness_threshold, 0.0, 2.0,
                      "eq. 10: |t| above this -> dim or bright (authors' code: 0.3)"),
          doubleParam("brightness_ramp", &P::brightness_ramp, 0.0, 2.0,
                      "Gamma correction weight min(1, (|t| - brightness_threshold) / ramp): continuous across the "
                      "class boundary under exposure changes; 0 = the paper's hard switch"),
          boolParam("texture_weighted_brightness", &P::texture_weighted_brightness,
                    "Bright (eq. 10) only if the textured pixels are (gradient-weighted mean), their histogram for "
                    "eq. 3: a flat sky or blown-out area does not darken the texture. Off: every pixel, as printed"),
          doubleParam("dim_lambda", &P::dim_lambda, 0.01, 2.0,
                      "eq. 5: smoothness lambda for dim images (authors' code: 0.75)"),
          doubleParam("dim_tau", &P::dim_tau, 0.01, 1.0,
                      "eq. 7: lower gamma bound tau for dim images (authors' code: 0.5)"),
          doubleParam("bright_lambda", &P::bright_lambda, 0.01, 2.0,
                      "eq. 5: lambda on the inverted image for bright images (authors' code: 0.25)"),
          doubleParam("bright_tau", &P::bright_tau, 0.01, 1.0, "eq. 7: tau on the inverted image for bright images"),
          doubleParam("epsilon", &P::epsilon, 0.0, 3.0, "eq. 12: weight of the gamma term (I_gamma - I_gauss)"),
          doubleParam("eta", &P::eta, 0.0, 5.0,
                      "eq. 12: weight of the unsharp mask G_mask (unsharp amount, authors' code: 1.5)"),
          doubleParam("unsharp_min_snr", &P::unsharp_min_snr, 0.0, 100.0,
                      "At or below this estimated SNR (contrast / noise of 4x4 means) the unsharp amount is 1: no "
                      "sharpening of the noise"),
          doubleParam("unsharp_full_snr", &P::unsharp_full_snr, 0.0, 100.0,
                      "At or above this estimated SNR the unsharp amount is eta (linear in between); 0 = eta always"),
          doubleParam("unsharp_noise_full", &P::unsharp_noise_full, 0.0, 255.0,
                      "At or below this pixel noise [grey levels] the unsharp amount is eta (SNR ramp permitting)"),
          doubleParam("unsharp_noise_none", &P::unsharp_noise_none, 0.0, 255.0,
                      "At or above this pixel noise [grey levels] the unsharp amount is 1: no sharpening of the "
                      "noise (linear from unsharp_noise_full); 0 = off"),
          doubleParam("denoise_noise", &P::denoise_noise, 0.0, 255.0,
                      "Above this pixel noise [grey levels] the image is first smoothed by a Gaussian that brings the "
                      "noise down to about this level (sigma = noise / (2 sqrt(pi) denoise_noise)); 0 = off"),
          doubleParam("clahe_clip_limit", &P::clahe_clip_limit, 0.1, 40.0, "CLAHE clip limit (ORB-SLAM3 TUM-VI: 3.0)"),
          intParam("clahe_tiles", &P::clahe_tiles, 1, 32, "CLAHE tiles per side (ORB-SLAM3 TUM-VI: 8)"),
      });
  return table;
}

std::string validate(const EnhanceParams& p) { return enhanceParamTable().validate(p); }

}  // namespace iraf_vo
