#include "iraf_vo/tracking/metric_scale_monitor.h"

namespace iraf_vo {

void MetricScaleMonitor::restart() {
  window_.clear();
  sum_ = 0;
  weak_ = false;
}

bool MetricScaleMonitor::add(int close_inliers) {
  const bool was_weak = weak_;
  window_.push_back(close_inliers);
  sum_ += close_inliers;
  const size_t size = static_cast<size_t>(p_.stereo_scale_window_frames);
  while (window_.size() > size) {
    sum_ -= window_.front();
    window_.pop_front();
  }
  weak_ = p_.stereo_scale_min_close_inliers > 0 && window_.size() >= size &&
          static_cast<double>(sum_) < static_cast<double>(p_.stereo_scale_min_close_inliers) * window_.size();
  return weak_ != was_weak;
}

double MetricScaleMonitor::mean() const {
  return window_.empty() ? -1.0 : static_cast<double>(sum_) / static_cast<double>(window_.size());
}

}  // namespace iraf_vo
