#include "iraf_vo/enhance/pixel_noise.h"

#include <cstdlib>

#include "iraf_vo/common/mask_noise.h"

namespace iraf_vo {

double estimatePixelNoise(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1 || gray.rows < 3 || gray.cols < 3) return 0.0;
  MaskResponseHistogram responses(16 * 255 + 1, 1.0, true);  // |response| <= 16 * 255: one bin per integer value
  for (int y = 1; y + 1 < gray.rows; y += 2) {
    const uint8_t* a = gray.ptr<uint8_t>(y - 1);
    const uint8_t* b = gray.ptr<uint8_t>(y);
    const uint8_t* c = gray.ptr<uint8_t>(y + 1);
    for (int x = 1; x + 1 < gray.cols; x += 2) responses.addBin(std::abs(maskResponse<uint8_t, int>(a, b, c, x)));
  }
  return responses.noiseSigma();
}

}  // namespace iraf_vo
