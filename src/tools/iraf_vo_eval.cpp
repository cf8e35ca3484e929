// iraf_vo_eval GT EST [--align sim3|se3|none] [--max-dt 0.02] [--rpe-delta 1.0] [--rpe-frames]
//              [--csv errors.csv] [--json out.json] [--camera sensor.yaml]
// Absolute (ATE) and relative (RPE) trajectory error of EST against GT, evo conventions (see trajectory_eval.h).
// GT: TUM file or EuRoC state_groundtruth_estimate0/data.csv (or its dataset folder), auto-detected; for EuRoC csv
// the body poses are turned into camera poses with T_BS from --camera (identity otherwise). EST: TUM or EuRoC csv.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/eval/trajectory_eval.h"
#include "iraf_vo/io/trajectory.h"

namespace {

void usage(FILE* f) {
  std::fprintf(f,
               "usage: iraf_vo_eval GT EST [--align sim3|se3|none] [--max-dt SEC] [--rpe-delta D] [--rpe-frames]\n"
               "                    [--csv errors.csv] [--json out.json] [--camera sensor.yaml]\n"
               "  GT, EST     TUM files (t tx ty tz qx qy qz qw; t in s, or ns when > 1e12) or EuRoC ground-truth csv\n"
               "  --align     alignment of EST onto GT (default sim3, the monocular default)\n"
               "  --max-dt    timestamp association tolerance in seconds (default 0.02)\n"
               "  --rpe-delta RPE step in seconds (default 1.0), or in frames with --rpe-frames\n"
               "  --csv       per-pose errors: t,error,est_x,est_y,est_z,gt_x,gt_y,gt_z (aligned estimate)\n"
               "  --json      summary numbers as JSON\n"
               "  --camera    camera yaml whose T_BS turns EuRoC body ground truth into camera poses\n");
}

bool parseNumber(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0' && std::isfinite(*v);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> pos;
  iraf_vo::EvalParams params;
  std::string csv, json, camera;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "iraf_vo_eval: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else if (a == "--align") {
      const std::string v = value("--align");
      if (!iraf_vo::parseAlignMode(v, &params.align)) {
        std::fprintf(stderr, "iraf_vo_eval: --align '%s': expected sim3, se3 or none\n", v.c_str());
        return 2;
      }
    } else if (a == "--max-dt") {
      const std::string v = value("--max-dt");
      if (!parseNumber(v, &params.max_dt) || params.max_dt < 0) {
        std::fprintf(stderr, "iraf_vo_eval: --max-dt '%s': expected a number >= 0 (seconds)\n", v.c_str());
        return 2;
      }
    } else if (a == "--rpe-delta") {
      const std::string v = value("--rpe-delta");
      if (!parseNumber(v, &params.rpe_delta) || params.rpe_delta <= 0) {
        std::fprintf(stderr, "iraf_vo_eval: --rpe-delta '%s': expected a number > 0\n", v.c_str());
        return 2;
      }
    } else if (a == "--rpe-frames") {
      params.rpe_delta_frames = true;
    } else if (a == "--csv") {
      csv = value("--csv");
    } else if (a == "--json") {
      json = value("--json");
    } else if (a == "--camera") {
      camera = value("--camera");
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "iraf_vo_eval: unknown option '%s'\n", a.c_str());
      usage(stderr);
      return 2;
    } else {
      pos.push_back(a);
    }
  }
  if (pos.size() != 2) {
    std::fprintf(stderr, "iraf_vo_eval: expected 2 positional arguments (GT EST), got %zu\n", pos.size());
    usage(stderr);
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
  if (!iraf_vo::readTrajectory(pos[0], &gt, &err, T_BS, &warnings)) {
    std::fprintf(stderr, "iraf_vo_eval: ground truth: %s\n", err.c_str());
    return 1;
  }
  if (!iraf_vo::readTrajectory(pos[1], &est, &err, Eigen::Matrix4d::Identity(), &warnings)) {
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
  std::printf("GT:       %s\nestimate: %s\n%s", pos[0].c_str(), pos[1].c_str(),
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
