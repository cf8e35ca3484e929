// iraf_vo_culling_table: does the culling score separate keypoints that the tracker uses from those it
// does not? (docs/evaluation.md, culling table)
//
//   iraf_vo_culling_table --dataset DIR [--first N] [--frames N] [--no-enhance] [--apply-culling] [--bins B]
//                         [--config FILE] [--set section.key=value ...] [--csv FILE]
//
// Runs the front-end (Enhancer iraf unless --no-enhance, FeatureExtractor with the given FeatureParams but
// culling OFF, so every keypoint reaches the tracker) and the tracker (mapping_thread = false: deterministic)
// on the ASL folder DIR. Each keypoint's culling score S (eq. 23 with the given parameters, computed exactly as
// culling would, on the same keypoint set) is recorded with its outcome:
//   inlier = the keypoint was matched to a map point and was a pose inlier in its own frame
//            (TrackResult::keypoint_inlier; only frames in the Tracking state count).
// Prints the inlier rate per S bin and for the keypoints culling would keep (S >= s_min) and cull (S < s_min,
// ignoring min_features), and their ratio (culled / kept; culling earns its place when it is clearly < 1).
// --apply-culling: culling ON as configured, so only the kept keypoints reach the tracker (the table then shows
// the inlier rate of what the tracker received; the "culled" row holds only keypoints kept by min_features).
// --csv writes one row per keypoint: frame,octave,response,threshold,density,contrast,S,inlier.
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/tracking/tracker.h"
#include "iraf_vo/pipeline/command_line.h"

namespace {

struct Counts {
  long n = 0, inliers = 0;
  double rate() const { return n > 0 ? static_cast<double>(inliers) / n : 0.0; }
};

}  // namespace

int main(int argc, char** argv) {
  std::string dataset, csv_path;
  int first_arg = 0, frames_arg = -1, bins = 10;
  bool enhance = true, apply_culling = false;
  iraf_vo::CommandLine cli("iraf_vo_culling_table",
                           "Inlier rate of the tracker's keypoints per bin of the culling score S (eq. 23).");
  cli.option("--dataset", "DIR", &dataset, "ASL folder (DIR/mav0/cam0/data.csv, sensor.yaml)");
  cli.option("--first", "N", &first_arg, 0, std::numeric_limits<int>::max(), "first frame (default 0)");
  cli.option("--frames", "N", &frames_arg, 0, std::numeric_limits<int>::max(), "frames to run (default: all)");
  cli.option("--bins", "B", &bins, 1, 1000, "bins of S in [0, 1] (default 10)");
  cli.option("--csv", "FILE", &csv_path,
             "one row per keypoint: frame,octave,response,threshold,density,contrast,S,inlier");
  cli.flag("--no-enhance", &enhance, "enhance.method none", false);
  cli.flag("--apply-culling", &apply_culling, "culling on as configured: only the kept keypoints reach the tracker");
  cli.stageParams({"enhance", "features", "tracker"});
  cli.require("--dataset");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  iraf_vo::PipelineParams params;
  params.tracker.mapping_thread = false;  // deterministic (--set tracker.mapping_thread=true overrides)
  if (const int code = cli.applyStageParams(&params); code >= 0) return code;
  const long first = first_arg, frames = frames_arg;
  const iraf_vo::FeatureParams& fp = params.features;
  const iraf_vo::TrackerParams& tp = params.tracker;
  iraf_vo::AslImageReader reader;
  std::string err;
  if (!reader.open(dataset, &err)) {
    std::fprintf(stderr, "iraf_vo_culling_table: --dataset %s: %s\n", dataset.c_str(), err.c_str());
    return 1;
  }
  iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(reader.sensorYamlPath(), &err);
  if (!cam) {
    std::fprintf(stderr, "iraf_vo_culling_table: %s: %s\n", reader.sensorYamlPath().c_str(), err.c_str());
    return 1;
  }
  iraf_vo::FeatureParams extract_params = fp;  // every keypoint reaches the tracker
  extract_params.culling = apply_culling && fp.culling;
  iraf_vo::FeatureParams score_params = fp;    // S exactly as culling computes it
  score_params.culling = true;
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) {
      std::fprintf(stderr, "iraf_vo_culling_table: --csv %s: cannot write\n", csv_path.c_str());
      return 1;
    }
    csv << "frame,octave,response,threshold,density,contrast,S,inlier\n";
  }

  iraf_vo::Enhancer enhancer;
  iraf_vo::EnhanceParams ep = params.enhance;
  if (!enhance) ep.method = iraf_vo::EnhanceMethod::kNone;
  iraf_vo::FeatureExtractor extractor;
  iraf_vo::Tracker tracker(cam, tp);
  std::vector<Counts> per_bin(bins);
  Counts kept, culled;
  long tracked_frames = 0;
  const long last = frames >= 0 ? std::min<long>(reader.size(), first + frames) : static_cast<long>(reader.size());
  for (long f = first; f < last; ++f) {
    cv::Mat gray;
    if (!reader.loadImage(static_cast<size_t>(f), &gray, &err)) {
      std::fprintf(stderr, "iraf_vo_culling_table: frame %ld skipped: %s\n", f, err.c_str());
      continue;
    }
    const cv::Mat img = enhancer.enhance(gray, ep).image;
    const iraf_vo::FeatureFrame frame = extractor.extract(img, reader.entries()[f].stamp(), extract_params);
    const iraf_vo::CullResult cr = iraf_vo::cullKeypoints(frame.keypoints, extractor.pyramid(), img.size(), score_params);
    const iraf_vo::TrackResult r = tracker.track(frame);
    if (r.state != iraf_vo::TrackingState::kTracking || r.keypoint_inlier.size() != frame.keypoints.size()) continue;
    ++tracked_frames;
    for (size_t i = 0; i < frame.keypoints.size(); ++i) {
      // With culling applied, S as extract() computed it on the full keypoint set (cr is on the kept ones).
      const float s = extract_params.culling ? frame.stability[i] : cr.stability[i];
      const bool inl = r.keypoint_inlier[i] != 0;
      const int b = std::min(bins - 1, std::max(0, static_cast<int>(s * bins)));
      ++per_bin[b].n;
      per_bin[b].inliers += inl;
      Counts& c = s >= fp.s_min ? kept : culled;
      ++c.n;
      c.inliers += inl;
      if (csv) {
        const cv::KeyPoint& kp = frame.keypoints[i];
        csv << f << "," << kp.octave << "," << kp.response << "," << kp.class_id << "," << cr.density[i] << ","
            << cr.contrast[i] << "," << s << "," << inl << "\n";
      }
    }
  }
  const long all = kept.n + culled.n;
  std::printf("iraf_vo_culling_table: %s frames [%ld, %ld), %ld tracked frames, %ld keypoints, s_min %.2f, culling %s\n",
              dataset.c_str(), first, last, tracked_frames, all, fp.s_min,
              extract_params.culling ? "applied" : "off (scores only)");
  std::printf("  S bin         keypoints   share   inlier rate\n");
  for (int b = 0; b < bins; ++b) {
    if (per_bin[b].n == 0) continue;
    std::printf("  [%.2f, %.2f)  %9ld  %5.1f %%   %5.1f %%\n", static_cast<double>(b) / bins,
                static_cast<double>(b + 1) / bins, per_bin[b].n, 100.0 * per_bin[b].n / std::max(1L, all),
                100.0 * per_bin[b].rate());
  }
  std::printf("  kept   (S >= s_min)  %9ld  %5.1f %%   %5.1f %%\n", kept.n, 100.0 * kept.n / std::max(1L, all),
              100.0 * kept.rate());
  std::printf("  culled (S <  s_min)  %9ld  %5.1f %%   %5.1f %%\n", culled.n, 100.0 * culled.n / std::max(1L, all),
              100.0 * culled.rate());
  std::printf("  inlier-rate ratio culled / kept  %.2f\n", kept.rate() > 0 ? culled.rate() / kept.rate() : 0.0);
  return 0;
}
