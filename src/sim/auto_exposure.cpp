#include "iraf_vo/sim/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace iraf_vo {

std::string validate(const AutoExposureParams& p) {
  std::ostringstream err;
  if (!(p.target_grey > 0.0 && p.target_grey < 255.0)) err << "target_grey must be in (0, 255); ";
  if (!(p.loop_gain > 0.0 && p.loop_gain <= 4.0)) err << "loop_gain must be in (0, 4]; ";
  if (p.delay_frames < 0 || p.delay_frames > 100) err << "delay_frames must be in [0, 100]; ";
  if (!(p.max_step > 1.0)) err << "max_step must be > 1; ";
  if (!(p.dead_band >= 0.0)) err << "dead_band must be >= 0; ";
  if (!(p.min_time_s > 0.0 && p.max_time_s >= p.min_time_s)) err << "need 0 < min_time_s <= max_time_s; ";
  if (!(p.min_gain > 0.0 && p.max_gain >= p.min_gain)) err << "need 0 < min_gain <= max_gain; ";
  if (!(p.initial.time_s > 0.0) || !(p.initial.gain > 0.0)) err << "initial exposure time and gain must be > 0; ";
  return err.str();
}

AutoExposure::AutoExposure(const AutoExposureParams& params) : p_(params), current_(params.initial) {
  const std::string err = validate(params);
  if (!err.empty()) throw std::invalid_argument("AutoExposure: " + err);
}

Exposure AutoExposure::split(double total) const {
  Exposure e;
  e.time_s = std::min(p_.max_time_s, std::max(p_.min_time_s, total));
  e.gain = std::min(p_.max_gain, std::max(p_.min_gain, total / e.time_s));
  return e;
}

void AutoExposure::meter(double mean_grey) {
  metered_.push_back(mean_grey);
  if (!p_.enabled) return;
  // The image that decides the next frame's exposure: delay_frames older than the one just taken.
  const int frame = static_cast<int>(metered_.size()) - 1 - p_.delay_frames;
  if (frame < 0) return;
  const double metered = std::max(0.5, metered_[frame]);  // a black image asks for the largest step
  const double error = std::log(p_.target_grey / metered);
  if (std::abs(error) <= p_.dead_band) return;
  const double step = std::min(std::log(p_.max_step), std::max(-std::log(p_.max_step), p_.loop_gain * error));
  current_ = split(current_.time_s * current_.gain * std::exp(step));
}

}  // namespace iraf_vo
