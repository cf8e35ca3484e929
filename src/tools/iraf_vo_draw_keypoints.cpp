// iraf_vo_draw_keypoints --input IMAGE --output OUT.png [--config params.yaml] [--set section.key=value ...]
//                        [--scale S]
// Paper Fig. 4: the keypoints of our FeatureExtractor on one image, side by side:
//   left  = baseline: the image as is, fixed ORB-SLAM FAST thresholds (ini_th_fast / min_th_fast), no culling;
//   right = IRAF: enhanced image (EnhanceMethod::kIraf, eqs. 1-12), adaptive FAST threshold (eqs. 13-20) and
//           culling (eqs. 21-23); kept keypoints coloured by the stability S (red = s_min .. green = 1),
//           culled ones as magenta crosses.
// Both panels use the same FeatureParams apart from adaptive_threshold / culling (and the same --config / --set).
// Prints the counts of both configurations.
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"

using namespace iraf_vo;

namespace {

void drawLabel(cv::Mat* img, const std::string& text, int line) {
  const double fs = std::max(0.5, img->cols / 1100.0);
  const int th = std::max(1, static_cast<int>(fs * 2));
  int base = 0;
  const cv::Size sz = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, fs, th, &base);
  const cv::Point org(8, 8 + (line + 1) * (sz.height + base + 6));
  cv::rectangle(*img, cv::Point(org.x - 4, org.y - sz.height - 4), cv::Point(org.x + sz.width + 4, org.y + base + 2),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(*img, text, org, cv::FONT_HERSHEY_SIMPLEX, fs, cv::Scalar(255, 255, 255), th, cv::LINE_AA);
}

// Circle radius grows with the octave, like ORB-SLAM's viewer.
int radius(const cv::KeyPoint& k) { return 3 + 2 * std::max(0, k.octave); }

}  // namespace

int main(int argc, char** argv) {
  std::string input, output;
  double scale = 1.0;
  CommandLine cli("iraf_vo_draw_keypoints",
                  "left: baseline (original image, fixed FAST thresholds, no culling)\n"
                  "right: IRAF (enhanced image, adaptive threshold, culling; culled keypoints as magenta crosses)");
  cli.option("--input", "IMAGE", &input, "the image");
  cli.option("--output", "OUT.png", &output, "the side-by-side picture");
  cli.option("--scale", "S", &scale, 0.05, 4.0, "output scale factor (default 1)");
  cli.stageParams({"enhance", "features"});
  cli.require("--input");
  cli.require("--output");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  PipelineParams params;
  if (const int code = cli.applyStageParams(&params); code >= 0) return code;
  EnhanceParams& ep = params.enhance;
  const FeatureParams& fp = params.features;
  ep.method = EnhanceMethod::kIraf;  // the right panel is always the full IRAF front-end

  const cv::Mat gray = cv::imread(input, cv::IMREAD_GRAYSCALE);
  if (gray.empty()) {
    std::fprintf(stderr, "iraf_vo_draw_keypoints: --input %s: cannot read the image\n", input.c_str());
    return 1;
  }
  if (gray.cols < 64 || gray.rows < 64) {
    std::fprintf(stderr, "iraf_vo_draw_keypoints: --input %s: image %dx%d is too small (>= 64x64)\n", input.c_str(),
                 gray.cols, gray.rows);
    return 1;
  }

  FeatureExtractor fx;
  FeatureParams fb = fp;  // baseline: ORB-SLAM fixed thresholds, no culling
  fb.adaptive_threshold = false;
  fb.culling = false;
  FeatureParams fi = fp;  // IRAF: adaptive threshold + culling
  fi.adaptive_threshold = true;
  fi.culling = true;
  FeatureFrame base, iraf;
  CulledFeatures culled;
  EnhanceResult er;
  try {
    base = fx.extract(gray, 0.0, fb);
    Enhancer enhancer;
    er = enhancer.enhance(gray, ep);
    iraf = fx.extract(er.image, 0.0, fi, &culled);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "iraf_vo_draw_keypoints: %s: %s\n", input.c_str(), e.what());
    return 1;
  }

  cv::Mat left, right;
  cv::cvtColor(gray, left, cv::COLOR_GRAY2BGR);
  cv::cvtColor(er.image, right, cv::COLOR_GRAY2BGR);
  for (const cv::KeyPoint& k : base.keypoints)
    cv::circle(left, k.pt, radius(k), cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
  for (const cv::KeyPoint& k : culled.keypoints)
    cv::drawMarker(right, k.pt, cv::Scalar(255, 0, 255), cv::MARKER_CROSS, 2 * radius(k), 1, cv::LINE_AA);
  for (size_t j = 0; j < iraf.keypoints.size(); ++j) {
    const cv::KeyPoint& k = iraf.keypoints[j];
    const float S = j < iraf.stability.size() ? iraf.stability[j] : 1.0f;
    const double a = std::clamp((S - fi.s_min) / std::max(1e-6, 1.0 - fi.s_min), 0.0, 1.0);
    cv::circle(right, k.pt, radius(k), cv::Scalar(0, 255 * a, 255 * (1 - a)), 1, cv::LINE_AA);
  }
  char buf[200];
  std::snprintf(buf, sizeof(buf), "baseline: original, FAST %d/%d: %zu kps", fb.ini_th_fast, fb.min_th_fast,
                base.keypoints.size());
  drawLabel(&left, buf, 0);
  std::snprintf(buf, sizeof(buf), "mean intensity %.0f", cv::mean(gray)[0]);
  drawLabel(&left, buf, 1);
  std::snprintf(buf, sizeof(buf), "IRAF: enhanced, adaptive threshold %.1f: %zu kept, %d culled", iraf.stats.global_threshold,
                iraf.keypoints.size(), iraf.stats.culled);
  drawLabel(&right, buf, 0);
  std::snprintf(buf, sizeof(buf), "mean intensity %.0f (was %.0f)", cv::mean(er.image)[0], er.mu);
  drawLabel(&right, buf, 1);
  cv::Mat sep(left.rows, 6, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat out;
  cv::hconcat(std::vector<cv::Mat>{left, sep, right}, out);
  if (scale != 1.0) cv::resize(out, out, cv::Size(), scale, scale, cv::INTER_AREA);
  try {
    if (!cv::imwrite(output, out)) {
      std::fprintf(stderr, "iraf_vo_draw_keypoints: --output %s: cannot write\n", output.c_str());
      return 1;
    }
  } catch (const cv::Exception& e) {
    std::fprintf(stderr, "iraf_vo_draw_keypoints: --output %s: %s\n", output.c_str(), e.what());
    return 1;
  }
  std::printf("%s: baseline %zu keypoints (FAST %d/%d); IRAF %zu kept + %d culled (F_t^g %.1f, cell median %.1f, "
              "enhance class %d, mu %.1f) -> %s\n",
              input.c_str(), base.keypoints.size(), fb.ini_th_fast, fb.min_th_fast, iraf.keypoints.size(),
              iraf.stats.culled, iraf.stats.global_threshold, iraf.stats.cell_threshold_median,
              static_cast<int>(er.brightness), er.mu, output.c_str());
  return 0;
}
