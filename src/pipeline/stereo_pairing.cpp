#include "iraf_vo/pipeline/stereo_pairing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace iraf_vo {

namespace {

std::string seconds(int64_t ns) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f", 1e-9 * static_cast<double>(ns));
  return buf;
}

}  // namespace

StereoPairing::StereoPairing(const StereoPairingParams& params)
    : params_(params), tolerance_ns_(std::llround(std::max(0.0, params.tolerance) * 1e9)) {}

std::vector<StereoPairing::Decision> StereoPairing::addLeft(int64_t stamp_ns, double now) {
  left_.push_back({stamp_ns, now});
  std::vector<Decision> out;
  decide(now, false, &out);
  return out;
}

std::vector<StereoPairing::Decision> StereoPairing::addRight(int64_t stamp_ns, double now) {
  right_.push_back({stamp_ns, now});
  waiting_ = true;  // the right stream is alive: the next left frames wait for their partner again
  std::vector<Decision> out;
  decide(now, false, &out);
  return out;
}

std::vector<StereoPairing::Decision> StereoPairing::poll(double now) {
  std::vector<Decision> out;
  decide(now, false, &out);
  return out;
}

std::vector<StereoPairing::Decision> StereoPairing::flush() {
  std::vector<Decision> out;
  decide(0.0, true, &out);
  return out;
}

std::vector<SessionMessage> StereoPairing::takeMessages() {
  std::vector<SessionMessage> m;
  m.swap(messages_);
  return m;
}

void StereoPairing::decide(double now, bool flushing, std::vector<Decision>* out) {
  for (;;) {
    if (left_.empty()) {
      if (!right_.empty() && (flushing || right_.size() > params_.max_pending_right)) {
        emitDropRight(out);
        continue;
      }
      return;
    }
    const int64_t l = left_.front().stamp_ns;
    if (!right_.empty()) {
      const int64_t r = right_.front().stamp_ns;
      if (r < l - tolerance_ns_) {  // too old for this left frame and for every later one
        emitDropRight(out);
        continue;
      }
      if (std::llabs(r - l) <= tolerance_ns_) {
        if (right_.size() > 1 && std::llabs(right_[1].stamp_ns - l) < std::llabs(r - l)) {
          emitDropRight(out);  // a closer partner followed
          continue;
        }
        emitPair(out);
        continue;
      }
      // The oldest right frame is later than this left one: its partner never came.
      if (!missing_)
        messages_.push_back({SessionMessage::Level::kWarn,
                             "no right image for the left frame at t=" + seconds(l) +
                                 " s (the next right one is at t=" + seconds(r) +
                                 " s): tracking with the left camera only until the right camera is back",
                             "stereo"});
      emitLeftOnly(out);
      continue;
    }
    const bool timed_out = now - left_.front().arrived >= params_.max_wait;
    if (!flushing && waiting_ && !timed_out) return;
    if (!missing_) {
      char why[96];
      std::snprintf(why, sizeof(why), flushing ? "the right stream ended" : "none within %.2f s", params_.max_wait);
      messages_.push_back({SessionMessage::Level::kWarn,
                           "no right image for the left frame at t=" + seconds(l) + " s (" + why +
                               "): tracking with the left camera only until the right camera is back",
                           "stereo"});
    }
    if (timed_out) waiting_ = false;  // silent right stream: the next left frames do not wait
    emitLeftOnly(out);
  }
}

void StereoPairing::emitLeftOnly(std::vector<Decision>* out) {
  Decision d;
  d.kind = Kind::kLeftOnly;
  d.left_ns = left_.front().stamp_ns;
  left_.pop_front();
  if (!missing_) ++counters_.missing_events;
  missing_ = true;
  ++left_only_run_;
  ++counters_.left_only;
  out->push_back(d);
}

void StereoPairing::emitPair(std::vector<Decision>* out) {
  Decision d;
  d.kind = Kind::kPair;
  d.left_ns = left_.front().stamp_ns;
  d.right_ns = right_.front().stamp_ns;
  left_.pop_front();
  right_.pop_front();
  if (missing_)
    messages_.push_back({SessionMessage::Level::kInfo,
                         "right camera back at t=" + seconds(d.left_ns) + " s after " +
                             std::to_string(left_only_run_) + " left-only frame(s): tracking with both cameras",
                         "stereo"});
  missing_ = false;
  left_only_run_ = 0;
  ++counters_.pairs;
  out->push_back(d);
}

void StereoPairing::emitDropRight(std::vector<Decision>* out) {
  Decision d;
  d.kind = Kind::kDropRight;
  d.right_ns = right_.front().stamp_ns;
  right_.pop_front();
  ++counters_.dropped_right;
  out->push_back(d);
}

}  // namespace iraf_vo
