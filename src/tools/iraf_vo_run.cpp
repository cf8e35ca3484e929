// iraf_vo_run --dataset DIR_OR_BAG [--topic T] [--camera sensor.yaml] --out traj.txt
//             [--mode iraf|baseline|enhance|adaptive|culling|he|clahe] [--gt GT] [--stats stats.json] [--config
//             params.yaml]
//             [--first N] [--frames N] [--set tracker.key=value ...] [--quiet]
// Offline monocular VO (no roscore): iraf_vo::OfflinePipeline (reader thread -> front-end thread) feeds the tracker
// on this thread (BA on its own thread). Writes the TUM trajectory of every tracked frame and a summary (frames,
// tracked %, lost events, map points, per-stage median / 95 % ms, ATE when --gt).
#include <iraf_vo/camera/camera_loader.h>
#include <iraf_vo/common/wall_clock.h>
#include <iraf_vo/eval/trajectory_eval.h>
#include <iraf_vo/pipeline/pipeline_params.h>
#include <iraf_vo/pipeline/run_report.h>
#include <iraf_vo/pipeline/bag_frame_source.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

void usage(FILE* f) {
  std::fprintf(
      f,
      "usage: iraf_vo_run --dataset DIR_OR_BAG [--topic T] [--camera sensor.yaml] --out traj.txt\n"
      "                   [--mode iraf|baseline|enhance|adaptive|culling|he|clahe] [--gt GT] [--stats stats.json]\n"
      "                   [--config params.yaml] [--first N] [--frames N] [--set section.key=value] [--frame-log F] "
      "[--quiet]\n"
      "                   [--no-resolution-rule] [--out-final traj_final.txt]\n"
      "  --dataset  ASL folder (DIR/mav0/cam0/data.csv) or a rosbag (.bag, needs --topic)\n"
      "  --camera   camera yaml (default: the ASL folder's mav0/cam0/sensor.yaml)\n"
      "  --mode     iraf = enhancement + adaptive threshold + culling (default); baseline = all off;\n"
      "             enhance / adaptive / culling = that module alone; he / clahe = global histogram\n"
      "             equalization / CLAHE (clip 3.0, 8x8 tiles) + the baseline features (paper Table I)\n"
      "  --gt       ground truth (TUM or EuRoC csv) -> Sim(3) ATE in the summary\n"
      "  --config   YAML with optional maps 'enhance:', 'features:', 'tracker:' (keys = parameter names)\n"
      "  --first/--frames  process frames [first, first + frames) only\n"
      "  --frame-log per-frame CSV: index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track,note\n"
      "             (note: why initialization failed / why the health monitor rejected the pose)\n"
      "  --set      override one parameter, e.g. --set tracker.ba_window_size=12 (after --mode / --config)\n"
      "  --no-resolution-rule  keep the 752x480 defaults of the size-dependent fields (n_features, cell_size,\n"
      "             n_levels, search radii, init counts); default: derive the ones not given by --config / --set\n"
      "             from the camera (pipeline_params.h, README)\n"
      "  --out-final the trajectory after mapping: each tracked pose re-attached to its reference keyframe's\n"
      "             final (BA-refined) pose, as ORB-SLAM / DSO result files are; --out keeps the poses as\n"
      "             published at each frame. With --gt both ATEs are printed.\n");
}

struct Args {
  std::string dataset, topic, camera_path, out, mode = "iraf", gt_path, stats_path, config_path, frame_log_path,
      out_final;
  long first = 0, max_frames = -1;
  bool quiet = false, no_resolution_rule = false;
  std::vector<std::string> sets;
};

/// Exit code 2 for bad arguments, -1 when parsed.
int parseArgs(int argc, char** argv, Args* a) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    std::string* text = k == "--dataset"     ? &a->dataset
                        : k == "--topic"     ? &a->topic
                        : k == "--camera"    ? &a->camera_path
                        : k == "--out"       ? &a->out
                        : k == "--mode"      ? &a->mode
                        : k == "--gt"        ? &a->gt_path
                        : k == "--stats"     ? &a->stats_path
                        : k == "--config"    ? &a->config_path
                        : k == "--frame-log" ? &a->frame_log_path
                        : k == "--out-final" ? &a->out_final
                                             : nullptr;
    const bool takes_value = text || k == "--set" || k == "--first" || k == "--frames";
    if (k == "-h" || k == "--help") return usage(stdout), 0;
    if (k == "--quiet" || k == "--no-resolution-rule") {
      (k == "--quiet" ? a->quiet : a->no_resolution_rule) = true;
      continue;
    }
    if (!takes_value) {
      std::fprintf(stderr, "iraf_vo_run: unknown argument '%s'\n", k.c_str());
      return usage(stderr), 2;
    }
    if (i + 1 >= argc) return std::fprintf(stderr, "iraf_vo_run: %s needs a value\n", k.c_str()), 2;
    const std::string v = argv[++i];
    if (text) {
      *text = v;
    } else if (k == "--set") {
      a->sets.push_back(v);
    } else {
      char* end = nullptr;
      const long x = std::strtol(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || x < 0)
        return std::fprintf(stderr, "iraf_vo_run: %s '%s': expected an integer >= 0\n", k.c_str(), v.c_str()), 2;
      (k == "--first" ? a->first : a->max_frames) = x;
    }
  }
  if (a->dataset.empty() || a->out.empty()) {
    std::fprintf(stderr, "iraf_vo_run: --dataset and --out are required\n");
    return usage(stderr), 2;
  }
  return -1;
}

/// Parameters: defaults -> mode -> config -> --set. Exit code 2 on error, -1 when usable.
int makeParams(const Args& a, iraf_vo::PipelineParams* p) {
  iraf_vo::FrontEndMode mode;
  if (!iraf_vo::parseFrontEndMode(a.mode, &mode))
    return std::fprintf(stderr, "iraf_vo_run: --mode '%s': expected %s\n", a.mode.c_str(), iraf_vo::frontEndModeList()),
           2;
  iraf_vo::applyFrontEndMode(mode, &p->enhance, &p->features);
  std::string err;
  if (!a.config_path.empty() && !iraf_vo::loadPipelineConfig(a.config_path, p, &err))
    return std::fprintf(stderr, "iraf_vo_run: --config %s\n", err.c_str()), 2;
  for (const std::string& s : a.sets)
    if (!iraf_vo::applyPipelineSetting(s, p, &err))
      return std::fprintf(stderr, "iraf_vo_run: --set '%s': %s\n", s.c_str(), err.c_str()), 2;
  if (!(err = iraf_vo::validate(*p)).empty()) return std::fprintf(stderr, "iraf_vo_run: %s\n", err.c_str()), 2;
  return -1;
}

double processCpuSeconds() {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  iraf_vo::PipelineParams params;
  int code = parseArgs(argc, argv, &a);
  if (code >= 0 || (code = makeParams(a, &params)) >= 0) return code;

  // ---- input ----
  struct stat ds;
  if (stat(a.dataset.c_str(), &ds) != 0)
    return std::fprintf(stderr, "iraf_vo_run: --dataset %s: no such file or folder\n", a.dataset.c_str()), 1;
  iraf_vo::AslImageReader asl;
  std::unique_ptr<iraf_vo::FrameSource> source;
  std::string err;
  if (S_ISDIR(ds.st_mode)) {
    if (!asl.open(a.dataset, &err))
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", a.dataset.c_str(), err.c_str()), 1;
    source = std::make_unique<iraf_vo::AslFrameSource>(&asl);
    for (const std::string& w : asl.warnings()) std::fprintf(stderr, "iraf_vo_run: %s\n", w.c_str());
    if (a.camera_path.empty()) a.camera_path = asl.sensorYamlPath();
  } else {
    if (a.topic.empty())
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s is not a folder: a bag needs --topic\n",
                          a.dataset.c_str()),
             2;
    // The bag reader (libiraf_vo_ros.so) is loaded only here: runs on ASL folders never load the ROS libraries.
    if (!(source = iraf_vo::openBagFrameSource(a.dataset, a.topic, &err)))
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", a.dataset.c_str(), err.c_str()), 1;
    if (!source->notice().empty()) std::fprintf(stderr, "iraf_vo_run: %s\n", source->notice().c_str());
  }
  if (a.camera_path.empty()) return std::fprintf(stderr, "iraf_vo_run: no camera: pass --camera sensor.yaml\n"), 2;
  const iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(a.camera_path, &err);
  if (!cam) return std::fprintf(stderr, "iraf_vo_run: --camera %s: %s\n", a.camera_path.c_str(), err.c_str()), 1;
  if (!a.no_resolution_rule) {
    const std::string rule = iraf_vo::applyResolutionRule(*cam, &params);
    if (!a.quiet) std::fprintf(stderr, "iraf_vo_run: resolution rule: %s\n", rule.c_str());
    if (!(err = iraf_vo::validate(params)).empty()) return std::fprintf(stderr, "iraf_vo_run: %s\n", err.c_str()), 2;
  }
  iraf_vo::Trajectory gt;
  if (!a.gt_path.empty() && !iraf_vo::readTrajectory(a.gt_path, &gt, &err, cam->T_BS))
    return std::fprintf(stderr, "iraf_vo_run: --gt %s: %s\n", a.gt_path.c_str(), err.c_str()), 1;
  const long total = static_cast<long>(source->size());
  iraf_vo::PipelineOptions opts;
  opts.first = a.first;
  opts.last = a.max_frames >= 0 ? std::min<long>(total, a.first + a.max_frames) : total;
  opts.width = cam->width();
  opts.height = cam->height();
  opts.camera_name = a.camera_path;
  const long n_run = std::max<long>(0, opts.last - opts.first);

  iraf_vo::RunRecorder recorder;
  const bool keep_final = !a.out_final.empty() || !a.gt_path.empty();  // the trajectory after mapping
  recorder.keepFinalTrajectory(keep_final);
  if (!a.frame_log_path.empty() && !recorder.openFrameLog(a.frame_log_path, &err))
    return std::fprintf(stderr, "iraf_vo_run: --frame-log %s\n", err.c_str()), 1;

  // ---- reader thread -> front-end thread -> tracking (this thread) ----
  iraf_vo::Tracker tracker(cam, params.tracker);
  const bool tty = isatty(fileno(stderr)) && !a.quiet;
  const auto t_start = iraf_vo::SteadyClock::now();
  iraf_vo::RunTotals totals;
  bool fatal = false;
  {
    iraf_vo::OfflinePipeline pipeline(source.get(), params.enhance, params.features, opts);
    for (iraf_vo::FrontEndItem it; !fatal && pipeline.next(&it);) {
      ++totals.processed;
      if ((fatal = it.fatal)) {
        std::fprintf(stderr, "\niraf_vo_run: %s\n", it.message.c_str());
      } else if (it.error) {
        ++totals.read_errors;
        std::fprintf(stderr, "\niraf_vo_run: frame %ld skipped: %s\n", it.index, it.message.c_str());
      } else {
        const iraf_vo::TrackResult r = tracker.track(it.frame);
        recorder.add(it, r, totals.processed);
        if (r.is_keyframe) recorder.updateKeyframes(tracker.keyframePoses());  // BA results arrive at keyframes
        if (!a.quiet)
          iraf_vo::printProgress(stderr, tty, totals.processed, n_run, 1e-3 * iraf_vo::msSince(t_start), r,
                                 it.frame.keypoints.size());
      }
    }
  }  // stops and joins the pipeline threads
  tracker.waitForMapping();
  recorder.updateKeyframes(tracker.keyframePoses());
  if (fatal) return 1;
  const std::string skipped = source->skippedSummary();
  if (!skipped.empty()) std::fprintf(stderr, "iraf_vo_run: %s\n", skipped.c_str());
  if (totals.processed > 0 && totals.read_errors == totals.processed)
    return std::fprintf(stderr, "iraf_vo_run: --dataset %s: none of the %ld frames could be read\n", a.dataset.c_str(),
                        totals.processed),
           1;
  totals.wall_s = 1e-3 * iraf_vo::msSince(t_start);
  if (tty) std::fprintf(stderr, "\n");

  if (!iraf_vo::writeTumTrajectory(a.out, recorder.trajectory(), &err))
    return std::fprintf(stderr, "iraf_vo_run: --out %s: %s\n", a.out.c_str(), err.c_str()), 1;
  const iraf_vo::Trajectory final_trajectory = keep_final ? recorder.finalTrajectory() : iraf_vo::Trajectory();
  if (!a.out_final.empty() && !iraf_vo::writeTumTrajectory(a.out_final, final_trajectory, &err))
    return std::fprintf(stderr, "iraf_vo_run: --out-final %s: %s\n", a.out_final.c_str(), err.c_str()), 1;
  totals.dataset = a.dataset;
  totals.mode = a.mode;
  totals.stats = tracker.stats();
  totals.map_points = tracker.mapPoints().size();
  totals.cpu_s = processCpuSeconds();
  totals.ate_requested = !a.gt_path.empty();
  if (totals.ate_requested) {
    iraf_vo::EvalParams evp;
    evp.align = iraf_vo::AlignMode::kSim3;
    totals.have_ate = iraf_vo::evaluateTrajectory(gt, recorder.trajectory(), evp, &totals.ate, &totals.ate_error);
    std::string final_error;
    totals.have_ate_final = iraf_vo::evaluateTrajectory(gt, final_trajectory, evp, &totals.ate_final, &final_error);
  }
  std::fprintf(stdout, "%s", recorder.summary(totals).c_str());
  if (!a.stats_path.empty() && !recorder.writeJson(a.stats_path, totals, &err))
    return std::fprintf(stderr, "iraf_vo_run: --stats %s\n", err.c_str()), 1;
  return 0;
}
