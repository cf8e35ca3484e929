#include "iraf_vo/pipeline/input_watchdog.h"

#include <algorithm>
#include <cstdio>

namespace iraf_vo {

namespace {

const int kWindow = 20;
const double kMinPeriod = 0.04;  // [s] a floor for the expected period (bursts of frames, fast cameras)

std::string fmt(const char* f, double a, double b = 0.0) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), f, a, b);
  return buf;
}

}  // namespace

InputWatchdog::InputWatchdog(std::string what, double dead_after, double late_periods)
    : what_(std::move(what)), dead_after_(dead_after), late_periods_(late_periods) {}

void InputWatchdog::arm(const std::string& topic, double now) {
  topic_ = topic;
  armed_at_ = now;
  have_frame_ = false;
  intervals_.clear();
  state_ = State::kWaiting;
}

void InputWatchdog::disarm() {
  state_ = State::kIdle;
  stamp_period_ = 0.0;
  have_frame_ = false;
  intervals_.clear();
}

double InputWatchdog::period() const {
  if (intervals_.empty() && stamp_period_ <= 0.0) return 0.0;
  double arrival = 0.0;
  if (!intervals_.empty()) {
    std::vector<double> v(intervals_.begin(), intervals_.end());
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    arrival = v[v.size() / 2];
  }
  return std::max({arrival, stamp_period_, kMinPeriod});
}

std::string InputWatchdog::describeSilence(double now) const {
  if (!have_frame_) return "no " + what_ + " on " + topic_ + fmt(" for %.1f s since subscribing", silence(now));
  const double p = period();
  return "no " + what_ + " on " + topic_ + fmt(" for %.2f s", silence(now)) +
         (p > 0.0 ? fmt(" (%.1f periods of %.1f ms)", silence(now) / p, p * 1e3) : "");
}

std::vector<SessionMessage> InputWatchdog::onFrame(double now, double stamp_period) {
  std::vector<SessionMessage> out;
  if (state_ == State::kIdle) return out;
  stamp_period_ = stamp_period;
  if (state_ == State::kLate || state_ == State::kDead || state_ == State::kSilent)
    out.push_back({SessionMessage::Level::kInfo,
                   what_ + "s on " + topic_ + fmt(" again after %.2f s", silence(now)), "input"});
  else if (have_frame_ && now > last_) {  // intervals of a regular stream only (not the gap before a recovery)
    intervals_.push_back(now - last_);
    while (static_cast<int>(intervals_.size()) > kWindow) intervals_.pop_front();
  }
  last_ = now;
  have_frame_ = true;
  state_ = State::kOk;
  return out;
}

std::vector<SessionMessage> InputWatchdog::check(double now) {
  std::vector<SessionMessage> out;
  if (state_ == State::kIdle) return out;
  const double s = silence(now);
  if (!have_frame_) {
    if (state_ == State::kWaiting && s > dead_after_) {
      state_ = State::kSilent;
      out.push_back({SessionMessage::Level::kWarn, describeSilence(now) + ": is the publisher running?", "input"});
    }
    return out;
  }
  if (state_ != State::kDead && s > dead_after_) {
    state_ = State::kDead;
    out.push_back({SessionMessage::Level::kError, describeSilence(now) + ": the publisher stopped", "input"});
  } else if (state_ == State::kOk && period() > 0.0 && s > late_periods_ * period()) {
    state_ = State::kLate;
    out.push_back({SessionMessage::Level::kWarn, describeSilence(now) + ": publisher stopped or stalled?", "input"});
  }
  return out;
}

HealthReport::Level InputWatchdog::level(double now, std::string* summary) const {
  if (state_ == State::kIdle) return HealthReport::kOk;
  const double s = silence(now);
  if (!have_frame_) {
    if (s <= dead_after_) return HealthReport::kOk;
    *summary = describeSilence(now);
    return HealthReport::kWarn;
  }
  if (s > dead_after_) {
    *summary = describeSilence(now) + ": the publisher stopped";
    return HealthReport::kError;
  }
  if (state_ == State::kLate) {
    *summary = describeSilence(now);
    return HealthReport::kWarn;
  }
  return HealthReport::kOk;
}

}  // namespace iraf_vo
