// iraf_vo_run --dataset DIR_OR_BAG [--topic T [--right-topic T --right-camera R.yaml]] [--camera sensor.yaml] --out traj.txt
//             [--mode iraf|baseline|enhance|adaptive|culling|he|clahe] [--gt GT] [--stats stats.json]
//             [--config params.yaml] [--first N] [--frames N] [--set section.key=value ...] [--quiet] [--stereo]
// Offline monocular or (--stereo, ASL cam0 + cam1) stereo VO (no roscore): iraf_vo::OfflinePipeline (reader thread -> front-end thread) feeds the tracker
// on this thread (BA on its own thread). Writes the TUM trajectory of every tracked frame and a summary (frames,
// tracked %, lost events, map points, per-stage median / 95 % ms, ATE when --gt).
#include <iraf_vo/camera/camera_loader.h>
#include <iraf_vo/camera/stereo_rig.h>
#include <iraf_vo/common/wall_clock.h>
#include <iraf_vo/pipeline/command_line.h>
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
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Args {
  std::string dataset, topic, right_topic, right_camera_path, camera_path, out, mode = "iraf", gt_path, stats_path, frame_log_path, out_final;
  int first = 0, max_frames = -1;
  bool quiet = false, no_resolution_rule = false, stereo = false;
};

/// Parameters: defaults -> mode -> --config -> --set. Exit code 0 / 2 when the run should not start, -1 otherwise.
int parseArgs(int argc, char** argv, Args* a, iraf_vo::PipelineParams* p) {
  iraf_vo::CommandLine cli(
      "iraf_vo_run",
      "Offline monocular VO on an ASL folder or a rosbag: writes the TUM trajectory and prints a summary.");
  cli.option("--dataset", "DIR_OR_BAG", &a->dataset,
             "ASL folder (DIR/mav0/cam0/data.csv) or a rosbag (.bag, needs --topic)");
  cli.option("--topic", "T", &a->topic, "image topic of a bag");
  cli.option("--right-topic", "T", &a->right_topic,
             "--stereo on a bag: the right image topic (paired with --topic by stamp, 5 ms)");
  cli.option("--right-camera", "R.yaml", &a->right_camera_path,
             "--stereo: the right camera yaml (default: the ASL folder's mav0/cam1/sensor.yaml)");
  cli.option("--camera", "sensor.yaml", &a->camera_path,
             "camera yaml (default: the ASL folder's mav0/cam0/sensor.yaml)");
  cli.option("--out", "traj.txt", &a->out, "TUM trajectory of every tracked frame, as published at each frame");
  cli.option("--mode", "M", &a->mode,
             "iraf = enhancement + adaptive threshold + culling (default); baseline = all off;\n"
             "enhance / adaptive / culling = that module alone; he / clahe = global histogram\n"
             "equalization / CLAHE (clip 3.0, 8x8 tiles) + the baseline features (paper Table I)");
  cli.option("--gt", "GT", &a->gt_path, "ground truth (TUM or EuRoC csv) -> Sim(3) ATE in the summary");
  cli.option("--stats", "stats.json", &a->stats_path, "the summary as JSON");
  cli.option("--first", "N", &a->first, 0, std::numeric_limits<int>::max(), "first frame to process");
  cli.option("--frames", "N", &a->max_frames, 0, std::numeric_limits<int>::max(),
             "process frames [first, first + N) only");
  cli.option("--frame-log", "F", &a->frame_log_path,
             "per-frame CSV: index,stamp,state,keypoints,matches,inliers,keyframe,pnp,ms_track,mean,snr,note\n"
             "(note: why initialization failed / why the health monitor rejected the pose / stereo: the metric scale\n"
             "became weakly observed or observed again)");
  cli.option("--out-final", "traj_final.txt", &a->out_final,
             "the trajectory after mapping: each tracked pose re-attached to its reference keyframe's\n"
             "final (BA-refined) pose, as ORB-SLAM / DSO result files are. With --gt both ATEs are printed.");
  cli.flag("--quiet", &a->quiet, "no progress line, no resolution-rule line");
  cli.flag("--stereo", &a->stereo,
           "stereo VO on an ASL folder: cam0 (left, --camera) + mav0/cam1 (right, its sensor.yaml), or on a\n"
           "bag with --right-topic and --right-camera; metric\n"
           "map from the first frame; frames without a cam1 image continue with the left camera");
  cli.flag("--no-resolution-rule", &a->no_resolution_rule,
           "keep the 752x480 defaults of the size-dependent fields (n_features, cell_size, n_levels,\n"
           "search radii, init counts); default: derive the ones not given by --config / --set from the\n"
           "camera (pipeline_params.h)");
  cli.stageParams({"enhance", "features", "tracker"});
  cli.require("--dataset");
  cli.require("--out");
  int code = cli.parse(argc, argv);
  if (code >= 0) return code;
  iraf_vo::FrontEndMode mode;
  if (!iraf_vo::parseFrontEndMode(a->mode, &mode))
    return std::fprintf(stderr, "iraf_vo_run: --mode '%s': expected %s\n", a->mode.c_str(), iraf_vo::frontEndModeList()),
           2;
  iraf_vo::applyFrontEndMode(mode, &p->enhance, &p->features);
  return cli.applyStageParams(p);
}

double processCpuSeconds() {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/// The frame's right features for the stereo tracker; an unusable right image is named on stderr (the frame then
/// has no stereo matches).
iraf_vo::FeatureFrame rightFeatures(iraf_vo::OfflinePipeline* pipeline, const iraf_vo::FrontEndItem& it) {
  iraf_vo::FeatureFrame f = pipeline->rightFeatures(it);
  if (!pipeline->rightError().empty())
    std::fprintf(stderr, "\niraf_vo_run: frame %ld: %s: no stereo matches\n", it.index, pipeline->rightError().c_str());
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  iraf_vo::PipelineParams params;
  if (const int code = parseArgs(argc, argv, &a, &params); code >= 0) return code;

  // ---- input ----
  struct stat ds;
  if (stat(a.dataset.c_str(), &ds) != 0)
    return std::fprintf(stderr, "iraf_vo_run: --dataset %s: no such file or folder\n", a.dataset.c_str()), 1;
  iraf_vo::AslImageReader asl;
  iraf_vo::AslImageReader asl_right;
  std::unique_ptr<iraf_vo::FrameSource> source;
  std::string err;
  if (S_ISDIR(ds.st_mode)) {
    if (!asl.open(a.dataset, &err))
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", a.dataset.c_str(), err.c_str()), 1;
    if (a.stereo && !asl_right.open(a.dataset, &err, "cam1"))
      return std::fprintf(stderr, "iraf_vo_run: --stereo: no right camera in %s: %s\n", a.dataset.c_str(), err.c_str()),
             1;
    // The right PNGs are decoded when the tracker matches a frame (initialization, keyframes), not for every frame.
    source = std::make_unique<iraf_vo::AslFrameSource>(&asl, a.stereo ? &asl_right : nullptr, true);
    for (const std::string& w : asl.warnings()) std::fprintf(stderr, "iraf_vo_run: %s\n", w.c_str());
    if (a.camera_path.empty()) a.camera_path = asl.sensorYamlPath();
  } else {
    if (a.stereo != !a.right_topic.empty() || (a.stereo && a.right_camera_path.empty()))
      return std::fprintf(stderr, "iraf_vo_run: a stereo bag needs --stereo, --right-topic and --right-camera\n"), 2;
    if (a.topic.empty())
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s is not a folder: a bag needs --topic\n",
                          a.dataset.c_str()),
             2;
    // The bag reader (libiraf_vo_ros.so) is loaded only here: runs on ASL folders never load the ROS libraries.
    iraf_vo::BagSourceOptions bag_options;
    bag_options.topic = a.topic;
    bag_options.right_topic = a.right_topic;
    if (!(source = iraf_vo::openBagFrameSource(a.dataset, bag_options, &err)))
      return std::fprintf(stderr, "iraf_vo_run: --dataset %s: %s\n", a.dataset.c_str(), err.c_str()), 1;
    if (!source->notice().empty()) std::fprintf(stderr, "iraf_vo_run: %s\n", source->notice().c_str());
  }
  if (a.camera_path.empty()) return std::fprintf(stderr, "iraf_vo_run: no camera: pass --camera sensor.yaml\n"), 2;
  const iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(a.camera_path, &err);
  if (!cam) return std::fprintf(stderr, "iraf_vo_run: --camera %s: %s\n", a.camera_path.c_str(), err.c_str()), 1;
  iraf_vo::StereoRig rig;
  if (a.stereo) {
    if (a.right_camera_path.empty()) a.right_camera_path = asl_right.sensorYamlPath();
    if (!iraf_vo::loadStereoRig(a.camera_path, a.right_camera_path, &rig, &err))
      return std::fprintf(stderr, "iraf_vo_run: --stereo: %s\n", err.c_str()), 1;
    if (rig.right->width() != cam->width() || rig.right->height() != cam->height())
      return std::fprintf(stderr, "iraf_vo_run: --stereo: %s is %dx%d, the left camera %dx%d\n",
                          a.right_camera_path.c_str(), rig.right->width(), rig.right->height(), cam->width(),
                          cam->height()),
             1;
    if (!a.quiet) std::fprintf(stderr, "iraf_vo_run: stereo, baseline %.4f m\n", rig.baseline());
  }
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
  opts.last = a.max_frames >= 0 ? std::min<long>(total, static_cast<long>(a.first) + a.max_frames) : total;
  opts.width = cam->width();
  opts.height = cam->height();
  opts.camera_name = a.camera_path;
  opts.stereo = a.stereo;
  const long n_run = std::max<long>(0, opts.last - opts.first);

  iraf_vo::RunRecorder recorder;
  const bool keep_final = !a.out_final.empty() || !a.gt_path.empty();  // the trajectory after mapping
  recorder.keepFinalTrajectory(keep_final);
  if (!a.frame_log_path.empty() && !recorder.openFrameLog(a.frame_log_path, &err))
    return std::fprintf(stderr, "iraf_vo_run: --frame-log %s\n", err.c_str()), 1;

  // ---- reader thread -> front-end thread -> tracking (this thread) ----
  std::unique_ptr<iraf_vo::Tracker> tracker_ptr =
      a.stereo ? std::make_unique<iraf_vo::Tracker>(rig, params.tracker)
               : std::make_unique<iraf_vo::Tracker>(cam, params.tracker);
  iraf_vo::Tracker& tracker = *tracker_ptr;
  bool right_was_missing = false;
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
        const iraf_vo::TrackResult r =
            a.stereo ? tracker.track(it.frame, it.has_right, [&] { return rightFeatures(&pipeline, it); })
                     : tracker.track(it.frame);
        if (a.stereo && r.right_missing != right_was_missing && r.right_missing)
          std::fprintf(stderr, "\niraf_vo_run: right image missing from frame %ld: continuing with the left camera\n",
                       it.index);
        if (a.stereo && r.right_missing != right_was_missing && !r.right_missing)
          std::fprintf(stderr, "\niraf_vo_run: right image back at frame %ld\n", it.index);
        right_was_missing = r.right_missing;
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
  totals.stereo = a.stereo;
  totals.baseline = a.stereo ? rig.baseline() : 0.0;
  totals.stats = tracker.stats();
  totals.map_points = tracker.mapPoints().size();
  totals.cpu_s = processCpuSeconds();
  totals.ate_requested = !a.gt_path.empty();
  if (totals.ate_requested) {
    iraf_vo::EvalParams evp;
    evp.align = iraf_vo::AlignMode::kSim3;
    totals.have_ate = iraf_vo::evaluateTrajectory(gt, recorder.trajectory(), evp, &totals.ate, &totals.ate_error);
    if (recorder.mapStarts().size() > 1)
      totals.ate_per_map = iraf_vo::evaluatePerMap(gt, recorder.trajectory(), recorder.mapStarts(), evp);
    std::string final_error;
    totals.have_ate_final = iraf_vo::evaluateTrajectory(gt, final_trajectory, evp, &totals.ate_final, &final_error);
    if (a.stereo) {  // metric: the SE(3)-aligned ATE as well
      evp.align = iraf_vo::AlignMode::kSE3;
      totals.have_ate_se3 = iraf_vo::evaluateTrajectory(gt, recorder.trajectory(), evp, &totals.ate_se3, &final_error);
    }
  }
  std::fprintf(stdout, "%s", recorder.summary(totals).c_str());
  if (!a.stats_path.empty() && !recorder.writeJson(a.stats_path, totals, &err))
    return std::fprintf(stderr, "iraf_vo_run: --stats %s\n", err.c_str()), 1;
  return 0;
}
