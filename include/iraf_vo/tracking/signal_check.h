// Darkness: whether a frame's image carries a usable signal, and the relocalization in the same map once the
// light returns (tracking thread; ROS-free).
//
// A frame is too dark when its image (ImageSignal, measured by the front-end before enhancement) has a mean grey of
// at most dark_max_mean and an estimated SNR below dark_min_snr or a contrast above the noise below
// dark_min_contrast. A frame is washed out when at least washout_min_clipped of its 4x4-pixel means are clipped
// white (the light returns on an exposure set for the dark, a flash): no texture is left either. Such a frame is not tracked at all: it is LOST with the reason ("too dark: mean 3, estimated
// SNR 0.8"), gives no pose, and neither counts towards the reset nor touches the map, the mapper or the
// initializer. When the light returns the tracker relocalizes in the map it kept (same scale, same world frame):
// the pose tracker's projection search around the last pose (normal, then wide window, then brute-force matching
// against all map points + PnP; a pose from the search needs Relocalizer::kMinAcceptedInliers before its narrow
// re-search, else the PnP decides, and it competes with the PnP pose), then the keyframe-wise Relocalizer
// (relocalizer.h) with the last pose moved on at the velocity before the dark (tracker_relocalization.cpp). Within
// dark_relocalization_frames frames after the last dark one a loss resets the map only after that many consecutive
// lost frames (instead of lost_frames_before_reset).
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
  /// "" unless the image is washed out, e.g. "washed out: 92 % of the image clipped white, mean 248".
  std::string washedOut(const ImageSignal& s) const;
  /// Why the image carries no usable signal (too dark or washed out), "" when it does.
  std::string noSignal(const ImageSignal& s) const {
    std::string why = tooDark(s);
    return why.empty() ? washedOut(s) : why;
  }

  /// A dark frame while a map exists: recovery in the same map follows once the light returns.
  void darkFrame() { recovering_ = true, relocalized_ = false, frames_since_dark_ = 0; }
  /// A frame with signal (called for every such frame before it is tracked).
  void lightFrame() {
    if (recovering_ && ++frames_since_dark_ > p_.dark_relocalization_frames) restart();
  }
  /// Consecutive lost frames allowed before the map is reset: dark_relocalization_frames within that many frames
  /// after dark ones (the light's return is a transient: the auto-exposure overshoots, a first relocalized pose
  /// may be lost again), else lost_frames_before_reset.
  int lostFramesBeforeReset() const;
  /// A tracked frame: the number of frames with signal it took to relocalize after darkness (1 = the first frame
  /// after the dark ones) for the first tracked frame after dark ones, else 0.
  int trackedFrame();
  /// The map was reset or re-initialized: no recovery pending.
  void restart() { recovering_ = false, relocalized_ = false, frames_since_dark_ = 0; }
  /// Within dark_relocalization_frames frames after dark ones.
  bool recovering() const { return recovering_; }
  /// Recovering and not tracked yet since the last dark frame: the next pose is a relocalization in the kept map.
  bool awaitingRelocalization() const { return recovering_ && !relocalized_; }

 private:
  const TrackerParams& p_;
  bool recovering_ = false;
  bool relocalized_ = false;   // tracked again since the last dark frame
  int frames_since_dark_ = 0;  // frames with signal since the last dark frame
};

}  // namespace iraf_vo
