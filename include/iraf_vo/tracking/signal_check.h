// Darkness: whether a frame's image carries a usable signal, and the relocalization in the same map once the
// light returns (tracking thread; ROS-free).
//
// A frame is too dark when its image (ImageSignal, measured by the front-end before enhancement) has a mean grey of
// at most dark_max_mean and an estimated SNR below dark_min_snr or a contrast above the noise below
// dark_min_contrast. Such a frame is not tracked at all: it is LOST with the reason ("too dark: mean 3, estimated
// SNR 0.8"), gives no pose, and neither counts towards the reset nor touches the map, the mapper or the
// initializer. When the light returns the tracker relocalizes in the map it kept (same scale, same world frame):
// the pose tracker's projection search around the last pose (normal, then wide window), then brute-force matching
// against the map's points + PnP RANSAC; only after dark_relocalization_frames failed frames (instead of
// lost_frames_before_reset) does it reset the map.
#pragma once

#include <iraf_vo/features/image_signal.h>
#include <iraf_vo/tracking/tracker_params.h>

#include <string>

namespace iraf_vo {

class SignalCheck {
 public:
  explicit SignalCheck(const TrackerParams& params) : p_(params) {}

  /// "" when the image can be tracked (or carries no estimate), else why not, e.g.
  /// "too dark: mean 3, estimated SNR 0.8".
  std::string tooDark(const ImageSignal& s) const;

  /// A dark frame while a map exists: recovery in the same map follows once the light returns.
  void darkFrame() { recovering_ = true, frames_since_dark_ = 0; }
  /// A frame with signal that could not be tracked.
  void lostFrame() {
    if (recovering_) ++frames_since_dark_;
  }
  /// Consecutive lost frames allowed before the map is reset: dark_relocalization_frames while recovering from
  /// darkness, else lost_frames_before_reset.
  int lostFramesBeforeReset() const;
  /// A tracked frame: the number of frames with signal it took to relocalize after darkness (1 = the first frame
  /// after the dark ones), or 0 when it did not end a recovery.
  int trackedFrame();
  /// The map was reset or re-initialized: no recovery pending.
  void restart() { recovering_ = false, frames_since_dark_ = 0; }
  bool recovering() const { return recovering_; }

 private:
  const TrackerParams& p_;
  bool recovering_ = false;
  int frames_since_dark_ = 0;  // frames with signal since the last dark frame, all lost
};

}  // namespace iraf_vo
