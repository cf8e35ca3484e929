// Unit tests of the enhancement stage (paper eqs. 1-12).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

#include "common/test_data.h"
#include "iraf_vo/common/mask_noise.h"
#include "iraf_vo/enhance/enhancer.h"

using namespace iraf_vo;
using iraf_vo_test::entropyBits;
using iraf_vo_test::withNoise;

namespace {

// eqs. (4)-(8) written out directly, independent of agcwdLut's code path.
double directGammaValue(const std::array<double, 256>& h, double lambda, double tau, int level) {
  double n = 0;
  for (double v : h) n += v;
  double pmax = 0, pmin = 1;
  for (double v : h) {
    pmax = std::max(pmax, v / n);
    pmin = std::min(pmin, v / n);
  }
  double sum_w = 0;
  for (double v : h) sum_w += pmax * std::pow((v / n - pmin) / (pmax - pmin), lambda);
  double cw = 0;
  for (int j = 0; j <= level; ++j) cw += pmax * std::pow((h[j] / n - pmin) / (pmax - pmin), lambda) / sum_w;
  const double gamma = std::max(tau, 1.0 - cw);
  return 255.0 * std::pow(level / 255.0, gamma);
}

cv::Mat scaled(const cv::Mat& img, double gain) {
  cv::Mat out;
  img.convertTo(out, CV_8U, gain);
  return out;
}

}  // namespace

TEST(AgcwdLut, EqualsEquationSevenOnHandMadeHistogram) {
  std::array<double, 256> h{};
  // A dark, bumpy histogram with empty bins.
  for (int i = 0; i < 256; ++i) h[i] = (i < 90 ? 400.0 - 3.0 * i : 0.0) + (i % 7 == 0 ? 25.0 : 0.0);
  h[200] = 13.0;
  for (double lambda : {0.25, 0.75, 1.0}) {
    for (double tau : {0.3, 0.5}) {
      const auto lut = agcwdLut(h, lambda, tau);
      for (int i = 0; i < 256; ++i) {
        const double expected = directGammaValue(h, lambda, tau, i);
        ASSERT_NEAR(lut[i], expected, 0.5 + 1e-9) << "level " << i << " lambda " << lambda << " tau " << tau;
      }
    }
  }
}

TEST(AgcwdLut, IsMonotonicAndBrightensDarkLevels) {
  std::array<double, 256> h{};
  for (int i = 0; i < 64; ++i) h[i] = 100.0;
  const auto lut = agcwdLut(h, 0.75, 0.5);
  EXPECT_EQ(lut[0], 0);
  EXPECT_EQ(lut[255], 255);
  for (int i = 1; i < 256; ++i) EXPECT_GE(lut[i], lut[i - 1]) << i;
  EXPECT_GT(lut[32], 32 + 20);  // gamma < 1 on the occupied dark levels
}

TEST(AgcwdLut, DegenerateHistogramsAreHandled) {
  std::array<double, 256> flat{};
  flat.fill(5.0);  // P_max == P_min
  const auto a = agcwdLut(flat, 0.75, 0.5);
  std::array<double, 256> empty{};
  const auto b = agcwdLut(empty, 0.75, 0.5);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(b[i], i);  // identity for an empty histogram
  EXPECT_EQ(a[255], 255);
}

TEST(Classification, FollowsEquationTen) {
  EnhanceParams p;
  p.mu_expected = 100.0;
  p.brightness_threshold = 0.3;
  double t = 0;
  EXPECT_EQ(classifyBrightness(60.0, p, &t), BrightnessClass::kDim);
  EXPECT_NEAR(t, -0.4, 1e-12);
  EXPECT_EQ(classifyBrightness(125.0, p, &t), BrightnessClass::kNormal);
  EXPECT_NEAR(t, 0.25, 1e-12);
  EXPECT_EQ(classifyBrightness(140.0, p, &t), BrightnessClass::kBright);
  EXPECT_NEAR(t, 0.4, 1e-12);
}

TEST(Enhancer, NormalImageOnlyGetsGaussianAndSharpening) {
  const cv::Mat img = iraf_vo_test::texturedImage();
  EnhanceParams p;
  p.mu_expected = cv::mean(img)[0];  // exactly "normal"
  Enhancer e;
  const EnhanceResult r = e.enhance(img, p);
  EXPECT_EQ(r.brightness, BrightnessClass::kNormal);
  // Expected: I' = B + eta * (I - B) with B the same Gaussian (epsilon term vanishes: I_gamma = I_gauss).
  cv::Mat B;
  cv::GaussianBlur(img, B, cv::Size(p.gaussian_kernel_size, p.gaussian_kernel_size), p.gaussian_sigma,
                   p.gaussian_sigma, cv::BORDER_REFLECT_101);
  cv::Mat I32, B32, expected;
  img.convertTo(I32, CV_32F);
  B.convertTo(B32, CV_32F);
  cv::Mat e32 = B32 + p.eta * (I32 - B32);
  e32.convertTo(expected, CV_8U);  // saturating, rounding
  cv::Mat diff;
  cv::absdiff(expected, r.image, diff);
  double maxdiff;
  cv::minMaxLoc(diff, nullptr, &maxdiff);
  EXPECT_LE(maxdiff, 1.0);
  EXPECT_GT(cv::norm(r.image, img, cv::NORM_L1), 0.0);  // sharpening did change it
}

TEST(Enhancer, CombinationEqualsScalarEquationsElevenTwelveExactly) {
  // A dim image (so I_gamma != I_gauss) whose width is not a multiple of the vector width: the vectorized blend
  // and the scalar tail must both give the bytes of eqs. (11)-(12) computed here pixel by pixel; both vector
  // kernels (128-bit; AVX-512 where the CPU has it).
  cv::Mat img(23, 37, CV_8U);
  cv::RNG rng(11);
  rng.fill(img, cv::RNG::UNIFORM, 0, 60);
  EnhanceParams p;
  p.unsharp_full_snr = 0.0;  // eta at every SNR and noise level (this image is noise only)
  p.unsharp_noise_none = 0.0;
  p.denoise_noise = 0.0;
  for (bool avx512 : {false, true}) {
  SCOPED_TRACE(enhanceBlendUseAvx512(avx512) ? "AVX-512" : "128-bit");
  Enhancer e;
  const EnhanceResult r = e.enhance(img, p);
  ASSERT_EQ(r.brightness, BrightnessClass::kDim);
  cv::Mat B;
  cv::GaussianBlur(img, B, cv::Size(p.gaussian_kernel_size, p.gaussian_kernel_size), p.gaussian_sigma,
                   p.gaussian_sigma, cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);
  const auto lut = agcwdLut(histogram256(B), p.dim_lambda, p.dim_tau);
  const float wi = static_cast<float>(p.eta), wb = static_cast<float>(1.0 - p.epsilon - p.eta),
              wg = static_cast<float>(p.epsilon);
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const uint8_t b = B.at<uint8_t>(y, x);
      const float v = wi * img.at<uint8_t>(y, x) + wb * b + wg * lut[b];
      ASSERT_EQ(r.image.at<uint8_t>(y, x), static_cast<uint8_t>(std::min(255.f, std::max(0.f, v + 0.5f))))
          << "at (" << x << ", " << y << ")";
    }
  }
  enhanceBlendUseAvx512(true);
}

TEST(Enhancer, UnsharpAmountFollowsTheSnrRamp) {
  EnhanceParams p;  // eta 1.5
  p.unsharp_full_snr = 8.0;  // ramp over SNR 5..8
  p.denoise_noise = 0.0;     // the ramp alone (the denoising: test_enhance_denoise)
  EXPECT_DOUBLE_EQ(unsharpAmount(20.0, p), p.eta);
  EXPECT_DOUBLE_EQ(unsharpAmount(8.0, p), p.eta);
  EXPECT_DOUBLE_EQ(unsharpAmount(6.5, p), 1.0 + 0.5 * (p.eta - 1.0));
  EXPECT_DOUBLE_EQ(unsharpAmount(5.0, p), 1.0);
  EXPECT_DOUBLE_EQ(unsharpAmount(0.5, p), 1.0);
  p.unsharp_full_snr = 0.0;  // the paper: eta always
  EXPECT_DOUBLE_EQ(unsharpAmount(0.5, p), p.eta);
}

TEST(Enhancer, NoisyImageIsNotSharpened) {
  // A camera at high gain: the textured image under Gaussian noise of 40 grey levels (estimated SNR < 5). The mask
  // would sharpen the noise; with the amount at 1 a normal image comes out as it went in (I + B - B).
  cv::Mat noise(iraf_vo_test::texturedImage().size(), CV_16S), noisy16, noisy;
  cv::RNG rng(3);
  rng.fill(noise, cv::RNG::NORMAL, 0, 40);
  iraf_vo_test::texturedImage().convertTo(noisy16, CV_16S);
  cv::Mat(noisy16 + noise).convertTo(noisy, CV_8U);
  EnhanceParams p;
  p.unsharp_full_snr = 8.0;  // ramp over SNR 5..8
  p.denoise_noise = 0.0;     // the ramp alone (the denoising: test_enhance_denoise)
  p.mu_expected = cv::mean(noisy)[0];  // normal
  Enhancer e;
  const EnhanceResult r = e.enhance(noisy, p);
  ASSERT_TRUE(r.signal.measured);
  EXPECT_LT(r.signal.snr, p.unsharp_min_snr);
  EXPECT_DOUBLE_EQ(r.unsharp_amount, 1.0);
  EXPECT_EQ(cv::norm(r.image, noisy, cv::NORM_INF), 0.0);
  // The clean image keeps the full amount.
  const EnhanceResult clean = e.enhance(iraf_vo_test::texturedImage(), p);
  EXPECT_GT(clean.signal.snr, p.unsharp_full_snr);
  EXPECT_DOUBLE_EQ(clean.unsharp_amount, p.eta);
}

TEST(PixelNoise, MeasuresSensorNoiseNotTexture) {
  // Texture at 4-48 px scales (the rostest render's kind of image, where the 4x4-mean SNR reads 7-8): no noise
  // found; added Gaussian noise of 3 / 8 / 20 grey levels found within 15 %.
  const cv::Mat tex = iraf_vo_test::texturedImage(376, 240);
  EXPECT_LT(estimatePixelNoise(tex), 1.5);
  for (double sigma : {3.0, 8.0, 20.0}) {
    const double est = estimatePixelNoise(withNoise(tex, sigma, 5));
    EXPECT_NEAR(est, sigma, 0.15 * sigma) << "sigma " << sigma;
  }
  EXPECT_EQ(estimatePixelNoise(cv::Mat()), 0.0);
  EXPECT_EQ(estimatePixelNoise(cv::Mat(2, 40, CV_8U, cv::Scalar(9))), 0.0);
  EXPECT_EQ(estimatePixelNoise(cv::Mat(20, 20, CV_32F, cv::Scalar(9))), 0.0);
}

TEST(MaskResponseHistogram, MedianInterpolatesInsideTheBinThatHoldsIt) {
  // Integer responses: bin v holds [v - 0.5, v + 0.5). Responses 0, 1, 1, 3: the half (2 of 4) falls in bin 1 after
  // one count below, half-way through its two counts -> 0.5 + 0.5 * 1.
  MaskResponseHistogram integers(8, 1.0, true);
  for (int r : {0, 1, 1, 3}) integers.addBin(r);
  EXPECT_DOUBLE_EQ(integers.median(), 1.0);
  EXPECT_DOUBLE_EQ(integers.noiseSigma(), 1.4826 / 6.0);
  // Binned responses, 16 bins per unit: bin v holds [v, v + 1) / 16; past the last bin counts in the last one.
  MaskResponseHistogram binned(32, 16.0, false);
  for (int b : {4, 8, 8, 100}) binned.addBin(b);
  EXPECT_DOUBLE_EQ(binned.median(), (8.0 + 0.5) / 16.0);
  binned.addBin(1000);
  binned.addBin(1000);
  EXPECT_EQ(binned.count(), 6);
  EXPECT_DOUBLE_EQ(binned.median(), (8.0 + 1.0) / 16.0);
  EXPECT_DOUBLE_EQ(MaskResponseHistogram(8, 1.0, true).median(), 0.0);
}

TEST(Enhancer, UnsharpAmountFollowsThePixelNoise) {
  EnhanceParams p;  // eta 1.5, ramp over 6..10 grey levels
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(1.0, p), p.eta);
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(6.0, p), p.eta);
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(8.0, p), 1.0 + 0.5 * (p.eta - 1.0));
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(10.0, p), 1.0);
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(40.0, p), 1.0);
  p.unsharp_noise_none = 0.0;  // off: the paper's eta always
  EXPECT_DOUBLE_EQ(unsharpAmountForNoise(40.0, p), p.eta);
}

TEST(Enhancer, DefaultDoesNotSharpenTheNoiseOfAHighGainCamera) {
  // The default settings on a textured image under the noise of a camera at high gain (20 grey levels): the
  // output carries no more noise than the input (the paper's fixed amount 1.5 adds half of it again), while a
  // clean image keeps the full amount, byte for byte as with the ramp off.
  const cv::Mat tex = iraf_vo_test::texturedImage(376, 240);
  const cv::Mat noisy = withNoise(tex, 20.0, 9);
  EnhanceParams p, paper;
  p.mu_expected = paper.mu_expected = cv::mean(noisy)[0];  // a normal image: no gamma term
  paper.unsharp_noise_none = 0.0;
  p.denoise_noise = paper.denoise_noise = 0.0;  // the amount alone (the denoising: test_enhance_denoise)
  Enhancer e;
  const EnhanceResult r = e.enhance(noisy, p);
  EXPECT_NEAR(r.pixel_noise, 20.0, 3.0);
  EXPECT_DOUBLE_EQ(r.unsharp_amount, 1.0);
  const double in = estimatePixelNoise(noisy), out = estimatePixelNoise(r.image);
  const double out_paper = estimatePixelNoise(e.enhance(noisy, paper).image);
  EXPECT_LT(out, 1.05 * in);
  EXPECT_GT(out_paper, 1.3 * in);
  const EnhanceResult clean = e.enhance(tex, p);
  EXPECT_DOUBLE_EQ(clean.unsharp_amount, p.eta);
  EXPECT_EQ(cv::norm(clean.image, e.enhance(tex, paper).image, cv::NORM_INF), 0.0);
}

TEST(Enhancer, SharpeningIsNotClippedBeforeCombination) {
  // A dark step edge: the negative side of the unsharp mask must survive (signed arithmetic).
  cv::Mat img(40, 40, CV_8U, cv::Scalar(100));
  img(cv::Rect(20, 0, 20, 40)).setTo(160);
  EnhanceParams p;
  p.mu_expected = cv::mean(img)[0];
  Enhancer e;
  const cv::Mat out = e.enhance(img, p).image;
  // Undershoot just left of the edge, overshoot just right of it.
  EXPECT_LT(out.at<uint8_t>(20, 19), 100);
  EXPECT_GT(out.at<uint8_t>(20, 20), 160);
  // Far from the edge: unchanged.
  EXPECT_EQ(out.at<uint8_t>(20, 5), 100);
  EXPECT_EQ(out.at<uint8_t>(20, 35), 160);
}

TEST(Enhancer, DarkSyntheticImageComesOutBrighterWithHigherEntropy) {
  const cv::Mat dark = scaled(iraf_vo_test::texturedImage(), 0.2);
  EnhanceParams p;
  Enhancer e;
  const EnhanceResult r = e.enhance(dark, p);
  EXPECT_EQ(r.brightness, BrightnessClass::kDim);
  EXPECT_LT(r.t, -p.brightness_threshold);
  EXPECT_GT(cv::mean(r.image)[0], cv::mean(dark)[0] + 20.0);
  EXPECT_GT(entropyBits(r.image), entropyBits(dark));
}

TEST(Enhancer, DarkRealEurocFrameComesOutBrighterWithHigherEntropy) {
  const cv::Mat frame = iraf_vo_test::eurocFrame(0);
  if (frame.empty()) GTEST_SKIP() << "shared EuRoC frames not found under " << IRAF_VO_SHARED_DIR;
  const cv::Mat dark = scaled(frame, 0.2);
  EnhanceParams p;  // generic mu_expected = 112
  Enhancer e;
  const EnhanceResult r = e.enhance(dark, p);
  EXPECT_EQ(r.brightness, BrightnessClass::kDim);
  EXPECT_GT(cv::mean(r.image)[0], 1.5 * cv::mean(dark)[0]);
  EXPECT_GT(entropyBits(r.image), entropyBits(dark));
}

TEST(Enhancer, RealLowLightStillsComeOutBrighterWithHigherEntropy) {
  const std::string dir = iraf_vo_test::sharedData("lowlight_stills/LIME");
  if (dir.empty()) GTEST_SKIP() << "shared low-light stills not found under " << IRAF_VO_SHARED_DIR;
  int checked = 0;
  for (const char* name : {"1.bmp", "3.bmp", "7.bmp"}) {
    const cv::Mat img = cv::imread(dir + "/" + name, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(img.empty()) << name;
    Enhancer e;
    const EnhanceResult r = e.enhance(img, EnhanceParams());
    if (r.brightness != BrightnessClass::kDim) continue;
    ++checked;
    EXPECT_GT(cv::mean(r.image)[0], cv::mean(img)[0]) << name;
    EXPECT_GT(entropyBits(r.image), entropyBits(img)) << name;
  }
  EXPECT_GE(checked, 2) << "expected the LIME stills to be classified dim";
}

TEST(Enhancer, OverBrightImageComesOutDarker) {
  cv::Mat src = iraf_vo_test::eurocFrame(0);
  if (src.empty()) src = iraf_vo_test::texturedImage();
  const cv::Mat bright = scaled(src, 3.0);  // saturates: over-exposed
  EnhanceParams p;
  p.texture_weighted_brightness = false;  // the paper: every pixel
  Enhancer e;
  const EnhanceResult r = e.enhance(bright, p);
  EXPECT_EQ(r.brightness, BrightnessClass::kBright);
  EXPECT_GT(r.t, p.brightness_threshold);
  EXPECT_LT(cv::mean(r.image)[0], cv::mean(bright)[0] - 5.0);
  // By default the clipped (flat) areas do not count: the class follows the textured pixels, less bright.
  const EnhanceResult by_texture = e.enhance(bright, EnhanceParams());
  EXPECT_GT(by_texture.mu_texture, 0.0);
  EXPECT_LT(by_texture.mu_texture, r.mu);
  EXPECT_LT(by_texture.t, r.t);
}

TEST(TextureWeightedHistogram, WeighsPixelsByTheirGradient) {
  cv::Mat flat(64, 64, CV_8UC1, cv::Scalar(200));
  const std::array<double, 256> none = textureWeightedHistogram(flat);
  for (double v : none) EXPECT_EQ(v, 0.0);
  EXPECT_EQ(histogramMean(none, 42.0), 42.0);  // nothing textured: the fallback
  // Left half flat at 240, right half a checkerboard of 90 / 110: the weight sits on the checkerboard.
  cv::Mat img(64, 64, CV_8UC1, cv::Scalar(240));
  for (int r = 0; r < 64; ++r)
    for (int c = 32; c < 64; ++c) img.at<uint8_t>(r, c) = ((r / 4 + c / 4) % 2) ? 110 : 90;
  const std::array<double, 256> h = textureWeightedHistogram(img);
  EXPECT_GT(cv::mean(img)[0], 165.0);
  EXPECT_NEAR(histogramMean(h, 0.0), 100.0, 25.0);  // the halved image's levels at the edges lie in between
}

// An outdoor view: a flat bright sky over a textured road of normal exposure. By the mean of every pixel the image
// is "bright" and the gamma correction darkens the road; weighted by texture it is normal and the road keeps its
// levels.
TEST(Enhancer, FlatBrightSkyDoesNotDarkenTheTexturedRoad) {
  cv::Mat img(160, 160, CV_8UC1, cv::Scalar(245));
  cv::Mat road = iraf_vo_test::texturedImage();
  cv::resize(road, road, cv::Size(160, 80));
  cv::Mat road_part = img(cv::Rect(0, 80, 160, 80));
  road.convertTo(road_part, CV_8U, 0.5, 40.0);  // about 100 +- 30
  const double road_in = cv::mean(road_part)[0];
  EnhanceParams p;
  p.eta = 1.0;  // no sharpening: only the gamma term moves the levels
  Enhancer e;
  p.texture_weighted_brightness = false;
  const EnhanceResult by_all = e.enhance(img, p);
  p.texture_weighted_brightness = true;
  const EnhanceResult by_texture = e.enhance(img, p);
  EXPECT_EQ(by_all.brightness, BrightnessClass::kBright);
  EXPECT_EQ(by_texture.brightness, BrightnessClass::kNormal);
  EXPECT_EQ(by_texture.mu, by_all.mu);  // eq. (9) is still reported
  EXPECT_LT(by_texture.mu_texture, by_all.mu - 30.0);
  const cv::Rect road_rect(0, 84, 160, 76);  // clear of the sky edge the blur spreads
  EXPECT_LT(cv::mean(by_all.image(road_rect))[0], road_in - 15.0);
  EXPECT_NEAR(cv::mean(by_texture.image(road_rect))[0], road_in, 2.0);
}

TEST(Enhancer, KeepsSizeAndTypeAndSurvivesTinyAndFlatInputs) {
  Enhancer e;
  EnhanceParams p;
  for (const cv::Mat& img : {cv::Mat(1, 1, CV_8U, cv::Scalar(7)), cv::Mat(480, 752, CV_8U, cv::Scalar(0)),
                             cv::Mat(480, 752, CV_8U, cv::Scalar(255)), cv::Mat(3, 200, CV_8U, cv::Scalar(90))}) {
    for (EnhanceMethod m : {EnhanceMethod::kIraf, EnhanceMethod::kHe, EnhanceMethod::kClahe, EnhanceMethod::kNone}) {
      p.method = m;
      const EnhanceResult r = e.enhance(img, p);
      EXPECT_EQ(r.image.size(), img.size()) << toString(m);
      EXPECT_EQ(r.image.type(), CV_8UC1) << toString(m);
      EXPECT_NE(r.image.data, img.data) << "result must not alias the input";
    }
  }
  // A non-continuous ROI is processed like its copy.
  const cv::Mat big = iraf_vo_test::texturedImage();
  const cv::Mat roi = big(cv::Rect(10, 10, 100, 80));
  p.method = EnhanceMethod::kIraf;
  EXPECT_EQ(cv::norm(e.enhance(roi, p).image, e.enhance(roi.clone(), p).image, cv::NORM_INF), 0.0);
}

TEST(Enhancer, RejectsBadInputAndBadParams) {
  Enhancer e;
  EXPECT_THROW(e.enhance(cv::Mat(), EnhanceParams()), std::invalid_argument);
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_8UC3), EnhanceParams()), std::invalid_argument);
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_16U), EnhanceParams()), std::invalid_argument);
  EnhanceParams bad;
  bad.gaussian_kernel_size = 4;
  EXPECT_FALSE(validate(bad).empty());
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_8U, cv::Scalar(1)), bad), std::invalid_argument);
  bad = EnhanceParams();
  bad.mu_expected = 0.0;
  EXPECT_NE(validate(bad).find("mu_expected"), std::string::npos);
  EXPECT_TRUE(validate(EnhanceParams()).empty());
}

TEST(Enhancer, ComparisonMethodsMatchOpenCv) {
  const cv::Mat img = scaled(iraf_vo_test::texturedImage(), 0.4);
  Enhancer e;
  EnhanceParams p;
  p.method = EnhanceMethod::kHe;
  cv::Mat he;
  cv::equalizeHist(img, he);
  EXPECT_EQ(cv::norm(e.enhance(img, p).image, he, cv::NORM_INF), 0.0);
  p.method = EnhanceMethod::kClahe;
  cv::Mat cl;
  cv::createCLAHE(3.0, cv::Size(8, 8))->apply(img, cl);
  EXPECT_EQ(cv::norm(e.enhance(img, p).image, cl, cv::NORM_INF), 0.0);
  p.method = EnhanceMethod::kNone;
  EXPECT_EQ(cv::norm(e.enhance(img, p).image, img, cv::NORM_INF), 0.0);
  EnhanceMethod m;
  EXPECT_TRUE(parseEnhanceMethod("clahe", &m));
  EXPECT_EQ(m, EnhanceMethod::kClahe);
  EXPECT_FALSE(parseEnhanceMethod("retinex", &m));
}

#include <yaml-cpp/yaml.h>

#include "iraf_vo/enhance/enhance_params.h"

TEST(EnhanceParamsIo, SetsEveryFieldByNameAndRejectsUnknownOrBadValues) {
  EnhanceParams p;
  std::string err;
  EXPECT_TRUE(enhanceParamTable().set(&p, "mu_expected", "50", &err)) << err;
  EXPECT_DOUBLE_EQ(p.mu_expected, 50.0);
  EXPECT_TRUE(enhanceParamTable().set(&p, "method", "clahe", &err)) << err;
  EXPECT_EQ(p.method, EnhanceMethod::kClahe);
  EXPECT_TRUE(enhanceParamTable().set(&p, "gaussian_kernel_size", "7", &err)) << err;
  EXPECT_EQ(p.gaussian_kernel_size, 7);
  EXPECT_FALSE(enhanceParamTable().set(&p, "gaussian_kernel_size", "7.5", &err));
  EXPECT_FALSE(enhanceParamTable().set(&p, "eta", "nan", &err));
  EXPECT_FALSE(enhanceParamTable().set(&p, "muexpected", "50", &err));
  EXPECT_NE(err.find("muexpected"), std::string::npos);
  // Every advertised name is settable.
  for (const auto& n : enhanceParamTable().names()) {
    EnhanceParams q;
    const std::string value = n == "method" ? "he" : n == "texture_weighted_brightness" ? "true" : "3";
    EXPECT_TRUE(enhanceParamTable().set(&q, n, value, &err)) << n << ": " << err;
  }
}

TEST(EnhanceParamsIo, LoadsYamlMapAndValidates) {
  EnhanceParams p;
  std::string err;
  EXPECT_TRUE(enhanceParamTable().load(YAML::Load("{mu_expected: 80, eta: 0.5, method: iraf}"), &p, &err)) << err;
  EXPECT_DOUBLE_EQ(p.mu_expected, 80.0);
  EXPECT_DOUBLE_EQ(p.eta, 0.5);
  EXPECT_FALSE(enhanceParamTable().load(YAML::Load("{gaussian_kernel_size: 4}"), &p, &err));
  EXPECT_NE(err.find("gaussian_kernel_size"), std::string::npos);
  EXPECT_FALSE(enhanceParamTable().load(YAML::Load("{typo_key: 1}"), &p, &err));
  EXPECT_FALSE(enhanceParamTable().load(YAML::Load("[1, 2]"), &p, &err));
}
