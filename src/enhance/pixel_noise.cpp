#include "iraf_vo/enhance/pixel_noise.h"

#include <algorithm>
#include <array>
#include <cstdlib>

namespace iraf_vo {

double estimatePixelNoise(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1 || gray.rows < 3 || gray.cols < 3) return 0.0;
  // |response| <= 16 * 255: one bin per integer value.
  std::array<long, 16 * 255 + 1> hist{};
  long total = 0;
  for (int y = 1; y + 1 < gray.rows; y += 2) {
    const uint8_t* a = gray.ptr<uint8_t>(y - 1);
    const uint8_t* b = gray.ptr<uint8_t>(y);
    const uint8_t* c = gray.ptr<uint8_t>(y + 1);
    for (int x = 1; x + 1 < gray.cols; x += 2) {
      const int r = (a[x - 1] + a[x + 1] + c[x - 1] + c[x + 1]) - 2 * (a[x] + c[x] + b[x - 1] + b[x + 1]) + 4 * b[x];
      ++hist[std::abs(r)];
      ++total;
    }
  }
  // Median of |r|, interpolated inside its bin (the responses are integers: bin v holds [v - 0.5, v + 0.5)).
  const double half = 0.5 * static_cast<double>(total);
  long below = 0;
  double median = 0.0;
  for (size_t v = 0; v < hist.size(); ++v) {
    if (hist[v] > 0 && static_cast<double>(below + hist[v]) >= half) {
      const double lo = v == 0 ? 0.0 : static_cast<double>(v) - 0.5, width = v == 0 ? 0.5 : 1.0;
      median = lo + width * (half - static_cast<double>(below)) / static_cast<double>(hist[v]);
      break;
    }
    below += hist[v];
  }
  return 1.4826 * median / 6.0;
}

}  // namespace iraf_vo
