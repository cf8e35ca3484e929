// What a live stage reports about its input stream (ROS-free; used by the enhance and tracker nodelets for the
// console, tracking_status and /diagnostics).
//
// Frames lost under overload never reach a callback (a subscriber queue overflows), so they are inferred from the
// stamps: the nominal period is the MEDIAN of the last `window` regular stamp steps (robust to stamp jitter: a 20 Hz
// stream with +-8 ms jitter has steps of 34-66 ms), and a step of more than kGapPeriods (1.6) periods means
// round(step / period) - 1 frames are missing, less the frames the graph itself rejected in between (the caller
// says how many: they arrived, they are not "missed"). Long steps do not enter the period estimate, unless `window`
// of them come in a row (the camera rate changed). Steps longer than max_gap seconds (a paused bag) are not counted;
// a step back of more than max_gap (a time jump: bag loop) restarts the count from that stamp, smaller steps back
// (late frames) are ignored.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "iraf_vo/pipeline/tracking_session.h"

namespace iraf_vo {

class StampGapCounter {
 public:
  explicit StampGapCounter(int window = 50, double max_gap = 2.0) : window_(window), max_gap_(max_gap) {}
  static constexpr double kGapPeriods = 1.6;
  /// One received frame; returns how many frames are missing right before it. rejected_before: frames rejected by
  /// the graph itself since the previous received one (they are not missing).
  long update(int64_t stamp_ns, long rejected_before = 0);
  long missed() const { return missed_; }
  /// Nominal period [s] (0 until two frames were seen).
  double period() const;

 private:
  int window_;
  double max_gap_;
  int64_t last_ns_ = 0;
  bool have_last_ = false;
  std::deque<int64_t> steps_;       // regular steps (period estimate)
  std::deque<int64_t> long_steps_;  // consecutive long steps (gaps) since the last regular one
  long missed_ = 0;
};

/// Events per second over the last `window` seconds of a caller-supplied clock (wall time in the nodelets).
class RateMeter {
 public:
  explicit RateMeter(double window = 5.0) : window_(window) {}
  void tick(double now);
  double rate(double now) const;
  long count() const { return count_; }

 private:
  double window_;
  mutable std::deque<double> times_;
  long count_ = 0;
};

/// Console throttling per kind of SessionMessage (its key): info always, "drop" / "error" once per 5 s, other
/// warnings (lost, rejected, reinit, reset, time_jump, restart) once per second each.
class MessageThrottle {
 public:
  bool allow(const SessionMessage& m, double now);

 private:
  std::map<std::string, double> last_;
};

/// The warning for frames missing before `stamp_ns` (StampGapCounter), key "drop".
SessionMessage missedFramesMessage(long missing, int64_t stamp_ns, const StampGapCounter& gaps);

/// The throttled one-line console status of the tracker, e.g.
/// "TRACKING, 143 inliers, 9 keyframes in map (41 created), 19.9 fps in, 19.8 odom/s, dropped 0, missed 3,
///  lost 1, resets 0, rejected 0".
std::string trackerStatusLine(TrackingState state, int inliers, const SessionCounters& c, double fps_in,
                              double odom_rate, long missed);

/// The tracker's shutdown summary, e.g. "summary: 866 frames, 850 tracked (98.2 %), 1 lost events, 0 resets, 0 time
/// resets, 2 dropped, 0 missed".
std::string sessionSummary(const SessionCounters& c, long missed);

/// A /diagnostics entry, ROS-free (the nodelets copy it into a diagnostic_updater::DiagnosticStatusWrapper).
struct HealthReport {
  enum Level { kOk = 0, kWarn = 1, kError = 2 };
  Level level = kOk;
  std::string summary;
  std::vector<std::pair<std::string, std::string>> values;
  void add(const std::string& key, const std::string& value) { values.emplace_back(key, value); }
  void add(const std::string& key, double value);
  void add(const std::string& key, long value) { add(key, std::to_string(value)); }
};

struct TrackerHealthInput {
  std::string no_calibration;  // CameraSource::reason(): "" when calibrated
  std::string camera;          // CameraModel::describe()
  TrackingState state = TrackingState::kNotInitialized;
  SessionCounters counters;
  double input_rate = 0.0, odometry_rate = 0.0;
  long missed = 0, missed_since_last_report = 0;
  std::string last_rejection;
};
/// ERROR without calibration, WARN when not TRACKING, when frames were missed since the last report or when a stereo
/// map's metric scale is weakly observed (SessionCounters::metric_scale_weak), else OK.
HealthReport trackerHealth(const TrackerHealthInput& in);

/// Everything the tracker nodelet reports about its run besides the session counters: input / odometry rates,
/// missed frames, the last state and rejection, console throttling. Not thread-safe (the nodelet's mutex).
class TrackerMonitor {
 public:
  /// A Features message arrived (before the session): the warning to log when frames are missing before it.
  /// rejected_before: frames the graph rejected since the previous message (Features.rejected_before).
  std::vector<SessionMessage> onInput(double now, int64_t stamp_ns, long rejected_before = 0);
  /// The session processed a frame.
  void onStep(const SessionStep& step);
  void onOdometry(double now) { odom_rate_.tick(now); }
  bool allow(const SessionMessage& m, double now) { return throttle_.allow(m, now); }
  long missed() const { return gaps_.missed(); }
  /// Nominal input period from the stamps [s] (0 until known).
  double period() const { return gaps_.period(); }
  /// For /diagnostics (each call starts a new "missed since the last report" interval).
  HealthReport health(const std::string& no_calibration, const std::string& camera, const SessionCounters& c,
                      double now);
  std::string statusLine(const SessionStep& step, double now) const;

 private:
  StampGapCounter gaps_;
  RateMeter in_rate_, odom_rate_;
  MessageThrottle throttle_;
  long reported_missed_ = 0;
  TrackingState last_state_ = TrackingState::kNotInitialized;
  std::string last_rejection_;
};

/// The input of the first nodelet (enhance): WARN when frames were rejected (size) or undecodable, else OK.
HealthReport inputHealth(const std::string& transport, const std::string& topic, double input_rate,
                         double output_rate, long undecodable, long rejected_size, long missed,
                         const std::string& last_problem);

/// Why the tracker has no calibration yet (published in tracking_status.reason at 1 Hz until it has one).
/// camera_file: ~camera_file ("" = camera_info mode); file_error: its load error; info_topic: the resolved
/// camera_info topic; info_error: the last invalid camera_info ("" if none arrived or it was valid).
std::string calibrationReason(const std::string& camera_file, const std::string& file_error,
                              const std::string& info_topic, const std::string& info_error);

}  // namespace iraf_vo
