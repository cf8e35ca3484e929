#include "iraf_vo/common/mask_noise.h"

namespace iraf_vo {

MaskResponseHistogram::MaskResponseHistogram(int bins, double bins_per_unit, bool integer_responses)
    : hist_(static_cast<std::size_t>(bins), 0), last_(bins - 1), bins_per_unit_(bins_per_unit),
      integer_responses_(integer_responses) {}

double MaskResponseHistogram::median() const {
  if (total_ == 0) return 0.0;
  const double half = 0.5 * static_cast<double>(total_);
  long below = 0;
  for (std::size_t v = 0; v < hist_.size(); ++v) {
    if (hist_[v] > 0 && static_cast<double>(below + hist_[v]) >= half) {
      const double fraction = (half - static_cast<double>(below)) / static_cast<double>(hist_[v]);
      if (!integer_responses_) return (static_cast<double>(v) + fraction) / bins_per_unit_;
      const double lo = v == 0 ? 0.0 : static_cast<double>(v) - 0.5, width = v == 0 ? 0.5 : 1.0;
      return (lo + width * fraction) / bins_per_unit_;
    }
    below += hist_[v];
  }
  return static_cast<double>(hist_.size()) / bins_per_unit_;
}

}  // namespace iraf_vo
