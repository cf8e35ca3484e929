// Parameters of the enhancement stage (paper section II-A): the struct (its initializers are the defaults) and its
// parameter table (common/param_table.h): names = field names = cfg/Enhance.cfg parameters = YAML `enhance:` keys =
// `--set enhance.key=value`. ROS-free.
#pragma once

#include <string>

#include "iraf_vo/common/param_table.h"

namespace iraf_vo {

/// Which preprocessing runs. `iraf` is the paper's pipeline; `he` / `clahe` are the comparison
/// front-ends of the paper's Table I (HE-SLAM, CLAHE-SLAM); `none` passes the image through.
enum class EnhanceMethod { kNone = 0, kIraf = 1, kHe = 2, kClahe = 3 };
const char* toString(EnhanceMethod m);
/// Parses "none" | "iraf" | "he" | "clahe"; returns false for anything else.
bool parseEnhanceMethod(const std::string& s, EnhanceMethod* m);

struct EnhanceParams {
  EnhanceMethod method = EnhanceMethod::kIraf;

  // eqs. (1)-(2): Gaussian filter. Not given in the paper or the authors' code: 5x5, sigma 1.0
  // removes sensor noise without erasing FAST-scale corners (unsharp masking restores edges).
  int gaussian_kernel_size = 5;  // odd, >= 1 (1 = no smoothing)
  double gaussian_sigma = 1.0;

  // eqs. (9)-(10): brightness classification.
  double mu_expected = 112.0;         // expected mean intensity; 112 generic, 50 used for EuRoC
  double brightness_threshold = 0.3;  // |t| above this -> dim (t < 0) or bright (t > 0)
  // The gamma correction of a dim / bright image is weighted by min(1, (|t| - brightness_threshold) /
  // brightness_ramp): 0 at the class boundary, so the output changes continuously with the exposure instead of
  // jumping when t crosses the threshold. 0 = the paper's hard switch (full weight as soon as |t| > threshold).
  double brightness_ramp = 0.1;
  // An image bright by eq. (9)'s mean is bright only as far as its textured pixels are (their gradient-weighted
  // mean, textureWeightedHistogram), and its gamma curve comes from their histogram: a flat sky or blown-out wall
  // does not darken the texture. Dim is judged as printed. false: every pixel, as printed.
  bool texture_weighted_brightness = true;

  // eqs. (5)-(7) for dim images: smoothness lambda and lower gamma bound tau.
  double dim_lambda = 0.75;
  double dim_tau = 0.5;
  // The same on the inverted image for over-bright images ("dimming").
  double bright_lambda = 0.25;
  double bright_tau = 0.5;

  // eq. (12): weights of the gamma term (epsilon) and of the unsharp mask (eta, the unsharp amount).
  double epsilon = 1.0;
  double eta = 1.5;
  // The unsharp mask amplifies the sensor noise with the detail: its amount falls from eta to 1 (no sharpening)
  // as the image's estimated SNR (features/image_signal.h) falls from unsharp_full_snr to unsharp_min_snr.
  // unsharp_full_snr 0 = eta at every SNR (the paper).
  double unsharp_min_snr = 5.0;
  double unsharp_full_snr = 0.0;  // 0 by default: docs/decisions.md
  // The same from the pixel-scale sensor noise (enhance/pixel_noise.h), which fine texture does not raise: the
  // amount is eta up to unsharp_noise_full grey levels of noise and 1 from unsharp_noise_none on (linear in
  // between). unsharp_noise_none 0 = off. The smaller of the two amounts applies.
  double unsharp_noise_full = 6.0;
  double unsharp_noise_none = 10.0;
  // Denoising before eqs. (1)-(12) on an image whose pixel noise exceeds denoise_noise grey levels (a camera at
  // high gain): a Gaussian sized so that white noise of the measured level falls to about denoise_noise (sigma =
  // noise / (2 sqrt(pi) denoise_noise): no blur at the threshold, 1.7 px at 24 grey levels). Clean images (EuRoC
  // 1.2-2.0) are untouched. The unsharp amount still follows the input's noise (1 on such an image). 0 = off.
  double denoise_noise = 4.0;  // docs/decisions.md

  // Comparison front-ends (Table I): CLAHE as ORB-SLAM3 uses it for TUM-VI.
  double clahe_clip_limit = 3.0;
  int clahe_tiles = 8;
};

/// Every EnhanceParams field with its accepted range and doc (cfg/Enhance.cfg also has the nodelet's `enabled`).
const ParamTable<EnhanceParams>& enhanceParamTable();

/// Returns a message naming each field out of its table range, or "" when the params are usable.
std::string validate(const EnhanceParams& p);

}  // namespace iraf_vo
