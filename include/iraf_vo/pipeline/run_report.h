// What an offline run (iraf_vo_run) records per frame and reports at the end: per-stage times, the estimated
// trajectory, memory samples, the optional per-frame CSV, the text summary and the JSON stats. ROS-free.
#pragma once

#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "iraf_vo/eval/trajectory_eval.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/pipeline/anchored_trajectory.h"
#include "iraf_vo/pipeline/offline_pipeline.h"
#include "iraf_vo/tracking/tracker.h"

namespace iraf_vo {

struct Percentiles {
  double median = 0, p95 = 0, mean = 0;
};
Percentiles percentiles(std::vector<double> v);

/// Resident set size of this process in MiB (Linux /proc), -1 when unavailable.
double rssMiB();

/// The totals of a finished run.
struct RunTotals {
  std::string dataset, mode;
  TrackerStats stats;
  size_t map_points = 0;
  long processed = 0, read_errors = 0;
  double wall_s = 0, cpu_s = 0;  // cpu_s: all threads of the process
  bool have_ate = false;
  EvalResult ate;
  std::string ate_error;  // when --gt was given but the ATE could not be computed
  bool ate_requested = false;
  bool have_ate_final = false;  // of the trajectory after mapping (KeyframeAnchoredTrajectory)
  EvalResult ate_final;
  bool stereo = false;     // stereo run: the report adds baseline, stereo matches, right-missing frames, SE(3) ATE
  double baseline = 0.0;   // [m]
  bool have_ate_se3 = false;
  EvalResult ate_se3;
  /// After a reset a new map starts at a new scale and in a new frame: with more than one map, each map's poses
  /// aligned on their own (Sim(3)), oldest first (a map with fewer than 3 poses has n_matched 0).
  std::vector<EvalResult> ate_per_map;
};

class RunRecorder {
 public:
  /// Per-frame CSV: index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track,mean,snr,note. false + *error.
  bool openFrameLog(const std::string& path, std::string* error);
  /// One tracked frame (a pose goes into the trajectory when tracking).
  void add(const FrontEndItem& item, const TrackResult& r, long processed);

  const Trajectory& trajectory() const { return trajectory_; }
  /// The stamps of the frames that initialized a map (the first one and one after each reset).
  const std::vector<double>& mapStarts() const { return map_starts_; }
  /// Keep what the trajectory after mapping needs (each frame's keyframe-relative pose); off by default, so a run
  /// without --out-final / --gt holds one pose per frame only.
  void keepFinalTrajectory(bool keep) { keep_final_ = keep; }
  /// Keyframe poses for the trajectory after mapping (call with Tracker::keyframePoses()).
  void updateKeyframes(const std::vector<KeyframePose>& keyframes) {
    if (keep_final_) anchored_.updateKeyframes(keyframes);
  }
  Trajectory finalTrajectory() const { return anchored_.build(); }
  /// "frames N, tracked ..." + per-stage table + RSS + ATE, as iraf_vo_run prints it.
  std::string summary(const RunTotals& t) const;
  /// The stats JSON. false + *error naming the path.
  bool writeJson(const std::string& path, const RunTotals& t, std::string* error) const;

 private:
  double fps(const RunTotals& t) const;
  double cpuMsPerFrame(const RunTotals& t) const;

  std::ofstream frame_log_;
  std::map<std::string, std::vector<double>> ms_;
  std::vector<std::pair<long, double>> rss_;  // (frames processed, MiB)
  Trajectory trajectory_;
  std::vector<double> map_starts_;
  KeyframeAnchoredTrajectory anchored_;
  bool keep_final_ = false;
};

/// The progress line on a terminal ("\r[####....] n/N fps state kps inl") or, without one, a line every 100 frames.
void printProgress(FILE* f, bool tty, long processed, long total, double elapsed_s, const TrackResult& r,
                   size_t keypoints);

}  // namespace iraf_vo
