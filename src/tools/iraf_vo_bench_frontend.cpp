// iraf_vo_bench_frontend: timing of the front-end (enhancement + feature stage) on an ASL/EuRoC folder.
//
//   iraf_vo_bench_frontend --dataset DIR [--frames N] [--mu-expected MU] [--config FILE.yaml] [--set ...]
//
// DIR is an ASL folder (DIR/mav0/cam0/data.csv + data/*.png). Single thread (cv::setNumThreads(0)).
// Images are loaded first; then, frame by frame (interleaved so machine load hits all variants alike):
//   orb       cv::ORB::create(1000)->detectAndCompute
//   all-off   our pipeline with every IRAF module off (no enhancement, fixed FAST 20/7, no culling)
//   all-on    Enhancer (iraf) + FeatureExtractor (adaptive threshold + culling), fast detection path
//   all-on, other path  the same with the other detection path (fast_path flipped)
// Prints the median ms per stage (enhance, threshold, pyramid, FAST, distribution + rest, describe, cull) and the
// ratios all-on / orb, all-on / all-off and reference / fast path.
// --config / --set: EnhanceParams and FeatureParams for all-on; all-off uses the same feature params with
// adaptive_threshold and culling off.
#include <opencv2/core/utility.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "iraf_vo/common/cpu_clock.h"
#include "iraf_vo/common/median.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/pipeline/command_line.h"

using namespace iraf_vo;

namespace {

// Minimal private ASL reader: DIR/mav0/cam0/data.csv rows "timestamp_ns,filename".
bool readAsl(const std::string& dir, int max_frames, std::vector<cv::Mat>* images, std::string* err) {
  const std::string cam = dir + "/mav0/cam0";
  std::ifstream csv(cam + "/data.csv");
  if (!csv) {
    *err = "cannot open " + cam + "/data.csv";
    return false;
  }
  std::string line;
  int row = 0;
  while (std::getline(csv, line) && static_cast<int>(images->size()) < max_frames) {
    ++row;
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    if (comma == std::string::npos) {
      *err = cam + "/data.csv line " + std::to_string(row) + ": expected 'timestamp,filename'";
      return false;
    }
    std::string name = line.substr(comma + 1);
    name.erase(name.find_last_not_of(" \r\t") + 1);
    name.erase(0, name.find_first_not_of(" \t"));
    const std::string path = cam + "/data/" + name;
    cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (img.empty()) {
      *err = "cannot read image " + path;
      return false;
    }
    images->push_back(img);
  }
  if (images->empty()) {
    *err = cam + "/data.csv lists no frames";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dataset;
  int frames = 200;
  double mu_expected = -1.0;
  CommandLine cli("iraf_vo_bench_frontend",
                  "Times the front-end (enhancement + feature stage) on an ASL folder, single thread.\n"
                  "all-on uses the enhance / features parameters of --config / --set; all-off the same features\n"
                  "with adaptive_threshold and culling off.");
  cli.option("--dataset", "DIR", &dataset, "ASL folder (DIR/mav0/cam0/data.csv)");
  cli.option("--frames", "N", &frames, 1, std::numeric_limits<int>::max(), "frames to time (default 200)");
  cli.option("--mu-expected", "MU", &mu_expected, 1.0, 254.0, "= --set enhance.mu_expected=MU");
  cli.stageParams({"enhance", "features"}, "features");
  cli.require("--dataset");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  PipelineParams params;
  if (mu_expected > 0) params.enhance.mu_expected = mu_expected;
  if (const int code = cli.applyStageParams(&params); code >= 0) return code;
  cv::setNumThreads(0);
  std::vector<cv::Mat> images;
  std::string err;
  if (!readAsl(dataset, frames, &images, &err)) {
    std::cerr << "iraf_vo_bench_frontend: " << err << "\n";
    return 1;
  }

  cv::Ptr<cv::ORB> orb = cv::ORB::create(1000);
  Enhancer enhancer;
  const EnhanceParams& ep = params.enhance;  // iraf unless --set enhance.method
  FeatureExtractor fx_on, fx_off;
  const FeatureParams on = params.features;
  FeatureParams ref = on;  // the other detection path
  ref.fast_path = !on.fast_path;
  FeatureParams off = on;
  off.adaptive_threshold = false;
  off.culling = false;

  std::vector<double> t_ref, pyr, fast, t_orb, t_off, t_on, det_enh_fixed, det_raw_adapt, enh, thr, det, desc_ms, cull, det_off, n_orb, n_on, n_off, n_culled;
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  // Warm-up (allocations, page faults) on the first frame.
  orb->detectAndCompute(images[0], cv::noArray(), kps, desc);
  fx_off.extract(images[0], 0, off);
  fx_on.extract(enhancer.enhance(images[0], ep).image, 0, on);

  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& img = images[i];
    auto t0 = threadCpuMs();
    orb->detectAndCompute(img, cv::noArray(), kps, desc);
    t_orb.push_back(threadCpuMsSince(t0));
    n_orb.push_back(static_cast<double>(kps.size()));

    t0 = threadCpuMs();
    const FeatureFrame f_off = fx_off.extract(img, 0, off);
    t_off.push_back(threadCpuMsSince(t0));
    det_off.push_back(f_off.stats.ms_detect);
    n_off.push_back(static_cast<double>(f_off.keypoints.size()));

    t0 = threadCpuMs();
    auto t_e = threadCpuMs();
    const EnhanceResult er = enhancer.enhance(img, ep);
    enh.push_back(threadCpuMsSince(t_e));
    const FeatureFrame f_on = fx_on.extract(er.image, 0, on);
    t_on.push_back(threadCpuMsSince(t0));
    thr.push_back(f_on.stats.ms_threshold);
    det.push_back(f_on.stats.ms_detect);
    desc_ms.push_back(f_on.stats.ms_describe);
    cull.push_back(f_on.stats.ms_cull);
    n_on.push_back(static_cast<double>(f_on.keypoints.size()));
    n_culled.push_back(f_on.stats.culled);
    pyr.push_back(f_on.stats.ms_pyramid);
    fast.push_back(f_on.stats.ms_fast);
    t0 = threadCpuMs();
    fx_on.extract(enhancer.enhance(img, ep).image, 0, ref);
    t_ref.push_back(threadCpuMsSince(t0));
    // Ablations (stage times only): enhancement with fixed thresholds; adaptive threshold on the raw image.
    det_enh_fixed.push_back(fx_off.extract(er.image, 0, off).stats.ms_detect);
    const FeatureFrame f_ra = fx_on.extract(img, 0, on);
    det_raw_adapt.push_back(f_ra.stats.ms_threshold + f_ra.stats.ms_detect);
  }

  const double m_orb = median(t_orb), m_off = median(t_off), m_on = median(t_on);
  std::printf("iraf_vo_bench_frontend: %zu frames %dx%d from %s, single thread\n", images.size(), images[0].cols,
              images[0].rows, dataset.c_str());
  std::printf("median thread-CPU ms per frame (keypoints):\n");
  std::printf("  cv::ORB::create(1000)->detectAndCompute   %7.2f  (%.0f kp)\n", m_orb, median(n_orb));
  std::printf("  ours, all IRAF modules off                %7.2f  (%.0f kp; detect+describe %.2f)\n", m_off,
              median(n_off), median(det_off));
  std::printf("  ours, all IRAF modules on (total)         %7.2f  (%.0f kp, %.0f culled; fast_path %s)\n", m_on,
              median(n_on), median(n_culled), on.fast_path ? "true" : "false");
  std::printf("    enhance                                 %7.2f\n", median(enh));
  std::printf("    threshold (eqs. 13-20)                  %7.2f\n", median(thr));
  std::printf("    detect + describe                       %7.2f\n", median(det));
  std::printf("      of which pyramid                      %7.2f\n", median(pyr));
  std::printf("      of which FAST (cell thresholds)       %7.2f\n", median(fast));
  std::printf("      of which orientation + describe       %7.2f\n", median(desc_ms));
  std::printf("    cull (eqs. 21-23)                       %7.2f\n", median(cull));
  std::printf("  ours, all on, fast_path %-5s (the other)  %7.2f  (ratio to cv::ORB %.2f)\n", ref.fast_path ? "true" : "false",
              median(t_ref), median(t_ref) / m_orb);
  std::printf("ablation: detect+describe, enhanced image, fixed 20/7       %7.2f\n", median(det_enh_fixed));
  std::printf("ablation: threshold+detect+describe, raw image, adaptive  %7.2f\n", median(det_raw_adapt));
  std::printf("ratio all-on / cv::ORB   %.2f\n", m_on / m_orb);
  std::printf("ratio all-on / all-off   %.2f\n", m_on / m_off);
  std::printf("ratio all-off / cv::ORB  %.2f\n", m_off / m_orb);
  std::printf("ratio all-on reference path / fast path  %.2f\n", on.fast_path ? median(t_ref) / m_on : m_on / median(t_ref));
  return 0;
}
