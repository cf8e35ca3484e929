// Which right image goes with which left image of a stereo camera (ROS-free; used by the tracker nodelet for the
// two feature streams and by the rosbag FrameSource for two image topics).
//
// The caller feeds the stamps of both streams in arrival order (each stream in stamp order) with the time of
// arrival on its own clock (wall time live, bag time offline) and consumes the decisions, in order:
//   * kPair:      the left frame and the right frame with |stamp difference| <= tolerance (the closest one);
//   * kLeftOnly:  a left frame without a right partner: a right image later than it arrived first, or none arrived
//                 within max_wait, or the right stream is known to be missing (then it does not wait). It is
//                 tracked with the left image only: a left frame is never dropped.
//   * kDropRight: a right frame no left frame can pair with (older than the oldest waiting left frame by more than
//                 the tolerance, or a closer right frame followed it): dropped and counted.
// Decisions consume each stream from its front, so a caller keeping the messages in two FIFOs pops the left front
// for kPair / kLeftOnly and the right front for kPair / kDropRight.
//
// The right stream is "missing" from the first left-only frame on (one kWarn message naming the stamp) until the
// next pair (one kInfo message with the number of left-only frames): while missing, left frames do not wait; any
// right frame arriving ends the no-wait mode, so the next left frame waits for its partner again.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "iraf_vo/pipeline/tracking_session.h"

namespace iraf_vo {

struct StereoPairingParams {
  double tolerance = 0.005;  // [s] largest |left - right| stamp difference of a pair (0: equal stamps only)
  double max_wait = 0.25;    // [s] how long a left frame waits for its right partner (caller's clock)
  size_t max_pending_right = 20;  // right frames waiting for a left one beyond this are dropped (oldest first)
};

struct StereoCounters {
  long pairs = 0, left_only = 0, dropped_right = 0;
  long missing_events = 0;  // times the right stream went missing
};

class StereoPairing {
 public:
  enum class Kind { kPair, kLeftOnly, kDropRight };
  struct Decision {
    Kind kind = Kind::kPair;
    int64_t left_ns = 0, right_ns = 0;  // the stamps concerned (left_ns unset for kDropRight, right_ns for kLeftOnly)
  };

  explicit StereoPairing(const StereoPairingParams& params = StereoPairingParams());

  /// A left / right frame arrived at `now` [s]; returns the decisions it makes possible (also see poll()).
  std::vector<Decision> addLeft(int64_t stamp_ns, double now);
  std::vector<Decision> addRight(int64_t stamp_ns, double now);
  /// The decisions due by `now` (left frames that waited max_wait). Call it regularly (a timer).
  std::vector<Decision> poll(double now);
  /// End of input: every waiting left frame left-only, every waiting right frame dropped.
  std::vector<Decision> flush();

  /// What to log since the last call: right stream missing / back (kWarn / kInfo).
  std::vector<SessionMessage> takeMessages();
  const StereoCounters& counters() const { return counters_; }
  bool rightMissing() const { return missing_; }
  size_t pendingLeft() const { return left_.size(); }
  size_t pendingRight() const { return right_.size(); }

 private:
  struct Pending {
    int64_t stamp_ns;
    double arrived;
  };
  void decide(double now, bool flushing, std::vector<Decision>* out);
  void emitLeftOnly(std::vector<Decision>* out);
  void emitPair(std::vector<Decision>* out);
  void emitDropRight(std::vector<Decision>* out);

  StereoPairingParams params_;
  int64_t tolerance_ns_;
  std::deque<Pending> left_, right_;
  bool missing_ = false, waiting_ = true;  // waiting_: left frames wait for a right partner
  long left_only_run_ = 0;
  StereoCounters counters_;
  std::vector<SessionMessage> messages_;
};

}  // namespace iraf_vo
