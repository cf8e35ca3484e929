// Auto-exposure controller of the simulated camera (ROS-free). After each frame it meters the image's
// mean grey; the exposure of frame i is decided from the image of frame i - 1 - delay_frames (the
// sensor pipeline's lag), as a multiplicative step on the current total exposure (time x gain):
//
//   step = clamp((target / metered)^loop_gain, 1 / max_step, max_step)     (1 inside the dead band)
//   total_i = total_{i-1} * step;  time = clamp(total, min, max time); gain = total / time, clamped
//
// The exposure time is raised first; the gain only once the time is at its maximum (noise grows with
// it). loop_gain < 1 converges smoothly; a loop gain above the stability limit of the delayed loop
// (about 0.6 with delay 2) overshoots and hunts, bounded by max_step and the limits.
#pragma once

#include <string>
#include <vector>

#include "iraf_vo/sim/sensor_model.h"

namespace iraf_vo {

struct AutoExposureParams {
  bool enabled = true;           // false: every frame uses `initial`
  double target_grey = 110.0;    // mean grey the controller aims at
  double loop_gain = 0.5;        // share of the log error corrected per step (> stability limit: hunting)
  int delay_frames = 1;          // frames between the metered image and the exposure it sets
  double max_step = 1.6;         // largest change of the total exposure per frame (factor)
  double dead_band = 0.06;       // |log(target / metered)| below this: no change
  double min_time_s = 50e-6, max_time_s = 0.03;
  double min_gain = 1.0, max_gain = 8.0;
  Exposure initial;              // exposure of the first frames (before the first metering applies)
};

/// Returns a message naming the first bad field, or "" when usable.
std::string validate(const AutoExposureParams& p);

class AutoExposure {
 public:
  /// Throws std::invalid_argument for bad parameters.
  explicit AutoExposure(const AutoExposureParams& params);

  /// Exposure for the next frame (frame number = frames metered so far).
  Exposure next() const { return current_; }
  /// Meters the frame just taken with next(): its mean grey. Updates next().
  void meter(double mean_grey);
  /// Forgets the metered frames (keeps next()): the sequence starts after a settling period.
  void restartHistory() { metered_.clear(); }

  const AutoExposureParams& params() const { return p_; }

 private:
  /// Time and gain of a total exposure (relative to 1 s at unity gain), within the limits.
  Exposure split(double total) const;

  AutoExposureParams p_;
  Exposure current_;
  std::vector<double> metered_;  // mean grey of every frame taken so far
};

}  // namespace iraf_vo
