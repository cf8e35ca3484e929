#include "iraf_vo/pipeline/run_monitor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace iraf_vo {

long StampGapCounter::update(int64_t stamp_ns) {
  long missing = 0;
  if (have_last_ && stamp_ns > last_ns_) {
    const int64_t step = stamp_ns - last_ns_;
    const double p = period();
    if (p > 0.0 && step * 1e-9 > 1.5 * p && step * 1e-9 <= max_gap_)
      missing = std::lround(step * 1e-9 / p) - 1;
    if (step * 1e-9 <= max_gap_) {
      steps_.push_back(step);
      while (static_cast<int>(steps_.size()) > window_) steps_.pop_front();
    }
  }
  if (!have_last_ || stamp_ns > last_ns_) last_ns_ = stamp_ns;
  have_last_ = true;
  missed_ += missing;
  return missing;
}

double StampGapCounter::period() const {
  if (steps_.empty()) return 0.0;
  return *std::min_element(steps_.begin(), steps_.end()) * 1e-9;
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
  return r;
}

std::string calibrationReason(const std::string& camera_file, const std::string& file_error,
                              const std::string& info_topic, const std::string& info_error) {
  if (!camera_file.empty()) return "no calibration: ~camera_file " + camera_file + ": " + file_error;
  if (!info_error.empty()) return "no calibration: invalid camera_info on " + info_topic + ": " + info_error;
  return "no calibration: waiting for camera_info on " + info_topic + " (~camera_file is empty)";
}

}  // namespace iraf_vo
