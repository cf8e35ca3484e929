#include "iraf_vo/features/image_signal.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "iraf_vo/common/mask_noise.h"

namespace iraf_vo {

namespace {

constexpr int kBlock = 4;           // the estimate is made on kBlock x kBlock means
constexpr int kHistogramBins = 4096;  // |mask response| histogram, in 1/16 grey levels (larger values: last bin)
constexpr float kBinsPerGrey = 16.0f;
constexpr float kClippedGrey = 250.0f;  // a 4x4 mean at least this bright is clipped white

// The kBlock x kBlock means (CV_32F), as cv::resize with INTER_AREA gives them on the float image. When the size is a
// multiple of kBlock they are integer sums / 16: exact in float either way, so summed here in integers (5x faster).
static_assert(kBlock == 4, "blockMeans sums four columns");
void blockMeans(const cv::Mat& gray, cv::Mat* small) {
  const cv::Size size(gray.cols / kBlock, gray.rows / kBlock);
  if (gray.cols % kBlock != 0 || gray.rows % kBlock != 0) {
    cv::Mat as_float;
    gray.convertTo(as_float, CV_32F);
    cv::resize(as_float, *small, size, 0, 0, cv::INTER_AREA);
    return;
  }
  small->create(size, CV_32F);
  std::vector<uint16_t> col_sums(gray.cols);
  for (int by = 0; by < size.height; ++by) {
    std::fill(col_sums.begin(), col_sums.end(), 0);
    for (int k = 0; k < kBlock; ++k) {
      const uint8_t* row = gray.ptr<uint8_t>(by * kBlock + k);
      for (int x = 0; x < gray.cols; ++x) col_sums[x] = static_cast<uint16_t>(col_sums[x] + row[x]);
    }
    float* out = small->ptr<float>(by);
    for (int bx = 0; bx < size.width; ++bx) {
      const uint16_t* c = &col_sums[bx * kBlock];
      out[bx] = static_cast<float>(c[0] + c[1] + c[2] + c[3]) / (kBlock * kBlock);
    }
  }
}

}  // namespace

ImageSignal measureImageSignal(const cv::Mat& gray) {
  ImageSignal s;
  if (gray.empty() || gray.type() != CV_8UC1 || gray.rows < 3 * kBlock || gray.cols < 3 * kBlock) return s;
  cv::Mat small;  // in float: 8-bit means would be rounded back to whole grey levels
  blockMeans(gray, &small);
  cv::Scalar mean, stddev;
  cv::meanStdDev(small, mean, stddev);
  MaskResponseHistogram responses(kHistogramBins, kBinsPerGrey, false);
  for (int y = 1; y + 1 < small.rows; ++y) {
    const float* a = small.ptr<float>(y - 1);
    const float* b = small.ptr<float>(y);
    const float* c = small.ptr<float>(y + 1);
    for (int x = 1; x + 1 < small.cols; ++x) {
      const float r = maskResponse<float, float>(a, b, c, x);
      responses.addBin(static_cast<int>(std::abs(r) * kBinsPerGrey));  // past the last bin: counted in it
    }
  }
  s.measured = true;
  s.mean = mean[0];
  const double quantization = 1.0 / (kBlock * std::sqrt(12.0));
  s.noise_sigma = std::max(quantization, responses.noiseSigma());
  s.contrast = std::sqrt(std::max(0.0, stddev[0] * stddev[0] - s.noise_sigma * s.noise_sigma));
  s.snr = s.contrast / s.noise_sigma;
  s.clipped = static_cast<double>(cv::countNonZero(small >= kClippedGrey)) / static_cast<double>(small.total());
  return s;
}

}  // namespace iraf_vo
