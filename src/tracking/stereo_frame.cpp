#include "iraf_vo/tracking/stereo_frame.h"

#include "iraf_vo/common/wall_clock.h"

namespace iraf_vo {

bool StereoFrame::begin(bool has_right, RightFeatures features, const cv::Mat& left_image) {
  const bool new_run = !has_right && !last_missing_;
  last_missing_ = !has_right;
  has_right_ = has_right;
  features_ = has_right ? std::move(features) : RightFeatures();
  matched_ = false;
  matches_.clear();
  left_image_ = has_right ? left_image : cv::Mat();
  return new_run;
}

const std::vector<StereoMatch>& StereoFrame::matches(Frame* cur, double* ms) {
  *ms = 0.0;
  if (matched_) return matches_;
  matched_ = true;
  if (!has_right_ || !features_) return matches_;
  const auto t0 = SteadyClock::now();
  if (!matcher_.matchRight(cur, features_(), &matches_, left_image_)) matches_.clear();
  features_ = RightFeatures();
  left_image_ = cv::Mat();
  *ms = msSince(t0);
  return matches_;
}

}  // namespace iraf_vo
