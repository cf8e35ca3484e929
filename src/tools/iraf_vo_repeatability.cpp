// iraf_vo_repeatability: front-end consistency between consecutive frames, per front-end mode (paper Table I).
//
//   iraf_vo_repeatability --dataset DIR [--reference DIR] [--first N] [--frames N] [--modes "baseline iraf ..."]
//                         [--gap K] [--gains A,B] [--radius PX] [--octave-gap L] [--csv FILE] [--config params.yaml]
//                         [--set section.key=v]...
//
// For each pair of frames (i, i+K) (--gap K, default 1: consecutive frames; a larger gap is what a keyframe meets) of the ASL folder DIR, every mode's front-end (enhancement + features,
// one FrontEnd per mode fed the frames in order, as iraf_vo_run does) extracts keypoints on both. Where frame i's
// keypoints went in frame i+K is measured on the --reference sequence (an undegraded copy with the same frames, e.g.
// the original EuRoC folder for a degraded copy or the clean render of a simulated one; default: DIR itself):
// pyramidal Lucas-Kanade from i to i+K and back, kept where the round trip closes within 0.5 px. Printed per mode,
// pooled over the pairs:
//   repeat     share of frame i's keypoints (with a flow, predicted inside the detection area) that have a keypoint of
//              frame i+K within --radius px (default 2) of the prediction, on a pyramid level at most --octave-gap
//              (default 1, as ORB-SLAM's projection search; -1: any level) from the keypoint's
//   p10        10th percentile of the per-pair repeatability (the bad pairs)
//   matched    share whose true match (the nearest such keypoint) has a descriptor distance <= 50 (ORB-SLAM TH_LOW)
//   hamming    mean descriptor distance of the true matches
// --gains A,B: frame i is multiplied by A and frame i+K by B (saturating at 255) before the front-end: an exposure
// step between two frames with the geometry unchanged. --csv: one row per mode and pair (with the enhancement's
// brightness class of both frames: -1 dim, 0 normal, 1 bright).
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "iraf_vo/eval/keypoint_repeatability.h"
#include "iraf_vo/pipeline/front_end.h"
#include "iraf_vo/pipeline/pipeline_params.h"
#include "iraf_vo/sim/sequence.h"

using namespace iraf_vo;

namespace {

struct Args {
  std::string dataset, reference, csv, config;
  int first = 0, frames = 100, gap = 1, octave_gap = 1;
  std::vector<std::string> modes{"baseline", "he", "clahe", "enhance", "adaptive", "culling", "iraf"};
  std::vector<std::string> sets;
  double gain_a = 1.0, gain_b = 1.0, radius = 2.0;
  bool gains = false;
};

void usage(FILE* f) {
  std::fprintf(f,
               "usage: iraf_vo_repeatability --dataset DIR [--reference DIR] [--first N] [--frames N]\n"
               "                             [--modes \"baseline he clahe enhance adaptive culling iraf\"] [--gains A,B]\n"
               "                             [--gap K] [--radius PX] [--octave-gap L] [--csv FILE] [--config params.yaml]\n"
               "                             [--set section.key=v]...\n");
}

bool parseDouble(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0';
}

int parseArgs(int argc, char** argv, Args* a) {
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "-h" || k == "--help") return usage(stdout), 0;
    if (i + 1 >= argc) return std::fprintf(stderr, "iraf_vo_repeatability: unknown or incomplete '%s'\n", k.c_str()), 2;
    const std::string v = argv[++i];
    double x = 0;
    if (k == "--dataset") a->dataset = v;
    else if (k == "--reference") a->reference = v;
    else if (k == "--csv") a->csv = v;
    else if (k == "--config") a->config = v;
    else if (k == "--set") a->sets.push_back(v);
    else if (k == "--modes") {
      std::istringstream in(v);
      a->modes.clear();
      for (std::string m; in >> m;) a->modes.push_back(m);
    } else if (k == "--first" || k == "--frames" || k == "--gap") {
      if (!parseDouble(v, &x) || x < 0 || x != static_cast<int>(x))
        return std::fprintf(stderr, "iraf_vo_repeatability: %s '%s': expected an integer >= 0\n", k.c_str(), v.c_str()), 2;
      (k == "--first" ? a->first : k == "--gap" ? a->gap : a->frames) = static_cast<int>(x);
    } else if (k == "--octave-gap") {
      if (!parseDouble(v, &x) || x < -1 || x != static_cast<int>(x))
        return std::fprintf(stderr, "iraf_vo_repeatability: --octave-gap '%s': expected an integer >= -1\n", v.c_str()), 2;
      a->octave_gap = static_cast<int>(x);
    } else if (k == "--radius") {
      if (!parseDouble(v, &a->radius) || !(a->radius > 0))
        return std::fprintf(stderr, "iraf_vo_repeatability: --radius '%s': expected a number > 0\n", v.c_str()), 2;
    } else if (k == "--gains") {
      const size_t comma = v.find(',');
      if (comma == std::string::npos || !parseDouble(v.substr(0, comma), &a->gain_a) ||
          !parseDouble(v.substr(comma + 1), &a->gain_b) || !(a->gain_a > 0) || !(a->gain_b > 0))
        return std::fprintf(stderr, "iraf_vo_repeatability: --gains '%s': expected A,B (numbers > 0)\n", v.c_str()), 2;
      a->gains = true;
    } else {
      return std::fprintf(stderr, "iraf_vo_repeatability: unknown argument '%s'\n", k.c_str()), usage(stderr), 2;
    }
  }
  if (a->dataset.empty()) return std::fprintf(stderr, "iraf_vo_repeatability: --dataset is required\n"), usage(stderr), 2;
  if (a->reference.empty()) a->reference = a->dataset;
  if (a->gap < 1) return std::fprintf(stderr, "iraf_vo_repeatability: --gap must be >= 1\n"), 2;
  if (a->frames <= a->gap) return std::fprintf(stderr, "iraf_vo_repeatability: --frames must exceed --gap\n"), 2;
  return -1;
}

/// Frames [first, first + count) of an ASL folder, as 8-bit grey images.
bool loadFrames(const std::string& dir, int first, int count, std::vector<cv::Mat>* images, std::string* err) {
  std::vector<std::pair<int64_t, std::string>> rows;
  if (!readAslCsv(dir + "/mav0/cam0/data.csv", &rows, err)) return false;
  for (int i = first; i < std::min<int>(first + count, static_cast<int>(rows.size())); ++i) {
    const std::string path = dir + "/mav0/cam0/data/" + rows[i].second;
    cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (img.empty()) return (*err = "cannot read " + path), false;
    images->push_back(img);
  }
  if (images->size() < 2) return (*err = dir + ": fewer than 2 frames from --first"), false;
  return true;
}

/// Where frame a's points went in frame b: forward-backward Lucas-Kanade on the reference images.
void predictPoints(const std::vector<cv::Mat>& pyr_a, const std::vector<cv::Mat>& pyr_b, int levels,
                   const std::vector<cv::KeyPoint>& kps, std::vector<cv::Point2f>* predicted,
                   std::vector<uint8_t>* valid) {
  std::vector<cv::Point2f> pts, back;
  cv::KeyPoint::convert(kps, pts);
  predicted->clear();
  valid->assign(kps.size(), 0);
  if (pts.empty()) return;
  std::vector<uint8_t> st_f, st_b;
  std::vector<float> err;
  const cv::Size win(21, 21);
  const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(pyr_a, pyr_b, pts, *predicted, st_f, err, win, levels, term);
  cv::calcOpticalFlowPyrLK(pyr_b, pyr_a, *predicted, back, st_b, err, win, levels, term);
  for (size_t i = 0; i < pts.size(); ++i) {
    const cv::Point2f d = back[i] - pts[i];
    (*valid)[i] = st_f[i] && st_b[i] && d.x * d.x + d.y * d.y < 0.25f;
  }
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

struct ModeRun {
  std::string name;
  FrontEnd front_end;
  std::vector<FeatureFrame> frames;  // frames i - K .. i, indexed by frame % (K + 1)
  RepeatabilityStats pooled;
  std::vector<double> per_pair;
  ModeRun(const std::string& n, const PipelineParams& p) : name(n), front_end(p.enhance, p.features) {}
};

}  // namespace

int main(int argc, char** argv) {
  Args a;
  if (const int code = parseArgs(argc, argv, &a); code >= 0) return code;
  cv::setNumThreads(0);
  std::vector<cv::Mat> images, reference;
  std::string err;
  if (!loadFrames(a.dataset, a.first, a.frames, &images, &err) ||
      !loadFrames(a.reference, a.first, a.frames, &reference, &err))
    return std::fprintf(stderr, "iraf_vo_repeatability: %s\n", err.c_str()), 1;
  const size_t n = std::min(images.size(), reference.size());
  for (size_t i = 0; i < n; ++i)
    if (images[i].size() != images[0].size() || reference[i].size() != images[0].size())
      return std::fprintf(stderr, "iraf_vo_repeatability: frame %zu: image sizes differ\n", a.first + i), 1;

  std::vector<ModeRun> runs;
  runs.reserve(a.modes.size());
  for (const std::string& m : a.modes) {
    FrontEndMode mode;
    if (!parseFrontEndMode(m, &mode))
      return std::fprintf(stderr, "iraf_vo_repeatability: --modes '%s': expected %s\n", m.c_str(), frontEndModeList()), 2;
    PipelineParams p;
    applyFrontEndMode(mode, &p.enhance, &p.features);
    if (!a.config.empty() && !loadPipelineConfig(a.config, &p, &err))
      return std::fprintf(stderr, "iraf_vo_repeatability: --config %s\n", err.c_str()), 2;
    for (const std::string& s : a.sets)
      if (!applyPipelineSetting(s, &p, &err))
        return std::fprintf(stderr, "iraf_vo_repeatability: --set '%s': %s\n", s.c_str(), err.c_str()), 2;
    applyFeatureResolutionRule(images[0].cols, images[0].rows, p.user_set, &p.features);
    if (!(err = validate(p)).empty()) return std::fprintf(stderr, "iraf_vo_repeatability: %s\n", err.c_str()), 2;
    runs.emplace_back(m, p);
  }
  std::ofstream csv;
  if (!a.csv.empty()) {
    csv.open(a.csv);
    if (!csv) return std::fprintf(stderr, "iraf_vo_repeatability: cannot write %s\n", a.csv.c_str()), 1;
    csv << "mode,frame,keypoints_a,keypoints_b,reference,repeated,matched,repeatability,mean_hamming,brightness_a,"
           "brightness_b\n";
  }
  const cv::Rect2f area = detectionArea(images[0].cols, images[0].rows);
  const auto scaled = [](const cv::Mat& img, double g) {
    cv::Mat out;
    img.convertTo(out, CV_8U, g);
    return out;
  };
  // Frames i - K .. i are kept (their reference pyramids and, without --gains, every mode's features).
  const size_t ring = static_cast<size_t>(a.gap) + 1;
  const int lk_levels = a.gap > 2 ? 4 : 3;
  std::vector<std::vector<cv::Mat>> pyramids(ring);
  for (ModeRun& r : runs) r.frames.resize(ring);
  std::vector<cv::Point2f> predicted;
  std::vector<uint8_t> valid;
  size_t pairs = 0;
  for (size_t i = 0; i < n; ++i) {
    cv::buildOpticalFlowPyramid(reference[i], pyramids[i % ring], cv::Size(21, 21), lk_levels);
    if (i < ring - 1) {
      for (ModeRun& r : runs)
        if (!a.gains) r.frames[i % ring] = r.front_end.process(images[i], static_cast<double>(i));
      continue;
    }
    const size_t i0 = i - a.gap;
    ++pairs;
    for (ModeRun& r : runs) {
      FeatureFrame& fa = r.frames[i0 % ring];
      FeatureFrame& fb = r.frames[i % ring];
      if (a.gains) fa = r.front_end.process(scaled(images[i0], a.gain_a), static_cast<double>(i0));
      fb = r.front_end.process(a.gains ? scaled(images[i], a.gain_b) : images[i], static_cast<double>(i));
      predictPoints(pyramids[i0 % ring], pyramids[i % ring], lk_levels, fa.keypoints, &predicted, &valid);
      const RepeatabilityStats st = measureRepeatability(fa, predicted, valid, fb, area, a.radius, a.octave_gap);
      r.pooled.add(st);
      r.per_pair.push_back(st.repeatability());
      if (csv)
        csv << r.name << ',' << a.first + i0 << ',' << st.keypoints_a << ',' << st.keypoints_b << ',' << st.reference
            << ',' << st.repeated << ',' << st.matched << ',' << st.repeatability() << ',' << st.meanHamming() << ','
            << fa.stats.brightness << ',' << fb.stats.brightness << '\n';
    }
  }
  std::printf("iraf_vo_repeatability: %zu pairs (gap %d) of %s (flow from %s)%s, radius %.1f px\n", pairs, a.gap,
              a.dataset.c_str(),
              a.reference.c_str(),
              a.gains ? (" at gains " + std::to_string(a.gain_a) + " -> " + std::to_string(a.gain_b)).c_str() : "",
              a.radius);
  std::printf("%-9s %9s %7s %6s %8s %8s\n", "mode", "keypoints", "repeat", "p10", "matched", "hamming");
  for (const ModeRun& r : runs)
    std::printf("%-9s %9.0f %7.3f %6.3f %8.3f %8.1f\n", r.name.c_str(),
                static_cast<double>(r.pooled.keypoints_a) / std::max<size_t>(1, r.per_pair.size()),
                r.pooled.repeatability(), percentile(r.per_pair, 0.1), r.pooled.matchedShare(), r.pooled.meanHamming());
  return 0;
}
