// Image noise from the median absolute response of the mask [1 -2 1; -2 4 -2; 1 -2 1] (ROS-free). The mask cancels
// planar intensity, so shading does not count, and edges are too few to move the median; the noise sigma is that
// median x 1.4826 / 6 (the Gaussian MAD factor / the mask's noise gain sqrt(36)). Used on the pixels
// (enhance/pixel_noise.h) and on 4x4-pixel means (features/image_signal.h).
#pragma once

#include <cstddef>
#include <vector>

namespace iraf_vo {

/// The mask's response at column x of the middle row, from the rows above and below (x-1 and x+1 must exist).
template <class Pixel, class Response = decltype(Pixel() + Pixel())>
inline Response maskResponse(const Pixel* above, const Pixel* row, const Pixel* below, int x) {
  return (above[x - 1] + above[x + 1] + below[x - 1] + below[x + 1]) - 2 * (above[x] + below[x] + row[x - 1] + row[x + 1]) +
         4 * row[x];
}

/// A histogram of |mask response| and the noise sigma its median gives.
class MaskResponseHistogram {
 public:
  /// Bin layout: when `integer_responses`, bin v holds the integer response v, i.e. [v - 0.5, v + 0.5) ([0, 0.5) for
  /// bin 0); otherwise bin v holds [v, v + 1) / bins_per_unit. Responses past the last bin count in the last bin.
  MaskResponseHistogram(int bins, double bins_per_unit, bool integer_responses);

  void addBin(int bin) { ++hist_[bin < last_ ? bin : last_]; ++total_; }
  long count() const { return total_; }

  /// Median |response|, interpolated inside the bin that holds it; 0 when empty.
  double median() const;
  /// Noise sigma of what the mask was applied to: 1.4826 * median / 6.
  double noiseSigma() const { return 1.4826 * median() / 6.0; }

 private:
  std::vector<long> hist_;
  int last_;
  double bins_per_unit_;
  bool integer_responses_;
  long total_ = 0;
};

}  // namespace iraf_vo
