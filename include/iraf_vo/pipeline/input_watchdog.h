// Is a live input stream still arriving? (ROS-free; used by the enhance nodelet for the camera topic and by the
// tracker nodelet for its features topic, driven by a wall-clock timer.)
//
// The expected period is the larger of the median of the last arrival intervals on the caller's clock (wall time: a
// bag played at half rate has twice the stamp period) and the stamp period the caller gives (frames that arrive in
// bursts have short arrival intervals), at least 40 ms. After `late_periods` (2.2) periods without a frame it is LATE
// (one warning: "no image on /cam0/image_raw for 0.11 s (2.2 periods of 50.0 ms): publisher stopped or stalled?"),
// after `dead_after` seconds it is DEAD (one error, /diagnostics ERROR), and the first frame after either gives one info
// line ("images on /cam0/image_raw again after 4.20 s"). Before the first frame nothing is expected until
// `dead_after` seconds after arm(); then the stream is SILENT (WARN: never started).
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "iraf_vo/pipeline/run_monitor.h"

namespace iraf_vo {

class InputWatchdog {
 public:
  enum class State { kIdle, kWaiting, kOk, kLate, kDead, kSilent };
  /// what: "image" / "features" (for the messages); dead_after [s]: silence until ERROR.
  explicit InputWatchdog(std::string what = "image", double dead_after = 3.0, double late_periods = 2.2);

  /// Start watching `topic` (subscribed at `now`); disarm() when unsubscribed (lazy subscription: no alarm).
  void arm(const std::string& topic, double now);
  void disarm();
  void setDeadAfter(double seconds) { dead_after_ = seconds; }
  /// A frame arrived at `now`: the message to log when the stream was late / dead / silent before.
  /// stamp_period: the nominal period from the stamps (StampGapCounter::period(); 0 = unknown).
  std::vector<SessionMessage> onFrame(double now, double stamp_period = 0.0);
  /// Called often (every period / 4 or so): the message to log when the state got worse.
  std::vector<SessionMessage> check(double now);

  State state() const { return state_; }
  /// Expected period [s] (0 before two frames and without a stamp period).
  double period() const;
  double silence(double now) const { return now - (have_frame_ ? last_ : armed_at_); }
  const std::string& topic() const { return topic_; }
  /// For /diagnostics: kOk while frames arrive (or before dead_after without any), WARN late (until the next frame)
  /// or silent, ERROR dead;
  /// *summary says why when not OK.
  HealthReport::Level level(double now, std::string* summary) const;

 private:
  std::string describeSilence(double now) const;

  std::string what_, topic_;
  double dead_after_, late_periods_;
  State state_ = State::kIdle;
  double armed_at_ = 0.0, last_ = 0.0;
  bool have_frame_ = false;
  double stamp_period_ = 0.0;
  std::deque<double> intervals_;
};

}  // namespace iraf_vo
