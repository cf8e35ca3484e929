// iraf_vo_keypoint_curve: FAST keypoint count vs. fixed threshold on original and enhanced low-light images
// (paper Fig. 3), plus the count with the adaptive threshold (eqs. 13-20).
//
//   iraf_vo_keypoint_curve --input DIR [--output FILE.csv] [--min 5] [--max 60] [--step 5] [--mu-expected MU]
//                          [--config FILE] [--set section.key=value ...]
//
// DIR (required; e.g. ../shared/data/lowlight_stills beside the checkout) is searched recursively for .jpg/.jpeg/.png/.bmp images.
// For each image, as loaded ("original") and after iraf_vo::Enhancer ("enhanced"):
//   * FAST (9/16, non-max suppression) corners at each fixed threshold, over the detection area the feature
//     stage uses (16 px border), on the full-resolution image;
//   * the adaptive per-cell threshold's corners on the same area (pyramid level 0, before distribution).
// CSV columns: image,variant,threshold,keypoints,global_threshold,cell_threshold_median
// (threshold = "adaptive" for the adaptive rows). A per-threshold mean over all images is printed.
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "iraf_vo/common/file_util.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/pipeline/command_line.h"

namespace fs = std::filesystem;
using namespace iraf_vo;

int main(int argc, char** argv) {
  std::string input, output = "keypoint_curve.csv";
  int t_min = 5, t_max = 60, step = 5;
  double mu_expected = -1.0;
  CommandLine cli("iraf_vo_keypoint_curve",
                  "FAST keypoint count vs. fixed threshold on original and enhanced images (paper Fig. 3).");
  cli.option("--input", "DIR", &input, "low-light stills, e.g. ../shared/data/lowlight_stills beside the checkout");
  cli.option("--output", "FILE.csv", &output, "the curve (default keypoint_curve.csv)");
  cli.option("--min", "T", &t_min, 1, 254, "lowest fixed threshold (default 5)");
  cli.option("--max", "T", &t_max, 1, 254, "highest fixed threshold (default 60)");
  cli.option("--step", "S", &step, 1, 254, "threshold step (default 5)");
  cli.option("--mu-expected", "MU", &mu_expected, 1.0, 254.0, "= --set enhance.mu_expected=MU");
  cli.stageParams({"enhance", "features"});
  cli.require("--input");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (t_min > t_max) {
    std::cerr << "iraf_vo_keypoint_curve: need --min <= --max\n";
    return 2;
  }
  PipelineParams params;
  if (mu_expected > 0) params.enhance.mu_expected = mu_expected;
  if (const int code = cli.applyStageParams(&params); code >= 0) return code;
  std::error_code ec;
  if (!fs::is_directory(input, ec)) {
    std::cerr << "iraf_vo_keypoint_curve: input folder '" << input << "' does not exist\n";
    return 1;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(input, ec))
    if (e.is_regular_file() && hasImageExtension(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::cerr << "iraf_vo_keypoint_curve: no .jpg/.png/.bmp images under '" << input << "'\n";
    return 1;
  }
  std::ofstream csv(output);
  if (!csv) {
    std::cerr << "iraf_vo_keypoint_curve: cannot write '" << output << "'\n";
    return 1;
  }
  csv << "image,variant,threshold,keypoints,global_threshold,cell_threshold_median\n";
  cv::setNumThreads(0);

  Enhancer enhancer;
  const EnhanceParams& ep = params.enhance;
  FeatureExtractor fx;
  FeatureParams fp = params.features;  // adaptive on; one level, culling off: count the level-0 FAST candidates
  fp.n_levels = 1;
  fp.culling = false;

  std::map<std::string, std::map<int, double>> sum;  // variant -> threshold (-1 = adaptive) -> sum of counts
  std::map<std::string, double> sum_global;
  int used = 0;
  std::vector<cv::KeyPoint> kps;
  for (const fs::path& f : files) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (img.empty() || img.cols < 64 || img.rows < 64) {
      std::cerr << "iraf_vo_keypoint_curve: skipping unreadable or tiny image " << f << "\n";
      continue;
    }
    ++used;
    const std::string name = fs::relative(f, input, ec).string();
    const cv::Mat enhanced = enhancer.enhance(img, ep).image;
    for (const auto& variant : {std::make_pair(std::string("original"), img), std::make_pair(std::string("enhanced"), enhanced)}) {
      const cv::Mat& im = variant.second;
      const cv::Mat roi = im(cv::Rect(16, 16, im.cols - 32, im.rows - 32));  // the feature stage's detection area
      for (int t = t_min; t <= t_max; t += step) {
        cv::FAST(roi, kps, t, true);
        csv << name << ',' << variant.first << ',' << t << ',' << kps.size() << ",,\n";
        sum[variant.first][t] += static_cast<double>(kps.size());
      }
      const FeatureFrame fr = fx.extract(im, 0, fp);
      csv << name << ',' << variant.first << ",adaptive," << fr.stats.candidates << ',' << fr.stats.global_threshold << ','
          << fr.stats.cell_threshold_median << "\n";
      sum[variant.first][-1] += fr.stats.candidates;
      sum_global[variant.first] += fr.stats.global_threshold;
    }
  }
  if (used == 0) {
    std::cerr << "iraf_vo_keypoint_curve: no usable image under '" << input << "'\n";
    return 1;
  }
  std::cout << "iraf_vo_keypoint_curve: " << used << " images from " << input << " -> " << output << "\n";
  std::cout << "mean FAST keypoints per image\nthreshold  original  enhanced\n";
  for (int t = t_min; t <= t_max; t += step)
    std::printf("%9d  %8.0f  %8.0f\n", t, sum["original"][t] / used, sum["enhanced"][t] / used);
  std::printf(" adaptive  %8.0f  %8.0f   (mean F_t^g original %.1f, enhanced %.1f)\n", sum["original"][-1] / used,
              sum["enhanced"][-1] / used, sum_global["original"] / used, sum_global["enhanced"] / used);
  return 0;
}
