#include "iraf_vo/pipeline/run_report.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace iraf_vo {

Percentiles percentiles(std::vector<double> v) {
  Percentiles p;
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  p.median = v[v.size() / 2];
  p.p95 = v[std::min(v.size() - 1, static_cast<size_t>(0.95 * v.size()))];
  double s = 0;
  for (double x : v) s += x;
  p.mean = s / v.size();
  return p;
}

// The frame log's last column: why the frame is too dark, why the health monitor rejected the pose, why
// initialization failed, after how many frames it relocalized after darkness, or that a stereo map's metric scale
// became weakly observed / observed again (no commas).
static std::string csvNote(const TrackResult& r) {
  std::string s = !r.too_dark.empty()  ? r.too_dark
                  : !r.rejected.empty() ? r.rejected
                  : r.relocalized_after_frames > 0
                      ? "relocalized after darkness at the frame " + std::to_string(r.relocalized_after_frames) +
                            " with signal"
                  : r.metric_scale_changed
                      ? (r.metric_scale_weak ? "metric scale weakly observed" : "metric scale observed again")
                      : r.init_status;
  std::replace(s.begin(), s.end(), ',', ';');
  return s;
}

double rssMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return -1.0;
}

bool RunRecorder::openFrameLog(const std::string& path, std::string* error) {
  frame_log_.open(path);
  if (!frame_log_) {
    *error = path + ": cannot write";
    return false;
  }
  frame_log_ << "index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track,mean,snr,note\n";
  return true;
}

void RunRecorder::add(const FrontEndItem& it, const TrackResult& r, long processed) {
  if (frame_log_)
    frame_log_ << it.index << "," << std::fixed << it.frame.stamp << std::defaultfloat << "," << toString(r.state)
               << "," << it.frame.keypoints.size() << "," << r.matches << "," << r.inliers << "," << r.is_keyframe
               << "," << r.used_pnp << "," << r.timing.ms_total << "," << it.frame.signal.mean << ","
               << it.frame.signal.snr << "," << csvNote(r) << "\n";
  if (r.initialized_now) map_starts_.push_back(it.frame.stamp);
  ms_["read"].push_back(it.ms_read);
  ms_["enhance"].push_back(it.ms_enhance);
  ms_["features"].push_back(it.ms_features);
  ms_["track"].push_back(r.timing.ms_total);
  ms_["track_match"].push_back(r.timing.ms_match);
  ms_["track_pose"].push_back(r.timing.ms_pose);
  ms_["track_keyframe"].push_back(r.timing.ms_keyframe);
  if (r.timing.ms_init > 0) ms_["track_init"].push_back(r.timing.ms_init);
  if (r.state == TrackingState::kTracking) trajectory_.push_back(it.frame.stamp, r.T_w_c);
  if (keep_final_) anchored_.addFrame(it.frame.stamp, r);
  if (processed % 500 == 0) rss_.emplace_back(processed, rssMiB());
}

double RunRecorder::fps(const RunTotals& t) const { return t.processed / std::max(t.wall_s, 1e-9); }
double RunRecorder::cpuMsPerFrame(const RunTotals& t) const {
  return 1000.0 * t.cpu_s / std::max<long>(1, t.processed);
}

std::string RunRecorder::summary(const RunTotals& t) const {
  const TrackerStats& st = t.stats;
  const double tracked_pct = st.frames > 0 ? 100.0 * st.tracked / st.frames : 0.0;
  std::ostringstream s;
  s << "frames " << st.frames << ", tracked " << st.tracked << " (" << tracked_pct << " %), lost frames "
    << st.lost_frames << ", lost events " << st.lost_events << ", resets " << st.resets << ", keyframes "
    << st.keyframes << ", map points " << t.map_points << ", BA runs " << st.ba_runs << " (mean "
    << (st.ba_runs ? st.ba_ms_total / st.ba_runs : 0.0) << " ms), BA CPU "
    << (st.ba_runs ? st.ba_cpu_ms_total / st.ba_runs : 0.0) << " ms per run\n";
  if (st.dark_frames > 0 || st.relocalizations > 0)
    s << "too dark: " << st.dark_frames << " frames in " << st.dark_events
      << " runs (lost, no pose, map kept); relocalized in the same map " << st.relocalizations
      << " times, at most " << st.frames_to_relocalize_max << " frames after the light returned\n";
  if (t.stereo)
    s << "stereo: baseline " << t.baseline << " m, left-right matched frames " << st.stereo_matched_frames
      << " (initialization and keyframes), matches per matched frame "
      << (st.stereo_matched_frames > 0 ? static_cast<double>(st.stereo_matches_total) / st.stereo_matched_frames : 0.0)
      << ", frames without a right image " << st.right_missing_frames << " (" << st.right_missing_events << " runs)"
      << ", frames with a weakly observed metric scale " << st.weak_scale_frames << " (" << st.weak_scale_events
      << " runs)\n";
  s << "wall " << t.wall_s << " s, " << fps(t)
    << " fps (reader, front-end, tracking and mapping threads in parallel); CPU " << t.cpu_s
    << " s = " << cpuMsPerFrame(t) << " ms/frame (all threads) -> <= " << 2000.0 / cpuMsPerFrame(t)
    << " fps on 2 idle cores\n";
  s << "per stage [ms] median / 95% / mean:\n";
  for (const auto& kv : ms_) {
    const Percentiles p = percentiles(kv.second);
    char buf[160];
    std::snprintf(buf, sizeof(buf), "  %-15s %7.2f %7.2f %7.2f\n", kv.first.c_str(), p.median, p.p95, p.mean);
    s << buf;
  }
  if (!rss_.empty()) {
    s << "RSS [MiB] after frames:";
    for (const auto& x : rss_) s << " " << x.first << ": " << x.second;
    s << "\n";
  }
  if (t.have_ate)
    s << "ATE (Sim3) RMSE " << t.ate.ate.rmse << " m, median " << t.ate.ate.median << " m, max " << t.ate.ate.max
      << " m over " << t.ate.n_matched << " poses (scale " << t.ate.scale << ", GT path " << t.ate.gt_length << " m)\n";
  for (size_t k = 0; k < t.ate_per_map.size(); ++k) {
    const EvalResult& m = t.ate_per_map[k];
    if (k == 0) s << "ATE per map (a reset starts a new map at a new scale; each aligned on its own):";
    s << (k ? "," : "") << " map " << k + 1 << ": ";
    if (m.n_matched > 0) s << m.ate.rmse << " m over " << m.n_matched << " poses (scale " << m.scale << ")";
    else s << "too few poses";
    if (k + 1 == t.ate_per_map.size()) s << "\n";
  }
  if (t.have_ate_se3)
    s << "ATE (SE3) RMSE " << t.ate_se3.ate.rmse << " m, median " << t.ate_se3.ate.median << " m, max "
      << t.ate_se3.ate.max << " m\n";
  if (t.have_ate && t.have_ate_final)
    s << "ATE after mapping (poses re-attached to their BA-refined keyframes, --out-final): RMSE "
      << t.ate_final.ate.rmse << " m, median " << t.ate_final.ate.median << " m\n";
  else if (t.ate_requested)
    s << "ATE: not computed: " << t.ate_error << "\n";
  return s.str();
}

bool RunRecorder::writeJson(const std::string& path, const RunTotals& t, std::string* error) const {
  std::ofstream js(path);
  if (!js) {
    *error = path + ": cannot write";
    return false;
  }
  const TrackerStats& st = t.stats;
  const double tracked_pct = st.frames > 0 ? 100.0 * st.tracked / st.frames : 0.0;
  js << "{\n  \"dataset\": \"" << t.dataset << "\",\n  \"mode\": \"" << t.mode << "\",\n  \"frames\": " << st.frames
     << ",\n  \"tracked\": " << st.tracked << ",\n  \"tracked_pct\": " << tracked_pct
     << ",\n  \"lost_frames\": " << st.lost_frames << ",\n  \"lost_events\": " << st.lost_events
     << ",\n  \"resets\": " << st.resets << ",\n  \"dark_frames\": " << st.dark_frames
     << ",\n  \"dark_events\": " << st.dark_events << ",\n  \"relocalizations\": " << st.relocalizations
     << ",\n  \"frames_to_relocalize_max\": " << st.frames_to_relocalize_max << ",\n  \"keyframes\": " << st.keyframes
     << ",\n  \"map_points\": " << t.map_points << ",\n  \"read_errors\": " << t.read_errors
     << ",\n  \"fps\": " << fps(t) << ",\n  \"cpu_ms_per_frame\": " << cpuMsPerFrame(t) << ",\n  \"ba_runs\": " << st.ba_runs
     << ",\n  \"ba_cpu_ms_per_run\": " << (st.ba_runs ? st.ba_cpu_ms_total / st.ba_runs : 0.0) << ",\n  \"ms\": {";
  bool first = true;
  for (const auto& kv : ms_) {
    const Percentiles p = percentiles(kv.second);
    js << (first ? "\n" : ",\n") << "    \"" << kv.first << "\": {\"median\": " << p.median << ", \"p95\": " << p.p95
       << ", \"mean\": " << p.mean << "}";
    first = false;
  }
  js << "\n  },\n  \"rss_mib\": {";
  for (size_t k = 0; k < rss_.size(); ++k) js << (k ? ", " : "") << "\"" << rss_[k].first << "\": " << rss_[k].second;
  js << "}";
  if (t.have_ate)
    js << ",\n  \"ate_rmse\": " << t.ate.ate.rmse << ",\n  \"ate_median\": " << t.ate.ate.median
       << ",\n  \"ate_scale\": " << t.ate.scale << ",\n  \"ate_matched\": " << t.ate.n_matched;
  if (t.have_ate_final) js << ",\n  \"ate_final_rmse\": " << t.ate_final.ate.rmse;
  if (!t.ate_per_map.empty()) {
    js << ",\n  \"ate_per_map_rmse\": [";
    for (size_t k = 0; k < t.ate_per_map.size(); ++k) js << (k ? ", " : "") << t.ate_per_map[k].ate.rmse;
    js << "],\n  \"ate_per_map_poses\": [";
    for (size_t k = 0; k < t.ate_per_map.size(); ++k) js << (k ? ", " : "") << t.ate_per_map[k].n_matched;
    js << "]";
  }
  if (t.stereo)
    js << ",\n  \"stereo\": true,\n  \"baseline\": " << t.baseline << ",\n  \"stereo_matches_total\": "
       << st.stereo_matches_total << ",\n  \"stereo_matched_frames\": " << st.stereo_matched_frames
       << ",\n  \"right_missing_frames\": " << st.right_missing_frames
       << ",\n  \"right_missing_events\": " << st.right_missing_events
       << ",\n  \"weak_scale_frames\": " << st.weak_scale_frames << ",\n  \"weak_scale_events\": " << st.weak_scale_events;
  if (t.have_ate_se3) js << ",\n  \"ate_se3_rmse\": " << t.ate_se3.ate.rmse;
  js << "\n}\n";
  return true;
}

void printProgress(FILE* f, bool tty, long processed, long total, double elapsed_s, const TrackResult& r,
                   size_t keypoints) {
  const double fps = processed / std::max(elapsed_s, 1e-9);
  if (tty) {
    const int width = 30;
    const int filled = total > 0 ? static_cast<int>(width * processed / total) : 0;
    std::fprintf(f, "\r[%s%s] %ld/%ld %5.1f fps %-15s kps %4zu inl %4d", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), processed, total, fps, toString(r.state), keypoints,
                 r.inliers);
    std::fflush(f);
  } else if (processed % 100 == 0) {
    std::fprintf(f, "iraf_vo_run: %ld/%ld frames, %.1f fps, %s\n", processed, total, fps, toString(r.state));
  }
}

}  // namespace iraf_vo
