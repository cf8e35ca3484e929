// iraf_vo_run --dataset DIR_OR_BAG [--topic T] [--camera sensor.yaml] --out traj.txt
//             [--mode iraf|baseline|enhance|adaptive|culling|he|clahe] [--gt GT] [--stats stats.json] [--config params.yaml]
//             [--first N] [--frames N] [--set tracker.key=value ...] [--quiet]
// Offline monocular VO (no roscore): front-end (enhance + features) and back-end (tracking; BA on its own thread)
// run on separate threads connected by a bounded queue. Writes the TUM trajectory of every tracked frame and a
// summary (frames, tracked %, lost events, map points, per-stage median / 95 % ms, ATE when --gt).
#include <atomic>
#include <iraf_vo/camera/camera_loader.h>
#include <iraf_vo/enhance/enhance_params_io.h>
#include <iraf_vo/enhance/enhancer.h>
#include <iraf_vo/eval/trajectory_eval.h>
#include <iraf_vo/features/feature_extractor.h>
#include <iraf_vo/features/feature_params.h>
#include <iraf_vo/io/image_folder.h>
#include <iraf_vo/io/trajectory.h>
#include <iraf_vo/ros/bag_reader.h>
#include <iraf_vo/tracking/tracker.h>
#include <iraf_vo/tracking/tracker_params_io.h>

#include <ros/time.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/stat.h>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

void usage(FILE* f) {
  std::fprintf(f,
               "usage: iraf_vo_run --dataset DIR_OR_BAG [--topic T] [--camera sensor.yaml] --out traj.txt\n"
               "                   [--mode iraf|baseline|enhance|adaptive|culling|he|clahe] [--gt GT] [--stats stats.json]\n"
               "                   [--config params.yaml] [--first N] [--frames N] [--set section.key=value] [--frame-log F] [--quiet]\n"
               "  --dataset  ASL folder (DIR/mav0/cam0/data.csv) or a rosbag (.bag, needs --topic)\n"
               "  --camera   camera yaml (default: the ASL folder's mav0/cam0/sensor.yaml)\n"
               "  --mode     iraf = enhancement + adaptive threshold + culling (default); baseline = all off;\n"
               "             enhance / adaptive / culling = that module alone; he / clahe = global histogram\n"
               "             equalization / CLAHE (clip 3.0, 8x8 tiles) + the baseline features (paper Table I)\n"
               "  --gt       ground truth (TUM or EuRoC csv) -> Sim(3) ATE in the summary\n"
               "  --config   YAML with optional maps 'enhance:', 'features:', 'tracker:' (keys = parameter names)\n"
               "  --first/--frames  process frames [first, first + frames) only\n"
               "  --frame-log per-frame CSV: index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track\n"
               "  --set      override one parameter, e.g. --set tracker.ba_window_size=12 (after --mode / --config)\n");
}

bool parseLong(const std::string& s, long* v) {
  char* end = nullptr;
  *v = std::strtol(s.c_str(), &end, 10);
  return !s.empty() && end && *end == '\0';
}

struct Percentiles {
  double median = 0, p95 = 0, mean = 0;
};
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

struct FrontItem {
  long index = 0;
  iraf_vo::FeatureFrame frame;
  double ms_read = 0, ms_enhance = 0, ms_features = 0;
  bool end = false;
  bool error = false;
  bool fatal = false;  // stops the run with a non-zero exit (e.g. image size != camera size)
  std::string message;
};

// Bounded single-producer / single-consumer queue.
template <typename Item>
class BoundedQueue {
 public:
  explicit BoundedQueue(size_t cap) : cap_(cap) {}
  void push(Item&& it) {
    std::unique_lock<std::mutex> lk(m_);
    not_full_.wait(lk, [&] { return q_.size() < cap_ || closed_; });
    if (closed_) return;
    q_.push_back(std::move(it));
    not_empty_.notify_one();
  }
  bool pop(Item* it) {  // false once closed and empty
    std::unique_lock<std::mutex> lk(m_);
    not_empty_.wait(lk, [&] { return !q_.empty() || closed_; });
    if (q_.empty()) return false;
    *it = std::move(q_.front());
    q_.pop_front();
    not_full_.notify_one();
    return true;
  }
  void close() {
    std::lock_guard<std::mutex> lk(m_);
    closed_ = true;
    not_full_.notify_all();
    not_empty_.notify_all();
  }

 private:
  size_t cap_;
  bool closed_ = false;
  std::deque<Item> q_;
  std::mutex m_;
  std::condition_variable not_full_, not_empty_;
};

// Resident set size of this process in MiB (Linux /proc), -1 when unavailable.
double rssMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;
  return -1.0;
}

bool isDirectory(const std::string& p) {
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

}  // namespace

int main(int argc, char** argv) {
  std::string frame_log_path;
  std::string dataset, topic, camera_path, out, mode = "iraf", gt_path, stats_path, config_path;
  long first = 0, max_frames = -1;
  bool quiet = false;
  std::vector<std::string> sets;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "iraf_vo_run: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--dataset") {
      dataset = value();
    } else if (a == "--topic") {
      topic = value();
    } else if (a == "--camera") {
      camera_path = value();
    } else if (a == "--out") {
      out = value();
    } else if (a == "--mode") {
      mode = value();
    } else if (a == "--gt") {
      gt_path = value();
    } else if (a == "--stats") {
      stats_path = value();
    } else if (a == "--config") {
      config_path = value();
    } else if (a == "--set") {
      sets.push_back(value());
    } else if (a == "--frame-log") {
      frame_log_path = value();
    } else if (a == "--quiet") {
      quiet = true;
    } else if (a == "--first" || a == "--frames") {
      const std::string v = value();
      long x;
      if (!parseLong(v, &x) || x < 0) {
        std::fprintf(stderr, "iraf_vo_run: %s '%s': expected an integer >= 0\n", a.c_str(), v.c_str());
        return 2;
      }
      (a == "--first" ? first : max_frames) = x;
    } else {
      std::fprintf(stderr, "iraf_vo_run: unknown argument '%s'\n", a.c_str());
      usage(stderr);
      return 2;
    }
  }
  if (dataset.empty() || out.empty()) {
    std::fprintf(stderr, "iraf_vo_run: --dataset and --out are required\n");
    usage(stderr);
    return 2;
  }

  // ---- parameters: defaults -> mode -> config -> --set ----
  iraf_vo::EnhanceParams ep;
  iraf_vo::FeatureParams fp;
  iraf_vo::TrackerParams tp;
  if (mode == "iraf") {
    ep.method = iraf_vo::EnhanceMethod::kIraf;
    fp.adaptive_threshold = true;
    fp.culling = true;
  } else if (mode == "baseline") {
    ep.method = iraf_vo::EnhanceMethod::kNone;
    fp.adaptive_threshold = false;
    fp.culling = false;
  } else if (mode == "enhance") {
    ep.method = iraf_vo::EnhanceMethod::kIraf;
    fp.adaptive_threshold = false;
    fp.culling = false;
  } else if (mode == "adaptive") {
    ep.method = iraf_vo::EnhanceMethod::kNone;
    fp.adaptive_threshold = true;
    fp.culling = false;
  } else if (mode == "culling") {
    ep.method = iraf_vo::EnhanceMethod::kNone;
    fp.adaptive_threshold = false;
    fp.culling = true;
  } else if (mode == "he" || mode == "clahe") {
    // Comparison front-ends of the paper's Table I: HE / CLAHE preprocessing + fixed ORB-SLAM FAST thresholds.
    ep.method = mode == "he" ? iraf_vo::EnhanceMethod::kHe : iraf_vo::EnhanceMethod::kClahe;
    fp.adaptive_threshold = false;
    fp.culling = false;
  } else {
    std::fprintf(stderr, "iraf_vo_run: --mode '%s': expected iraf, baseline, enhance, adaptive, culling, he or clahe\n",
                 mode.c_str());
    return 2;
  }
  if (!config_path.empty()) {
    YAML::Node root;
    try {
      root = YAML::LoadFile(config_path);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "iraf_vo_run: --config %s: %s\n", config_path.c_str(), e.what());
      return 2;
    }
    std::string err;
    if (root["enhance"] && !iraf_vo::loadEnhanceParams(root["enhance"], &ep, &err)) {
      std::fprintf(stderr, "iraf_vo_run: %s: enhance: %s\n", config_path.c_str(), err.c_str());
      return 2;
    }
    if (root["features"] && !iraf_vo::loadFeatureParams(root["features"], &fp, &err)) {
      std::fprintf(stderr, "iraf_vo_run: %s: features: %s\n", config_path.c_str(), err.c_str());
      return 2;
    }
    if (root["tracker"] && !iraf_vo::loadTrackerParams(root["tracker"], &tp, &err)) {
      std::fprintf(stderr, "iraf_vo_run: %s: tracker: %s\n", config_path.c_str(), err.c_str());
      return 2;
    }
  }
  for (const std::string& s : sets) {
    const size_t dot = s.find('.'), eq = s.find('=');
    if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
      std::fprintf(stderr, "iraf_vo_run: --set '%s': expected section.key=value\n", s.c_str());
      return 2;
    }
    const std::string sec = s.substr(0, dot), key = s.substr(dot + 1, eq - dot - 1), val = s.substr(eq + 1);
    std::string err;
    bool ok = false;
    if (sec == "tracker") {
      ok = iraf_vo::setTrackerParam(&tp, key, val, &err);
    } else if (sec == "enhance") {
      ok = iraf_vo::setEnhanceParam(&ep, key, val, &err);
    } else if (sec == "features") {
      YAML::Node n;
      n[key] = YAML::Load(val);
      ok = iraf_vo::loadFeatureParams(n, &fp, &err);
    } else {
      err = "unknown section '" + sec + "' (tracker, enhance, features)";
    }
    if (!ok) {
      std::fprintf(stderr, "iraf_vo_run: --set '%s': %s\n", s.c_str(), err.c_str());
      return 2;
    }
  }
  tp.scale_factor = fp.scale_factor;  // one pyramid for features and tracking
  for (const std::string& e : {iraf_vo::validate(ep), iraf_vo::validate(fp), iraf_vo::validate(tp)})
    if (!e.empty()) {
      std::fprintf(stderr, "iraf_vo_run: %s\n", e.c_str());
      return 2;
    }

  // ---- input ----
  struct stat ds;
  if (stat(dataset.c_str(), &ds) != 0) {
    std::fprintf(stderr, "iraf_vo_run: --dataset %s: no such file or folder\n", dataset.c_str());
    return 1;
  }
  const bool is_bag = !isDirectory(dataset);
  iraf_vo::AslImageReader asl;
  iraf_vo::BagImageReader bag;
  std::string err;
  size_t total = 0;
  if (!is_bag) {
    if (!asl.open(dataset, &err)) {
      std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", dataset.c_str(), err.c_str());
      return 1;
    }
    total = asl.size();
    for (const std::string& w : asl.warnings()) std::fprintf(stderr, "iraf_vo_run: %s\n", w.c_str());
    if (camera_path.empty()) camera_path = asl.sensorYamlPath();
  } else {
    if (topic.empty()) {
      std::fprintf(stderr, "iraf_vo_run: --dataset %s is not a folder: a bag needs --topic\n", dataset.c_str());
      return 2;
    }
    if (!bag.open(dataset, topic, &err)) {
      std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", dataset.c_str(), err.c_str());
      return 1;
    }
    total = bag.size();
    if (!bag.notice().empty()) std::fprintf(stderr, "iraf_vo_run: %s\n", bag.notice().c_str());
  }
  if (camera_path.empty()) {
    std::fprintf(stderr, "iraf_vo_run: no camera: pass --camera sensor.yaml\n");
    return 2;
  }
  iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(camera_path, &err);
  if (!cam) {
    std::fprintf(stderr, "iraf_vo_run: --camera %s: %s\n", camera_path.c_str(), err.c_str());
    return 1;
  }
  iraf_vo::Trajectory gt;
  if (!gt_path.empty() && !iraf_vo::readTrajectory(gt_path, &gt, &err, cam->T_BS)) {
    std::fprintf(stderr, "iraf_vo_run: --gt %s: %s\n", gt_path.c_str(), err.c_str());
    return 1;
  }
  const long last = max_frames >= 0 ? std::min<long>(total, first + max_frames) : static_cast<long>(total);
  const long n_run = std::max<long>(0, last - first);

  // ---- reader thread (image decoding) -> front-end thread (enhance + features) -> tracking (this thread) ----
  struct ReadItem {
    long index = 0;
    double stamp = 0;
    cv::Mat gray;
    double ms_read = 0;
    bool end = false, error = false, fatal = false;
    std::string message;
  };
  BoundedQueue<ReadItem> read_queue(4);
  std::atomic<bool> stop_threads{false};  // set when tracking stops early (fatal input error)
  BoundedQueue<FrontItem> queue(4);
  std::thread reader([&] {
    long idx = 0;
    for (;;) {
      if (stop_threads) return;
      ReadItem it;
      const auto t0 = Clock::now();
      bool have = false;
      if (!is_bag) {
        if (idx < first) idx = first;
        if (idx < last) {
          std::string e;
          if (!asl.loadImage(static_cast<size_t>(idx), &it.gray, &e)) {
            it.error = true;
            it.message = e;
          }
          it.stamp = asl.entries()[idx].stamp();
          have = true;
        }
      } else {
        ros::Time t;
        while (idx < first && bag.next(&t, &it.gray)) ++idx;
        if (idx < last && bag.next(&t, &it.gray)) {
          it.stamp = t.toSec();
          have = true;
        }
      }
      if (!have) {
        it.end = true;
        read_queue.push(std::move(it));
        return;
      }
      if (!it.error && (it.gray.cols != cam->width() || it.gray.rows != cam->height())) {
        // Tracking with the wrong intrinsics would give silent garbage: stop with an error naming both files.
        it.error = it.fatal = true;
        it.message = (is_bag ? dataset + " (topic " + topic + ")" : asl.entries()[idx].path) + ": image " +
                     std::to_string(it.gray.cols) + "x" + std::to_string(it.gray.rows) + " does not match the camera " +
                     camera_path + " (" + std::to_string(cam->width()) + "x" + std::to_string(cam->height()) + ")";
      }
      it.index = idx++;
      it.ms_read = msSince(t0);
      read_queue.push(std::move(it));
    }
  });
  std::thread front([&] {
    iraf_vo::Enhancer enhancer;
    iraf_vo::FeatureExtractor extractor;
    for (;;) {
      ReadItem in;
      if (!read_queue.pop(&in)) return;  // closed and drained (early stop)
      FrontItem it;
      if (in.end) {
        it.end = true;
        queue.push(std::move(it));
        return;
      }
      it.index = in.index;
      it.ms_read = in.ms_read;
      it.error = in.error;
      it.fatal = in.fatal;
      it.message = in.message;
      if (!it.error) {
        try {
          auto t0 = Clock::now();
          const iraf_vo::EnhanceResult er = enhancer.enhance(in.gray, ep);
          it.ms_enhance = msSince(t0);
          t0 = Clock::now();
          it.frame = extractor.extract(er.image, in.stamp, fp);
          it.ms_features = msSince(t0);
        } catch (const std::exception& e) {
          it.error = true;
          it.message = e.what();
        }
      }
      it.frame.stamp = in.stamp;
      queue.push(std::move(it));
    }
  });

  std::ofstream frame_log;
  if (!frame_log_path.empty()) {
    frame_log.open(frame_log_path);
    if (!frame_log) {
      std::fprintf(stderr, "iraf_vo_run: --frame-log %s: cannot write\n", frame_log_path.c_str());
      return 1;
    }
    frame_log << "index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track\n";
  }
  // ---- back-end: tracking ----
  iraf_vo::Tracker tracker(cam, tp);
  iraf_vo::Trajectory est;
  std::map<std::string, std::vector<double>> ms;
  const bool tty = isatty(fileno(stderr)) && !quiet;
  const auto t_start = Clock::now();
  long processed = 0, errors = 0;
  bool fatal = false;
  std::vector<std::pair<long, double>> rss;  // (frames processed, MiB)
  iraf_vo::TrackingState last_state = iraf_vo::TrackingState::kNotInitialized;
  for (;;) {
    FrontItem it;
    queue.pop(&it);
    if (it.end) break;
    ++processed;
    if (it.fatal) {
      std::fprintf(stderr, "\niraf_vo_run: %s\n", it.message.c_str());
      fatal = true;
      break;
    }
    if (it.error) {
      ++errors;
      std::fprintf(stderr, "\niraf_vo_run: frame %ld skipped: %s\n", it.index, it.message.c_str());
      continue;
    }
    const iraf_vo::TrackResult r = tracker.track(it.frame);
    last_state = r.state;
    if (frame_log)
      frame_log << it.index << "," << std::fixed << it.frame.stamp << std::defaultfloat << "," << iraf_vo::toString(r.state)
                << "," << it.frame.keypoints.size() << "," << r.matches << "," << r.inliers << "," << r.is_keyframe << ","
                << r.used_pnp << "," << r.timing.ms_total << "\n";
    ms["read"].push_back(it.ms_read);
    ms["enhance"].push_back(it.ms_enhance);
    ms["features"].push_back(it.ms_features);
    ms["track"].push_back(r.timing.ms_total);
    ms["track_match"].push_back(r.timing.ms_match);
    ms["track_pose"].push_back(r.timing.ms_pose);
    ms["track_keyframe"].push_back(r.timing.ms_keyframe);
    if (r.timing.ms_init > 0) ms["track_init"].push_back(r.timing.ms_init);
    if (r.state == iraf_vo::TrackingState::kTracking) est.push_back(it.frame.stamp, r.T_w_c);
    if (processed % 500 == 0) rss.emplace_back(processed, rssMiB());
    const double el = std::chrono::duration<double>(Clock::now() - t_start).count();
    if (tty) {
      const int width = 30;
      const int filled = n_run > 0 ? static_cast<int>(width * processed / n_run) : 0;
      std::fprintf(stderr, "\r[%s%s] %ld/%ld %5.1f fps %-15s kps %4zu inl %4d", std::string(filled, '#').c_str(),
                   std::string(width - filled, '.').c_str(), processed, n_run, processed / std::max(el, 1e-9),
                   iraf_vo::toString(r.state), it.frame.keypoints.size(), r.inliers);
      std::fflush(stderr);
    } else if (!quiet && processed % 100 == 0) {
      std::fprintf(stderr, "iraf_vo_run: %ld/%ld frames, %.1f fps, %s\n", processed, n_run,
                   processed / std::max(el, 1e-9), iraf_vo::toString(r.state));
    }
  }
  stop_threads = true;
  queue.close();
  read_queue.close();
  front.join();
  reader.join();
  tracker.waitForMapping();
  if (fatal) return 1;
  const std::string skipped = is_bag ? bag.skippedSummary() : asl.skippedSummary();
  if (!skipped.empty()) std::fprintf(stderr, "iraf_vo_run: %s\n", skipped.c_str());
  if (processed > 0 && errors == processed) {
    std::fprintf(stderr, "iraf_vo_run: --dataset %s: none of the %ld frames could be read\n", dataset.c_str(), processed);
    return 1;
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t_start).count();
  if (tty) std::fprintf(stderr, "\n");
  (void)last_state;

  if (!iraf_vo::writeTumTrajectory(out, est, &err)) {
    std::fprintf(stderr, "iraf_vo_run: --out %s: %s\n", out.c_str(), err.c_str());
    return 1;
  }
  const iraf_vo::TrackerStats st = tracker.stats();
  const size_t n_points = tracker.mapPoints().size();
  const double tracked_pct = st.frames > 0 ? 100.0 * st.tracked / st.frames : 0.0;
  const double fps = processed / std::max(wall, 1e-9);
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  const double cpu_s = ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  const double cpu_ms_per_frame = 1000.0 * cpu_s / std::max<long>(1, processed);
  std::ostringstream summary;
  summary << "frames " << st.frames << ", tracked " << st.tracked << " (" << tracked_pct << " %), lost frames "
          << st.lost_frames << ", lost events " << st.lost_events << ", resets " << st.resets << ", keyframes "
          << st.keyframes << ", map points " << n_points << ", BA runs " << st.ba_runs << " (mean "
          << (st.ba_runs ? st.ba_ms_total / st.ba_runs : 0.0) << " ms)\n";
  summary << "wall " << wall << " s, " << fps << " fps (reader, front-end, tracking and mapping threads in parallel); CPU "
          << cpu_s << " s = " << cpu_ms_per_frame << " ms/frame (all threads) -> <= " << 2000.0 / cpu_ms_per_frame
          << " fps on 2 idle cores\n";
  summary << "per stage [ms] median / 95% / mean:\n";
  for (const auto& kv : ms) {
    const Percentiles p = percentiles(kv.second);
    char buf[160];
    std::snprintf(buf, sizeof(buf), "  %-15s %7.2f %7.2f %7.2f\n", kv.first.c_str(), p.median, p.p95, p.mean);
    summary << buf;
  }
  if (!rss.empty()) {
    summary << "RSS [MiB] after frames:";
    for (const auto& x : rss) summary << " " << x.first << ": " << x.second;
    summary << "\n";
  }
  iraf_vo::EvalResult ev;
  bool have_ate = false;
  if (!gt_path.empty()) {
    iraf_vo::EvalParams evp;
    evp.align = iraf_vo::AlignMode::kSim3;
    if (iraf_vo::evaluateTrajectory(gt, est, evp, &ev, &err)) {
      have_ate = true;
      summary << "ATE (Sim3) RMSE " << ev.ate.rmse << " m, median " << ev.ate.median << " m, max " << ev.ate.max
              << " m over " << ev.n_matched << " poses (scale " << ev.scale << ", GT path " << ev.gt_length
              << " m)\n";
    } else {
      summary << "ATE: not computed: " << err << "\n";
    }
  }
  std::fprintf(stdout, "%s", summary.str().c_str());
  if (!stats_path.empty()) {
    std::ofstream js(stats_path);
    if (!js) {
      std::fprintf(stderr, "iraf_vo_run: --stats %s: cannot write\n", stats_path.c_str());
      return 1;
    }
    js << "{\n  \"dataset\": \"" << dataset << "\",\n  \"mode\": \"" << mode << "\",\n  \"frames\": " << st.frames
       << ",\n  \"tracked\": " << st.tracked << ",\n  \"tracked_pct\": " << tracked_pct
       << ",\n  \"lost_frames\": " << st.lost_frames << ",\n  \"lost_events\": " << st.lost_events
       << ",\n  \"resets\": " << st.resets << ",\n  \"keyframes\": " << st.keyframes << ",\n  \"map_points\": "
       << n_points << ",\n  \"read_errors\": " << errors << ",\n  \"fps\": " << fps << ",\n  \"cpu_ms_per_frame\": " << cpu_ms_per_frame << ",\n  \"ms\": {";
    bool firstk = true;
    for (const auto& kv : ms) {
      const Percentiles p = percentiles(kv.second);
      js << (firstk ? "\n" : ",\n") << "    \"" << kv.first << "\": {\"median\": " << p.median << ", \"p95\": " << p.p95
         << ", \"mean\": " << p.mean << "}";
      firstk = false;
    }
    js << "\n  },\n  \"rss_mib\": {";
    for (size_t k = 0; k < rss.size(); ++k) js << (k ? ", " : "") << "\"" << rss[k].first << "\": " << rss[k].second;
    js << "}";
    if (have_ate)
      js << ",\n  \"ate_rmse\": " << ev.ate.rmse << ",\n  \"ate_median\": " << ev.ate.median
         << ",\n  \"ate_scale\": " << ev.scale << ",\n  \"ate_matched\": " << ev.n_matched;
    js << "\n}\n";
  }
  return 0;
}
