#include "iraf_vo/pipeline/run_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace iraf_vo {

long StampGapCounter::update(int64_t stamp_ns, long rejected_before) {
  if (!have_last_) {
    last_ns_ = stamp_ns;
    have_last_ = true;
    return 0;
  }
  if (stamp_ns <= last_ns_) {
    // A step back beyond max_gap (bag loop, restarted player): the stream starts again from this stamp. Smaller ones
    // (a late frame, a duplicate) are ignored.
    if ((last_ns_ - stamp_ns) * 1e-9 > max_gap_) last_ns_ = stamp_ns;
    return 0;
  }
  const int64_t step = stamp_ns - last_ns_;
  last_ns_ = stamp_ns;
  if (step * 1e-9 > max_gap_) return 0;  // a pause
  const double p = period();
  long missing = 0;
  if (p > 0.0 && step * 1e-9 > kGapPeriods * p) {
    missing = std::max(0L, std::lround(step * 1e-9 / p) - 1 - std::max(0L, rejected_before));
    long_steps_.push_back(step);
    // `window` long steps in a row: the camera rate changed (not an overload): take the new rate.
    if (static_cast<int>(long_steps_.size()) >= window_) {
      steps_.assign(long_steps_.begin(), long_steps_.end());
      long_steps_.clear();
      missing = 0;
    }
  } else {
    long_steps_.clear();
    steps_.push_back(step);
    while (static_cast<int>(steps_.size()) > window_) steps_.pop_front();
  }
  missed_ += missing;
  return missing;
}

double StampGapCounter::period() const {
  if (steps_.empty()) return 0.0;
  std::vector<int64_t> v(steps_.begin(), steps_.end());
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2] * 1e-9;
}

void RateMeter::tick(double now) {
  times_.push_back(now);
  ++count_;
  while (!times_.empty() && times_.front() < now - window_) times_.pop_front();
}

double RateMeter::rate(double now) const {
  while (!times_.empty() && times_.front() < now - window_) times_.pop_front();
  if (times_.size() < 2) return 0.0;
  const double span = std::max(now - times_.front(), 1e-6);
  return static_cast<double>(times_.size() - 1) / span;
}

bool MessageThrottle::allow(const SessionMessage& m, double now) {
  if (m.level == SessionMessage::Level::kInfo) return true;
  const double period = m.key == "drop" || m.key == "error" ? 5.0 : 1.0;
  auto it = last_.find(m.key);
  if (it != last_.end() && now - it->second < period) return false;
  last_[m.key] = now;
  return true;
}

SessionMessage missedFramesMessage(long missing, int64_t stamp_ns, const StampGapCounter& gaps) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "%ld frame(s) missed before stamp %.3f (%ld in total; camera period %.1f ms): the graph cannot keep up "
                "(queue overflow)",
                missing, stamp_ns * 1e-9, gaps.missed(), gaps.period() * 1e3);
  return {SessionMessage::Level::kWarn, buf, "drop"};
}

std::string trackerStatusLine(TrackingState state, int inliers, const SessionCounters& c, double fps_in,
                              double odom_rate, long missed) {
  char buf[320];
  std::snprintf(buf, sizeof(buf),
                "%s, %d inliers, %d keyframes in map (%ld created), %.1f fps in, %.1f odom/s, dropped %ld, missed %ld, "
                "lost %ld, resets %ld, rejected %ld",
                toString(state), inliers, c.map_keyframes, c.keyframes, fps_in, odom_rate, c.dropped, missed,
                c.lost_events, c.resets, c.rejected);
  return buf;
}

std::string sessionSummary(const SessionCounters& c, long missed) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "summary: %ld frames, %ld tracked (%.1f %%), %ld lost events, %ld resets, %ld time resets, %ld dropped, "
                "%ld missed",
                c.frames, c.tracked, c.frames > 0 ? 100.0 * c.tracked / c.frames : 0.0, c.lost_events, c.resets,
                c.time_resets, c.dropped, missed);
  return buf;
}

void HealthReport::add(const std::string& key, double value) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", value);
  add(key, std::string(buf));
}

HealthReport trackerHealth(const TrackerHealthInput& in) {
  HealthReport r;
  const SessionCounters& c = in.counters;
  if (!in.no_calibration.empty()) {
    r.level = HealthReport::kError;
    r.summary = in.no_calibration;
  } else if (in.state != TrackingState::kTracking) {
    r.level = HealthReport::kWarn;
    r.summary = toString(in.state);
  } else if (in.missed_since_last_report > 0) {
    r.level = HealthReport::kWarn;
    r.summary = "tracking; " + std::to_string(in.missed_since_last_report) + " frames missed (overload)";
  } else if (c.metric_scale_weak) {
    r.level = HealthReport::kWarn;
    char buf[128];
    std::snprintf(buf, sizeof(buf), "tracking; metric scale weakly observed (%.1f close stereo inliers per frame)",
                  c.close_inliers_mean);
    r.summary = buf;
  } else {
    r.summary = "tracking";
  }
  r.add("camera", in.camera);
  r.add("state", std::string(toString(in.state)));
  r.add("input rate [Hz]", in.input_rate);
  r.add("odometry rate [Hz]", in.odometry_rate);
  r.add("frames", c.frames);
  r.add("tracked", c.tracked);
  r.add("dropped frames", c.dropped);
  r.add("missed frames", in.missed);
  r.add("lost events", c.lost_events);
  r.add("resets", c.resets);
  r.add("time resets", c.time_resets);
  r.add("rejected poses", c.rejected);
  r.add("last rejection", in.last_rejection);
  r.add("keyframes in map", static_cast<long>(c.map_keyframes));
  r.add("map points", static_cast<long>(c.map_points));
  if (c.close_inliers_mean >= 0.0) {
    r.add("close stereo inliers per frame", c.close_inliers_mean);
    r.add("frames with a weak metric scale", c.weak_scale_frames);
  }
  return r;
}

std::vector<SessionMessage> TrackerMonitor::onInput(double now, int64_t stamp_ns, long rejected_before) {
  in_rate_.tick(now);
  const long missing = gaps_.update(stamp_ns, rejected_before);
  if (missing <= 0) return {};
  return {missedFramesMessage(missing, stamp_ns, gaps_)};
}

void TrackerMonitor::onStep(const SessionStep& step) {
  if (!step.tracked_frame) return;
  last_state_ = step.result.state;
  if (!step.result.rejected.empty()) last_rejection_ = step.result.rejected;
}

HealthReport TrackerMonitor::health(const std::string& no_calibration, const std::string& camera,
                                    const SessionCounters& c, double now) {
  TrackerHealthInput in;
  in.no_calibration = no_calibration;
  in.camera = camera;
  in.state = last_state_;
  in.counters = c;
  in.input_rate = in_rate_.rate(now);
  in.odometry_rate = odom_rate_.rate(now);
  in.missed = gaps_.missed();
  in.missed_since_last_report = gaps_.missed() - reported_missed_;
  in.last_rejection = last_rejection_;
  reported_missed_ = gaps_.missed();
  return trackerHealth(in);
}

std::string TrackerMonitor::statusLine(const SessionStep& step, double now) const {
  return trackerStatusLine(step.result.state, step.result.inliers, step.counters, in_rate_.rate(now),
                           odom_rate_.rate(now), gaps_.missed());
}

HealthReport inputHealth(const std::string& transport, const std::string& topic, double input_rate,
                         double output_rate, long undecodable, long rejected_size, long missed,
                         const std::string& last_problem) {
  HealthReport r;
  r.level = undecodable + rejected_size > 0 ? HealthReport::kWarn : HealthReport::kOk;
  r.summary = topic.empty() ? "not subscribed (no listener)" : r.level ? "frames rejected: " + last_problem : "ok";
  r.add("transport", transport);
  r.add("topic", topic);
  r.add("input rate [Hz]", input_rate);
  r.add("output rate [Hz]", output_rate);
  r.add("undecodable frames", undecodable);
  r.add("rejected frames (size)", rejected_size);
  r.add("missed frames", missed);
  r.add("last problem", last_problem);
  return r;
}

std::string calibrationReason(const std::string& camera_file, const std::string& file_error,
                              const std::string& info_topic, const std::string& info_error) {
  if (!camera_file.empty()) return "no calibration: ~camera_file " + camera_file + ": " + file_error;
  if (!info_error.empty()) return "no calibration: invalid camera_info on " + info_topic + ": " + info_error;
  return "no calibration: waiting for camera_info on " + info_topic + " (~camera_file is empty)";
}

}  // namespace iraf_vo
