// iraf_vo_eval GT EST [--align sim3|se3|none] [--max-dt 0.02] [--rpe-delta 1.0] [--rpe-frames]
//              [--csv errors.csv] [--json out.json] [--camera sensor.yaml]
// Absolute (ATE) and relative (RPE) trajectory error of EST against GT, evo conventions (see trajectory_eval.h).
// GT: TUM file or EuRoC state_groundtruth_estimate0/data.csv (or its dataset folder), auto-detected; for EuRoC csv
// the body poses are turned into camera poses with T_BS from --camera (identity otherwise). EST: TUM or EuRoC csv.
#include <cstdio>
#include <fstream>
#include <string>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/eval/trajectory_eval.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/pipeline/command_line.h"

int main(int argc, char** argv) {
  iraf_vo::EvalParams params;
  std::string gt_path, est_path, align, csv, json, camera;
  iraf_vo::CommandLine cli("iraf_vo_eval",
                           "Absolute (ATE) and relative (RPE) trajectory error of EST against GT (evo conventions).");
  cli.positional("GT", &gt_path,
                 "TUM file (t tx ty tz qx qy qz qw; t in s, or ns when > 1e12) or EuRoC ground-truth csv / folder");
  cli.positional("EST", &est_path, "TUM file or EuRoC csv");
  cli.option("--align", "sim3|se3|none", &align, "alignment of EST onto GT (default sim3, the monocular default)");
  cli.option("--max-dt", "SEC", &params.max_dt, 0.0, 1e6, "timestamp association tolerance in seconds (default 0.02)");
  cli.option("--rpe-delta", "D", &params.rpe_delta, 1e-9, 1e9,
             "RPE step in seconds (default 1.0), or in frames with --rpe-frames");
  cli.flag("--rpe-frames", &params.rpe_delta_frames, "--rpe-delta counts frames");
  cli.option("--csv", "errors.csv", &csv,
             "per-pose errors: t,error,est_x,est_y,est_z,gt_x,gt_y,gt_z (aligned estimate)");
  cli.option("--json", "out.json", &json, "summary numbers as JSON");
  cli.option("--camera", "sensor.yaml", &camera,
             "camera yaml whose T_BS turns EuRoC body ground truth into camera poses");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (!align.empty() && !iraf_vo::parseAlignMode(align, &params.align)) {
    std::fprintf(stderr, "iraf_vo_eval: --align '%s': expected sim3, se3 or none\n", align.c_str());
    return 2;
  }
  std::string err;
  Eigen::Matrix4d T_BS = Eigen::Matrix4d::Identity();
  if (!camera.empty()) {
    iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(camera, &err);
    if (!cam) {
      std::fprintf(stderr, "iraf_vo_eval: --camera: %s\n", err.c_str());
      return 1;
    }
    T_BS = cam->T_BS;
  }
  iraf_vo::Trajectory gt, est;
  std::vector<std::string> warnings;
  if (!iraf_vo::readTrajectory(gt_path, &gt, &err, T_BS, &warnings)) {
    std::fprintf(stderr, "iraf_vo_eval: ground truth: %s\n", err.c_str());
    return 1;
  }
  if (!iraf_vo::readTrajectory(est_path, &est, &err, Eigen::Matrix4d::Identity(), &warnings)) {
    std::fprintf(stderr, "iraf_vo_eval: estimate: %s\n", err.c_str());
    return 1;
  }
  for (size_t i = 0; i < warnings.size() && i < 20; ++i) std::fprintf(stderr, "warning: %s\n", warnings[i].c_str());
  if (warnings.size() > 20) std::fprintf(stderr, "warning: ... %zu more\n", warnings.size() - 20);

  iraf_vo::EvalResult result;
  if (!iraf_vo::evaluateTrajectory(gt, est, params, &result, &err)) {
    std::fprintf(stderr, "iraf_vo_eval: %s\n", err.c_str());
    return 1;
  }
  std::printf("GT:       %s\nestimate: %s\n%s", gt_path.c_str(), est_path.c_str(),
              iraf_vo::formatSummary(result, params).c_str());
  if (!csv.empty()) {
    if (!iraf_vo::writeErrorsCsv(csv, result, &err)) {
      std::fprintf(stderr, "iraf_vo_eval: --csv: %s\n", err.c_str());
      return 1;
    }
    std::printf("per-pose errors written to %s\n", csv.c_str());
  }
  if (!json.empty()) {
    std::ofstream f(json);
    f << iraf_vo::toJson(result, params);
    if (!f) {
      std::fprintf(stderr, "iraf_vo_eval: --json: %s: cannot write\n", json.c_str());
      return 1;
    }
    std::printf("summary written to %s\n", json.c_str());
  }
  return 0;
}
