#include <iraf_vo/tracking/signal_check.h>

#include <algorithm>
#include <cstdio>

namespace iraf_vo {

std::string SignalCheck::tooDark(const ImageSignal& s) const {
  if (!p_.dark_check || !s.measured || s.mean > p_.dark_max_mean) return "";
  if (s.snr >= p_.dark_min_snr && s.contrast >= p_.dark_min_contrast) return "";
  char buf[160];
  std::snprintf(buf, sizeof(buf), "too dark: mean %.1f, estimated SNR %.2f (contrast %.2f, noise %.2f grey levels)",
                s.mean, s.snr, s.contrast, s.noise_sigma);
  return buf;
}

std::string SignalCheck::washedOut(const ImageSignal& s) const {
  if (!p_.dark_check || !s.measured || p_.washout_min_clipped >= 1.0 || s.clipped < p_.washout_min_clipped) return "";
  char buf[120];
  std::snprintf(buf, sizeof(buf), "washed out: %.0f %% of the image clipped white, mean %.1f", 100.0 * s.clipped, s.mean);
  return buf;
}

int SignalCheck::lostFramesBeforeReset() const {
  return recovering_ ? std::max(p_.lost_frames_before_reset, p_.dark_relocalization_frames)
                     : p_.lost_frames_before_reset;
}

int SignalCheck::trackedFrame() {
  if (!recovering_ || relocalized_) return 0;
  relocalized_ = true;
  return frames_since_dark_;
}

}  // namespace iraf_vo
