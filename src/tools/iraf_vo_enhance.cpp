// iraf_vo_enhance: run the enhancement stage on one image or a folder of images.
//
//   iraf_vo_enhance INPUT OUTPUT_DIR [--method iraf|he|clahe|none] [--config FILE.yaml]
//                   [--set enhance.key=value ...] [--threads N] [--csv stats.csv] [--no-write]
//
// INPUT: an image file, a folder of images, or an ASL/EuRoC folder (the images listed in mav0/cam0/data.csv).
// Writes OUTPUT_DIR/<name>.png per image and prints per-image class/mu/t/ms and a summary. Missing / unreadable
// images are reported (file, data.csv line), skipped and counted at the end; then the exit code is 1.
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/common/file_util.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/io/image_folder.h"

namespace fs = std::filesystem;
using namespace iraf_vo;

int main(int argc, char** argv) {
  std::string input_arg, output, method, csv_path;
  int threads = 1;
  bool write = true;
  CommandLine cli("iraf_vo_enhance",
                  "Runs the enhancement stage on one image or a folder of images and writes OUTPUT_DIR/<name>.png.\n"
                  "Missing / unreadable images are reported and skipped; exit code 1 if any was skipped.");
  cli.positional("INPUT", &input_arg,
                 "image file, folder of images, or ASL folder (images listed in mav0/cam0/data.csv)");
  cli.positional("OUTPUT_DIR", &output, "where the enhanced images go (not needed with --no-write)", false);
  cli.option("--method", "M", &method, "iraf | he | clahe | none (= --set enhance.method=M)");
  cli.option("--threads", "N", &threads, 0, 256, "OpenCV threads (default 1)");
  cli.option("--csv", "stats.csv", &csv_path, "per-image class, mu, t, ms");
  cli.flag("--no-write", &write, "only the statistics, no images", false);
  cli.stageParams({"enhance"}, "enhance");
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (write && output.empty()) {
    std::cerr << "iraf_vo_enhance: OUTPUT_DIR is required (or --no-write)\n" << cli.usage();
    return 2;
  }
  PipelineParams pipeline;
  std::string err;
  if (!method.empty() && !setPipelineParam("enhance", "method", method, &pipeline, &err)) {
    std::cerr << "iraf_vo_enhance: --method: " << err << " (iraf | he | clahe | none)\n";
    return 2;
  }
  if (const int code = cli.applyStageParams(&pipeline); code >= 0) return code;
  const EnhanceParams& params = pipeline.enhance;
  cv::setNumThreads(threads <= 1 ? 0 : threads);  // 0 = OpenCV runs sequentially

  fs::path input = input_arg;
  std::vector<fs::path> files;
  std::error_code ec;
  AslImageReader asl;  // ASL folder: the images data.csv lists (missing ones reported with their line)
  const bool is_asl = fs::is_regular_file(input / "mav0" / "cam0" / "data.csv", ec) ||
                      fs::is_regular_file(input / "cam0" / "data.csv", ec) || fs::is_regular_file(input / "data.csv", ec);
  if (is_asl) {
    if (!asl.open(input.string(), &err)) {
      std::cerr << "iraf_vo_enhance: " << err << "\n";
      return 1;
    }
    for (const std::string& w : asl.warnings()) std::cerr << "iraf_vo_enhance: " << w << "\n";
    for (const ImageEntry& e : asl.entries()) files.push_back(e.path);
  } else if (fs::is_directory(input, ec)) {
    for (const auto& e : fs::directory_iterator(input, ec))
      if (e.is_regular_file() && hasImageExtension(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
  } else if (fs::is_regular_file(input, ec)) {
    files.push_back(input);
  } else {
    std::cerr << "iraf_vo_enhance: input not found: " << input << "\n";
    return 1;
  }
  if (files.empty()) {
    std::cerr << "iraf_vo_enhance: no images (png/jpg/bmp/pgm/tif) in " << input << "\n";
    return 1;
  }
  fs::path out_dir = output;
  if (write) {
    fs::create_directories(out_dir, ec);
    if (ec) {
      std::cerr << "iraf_vo_enhance: cannot create " << out_dir << ": " << ec.message() << "\n";
      return 1;
    }
  }
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) {
      std::cerr << "iraf_vo_enhance: cannot write " << csv_path << "\n";
      return 1;
    }
    csv << "file,brightness,mu,t,ms\n";
  }

  Enhancer enhancer;
  std::vector<double> ms;
  std::map<std::string, int> classes;
  int failed = 0, unreadable = 0;
  const bool verbose = files.size() <= 20;
  for (size_t k = 0; k < files.size(); ++k) {
    const fs::path& f = files[k];
    cv::Mat img;
    if (!(is_asl ? asl.loadImage(k, &img, &err) : readMono8(f.string(), &img, &err))) {
      std::cerr << "iraf_vo_enhance: " << err << ", skipped\n";
      ++failed;
      ++unreadable;
      continue;
    }
    const EnhanceResult r = enhancer.enhance(img, params);
    ms.push_back(r.ms);
    ++classes[toString(r.brightness)];
    if (verbose)
      std::printf("%s  %dx%d  %-6s mu %6.1f  t %+6.2f  %6.2f ms\n", f.filename().c_str(), img.cols, img.rows,
                  toString(r.brightness), r.mu, r.t, r.ms);
    if (csv) csv << f.filename().string() << "," << toString(r.brightness) << "," << r.mu << "," << r.t << "," << r.ms << "\n";
    if (write) {
      const fs::path out = out_dir / (f.stem().string() + ".png");
      if (!cv::imwrite(out.string(), r.image)) {
        std::cerr << "iraf_vo_enhance: cannot write " << out << "\n";
        ++failed;
      }
    }
  }
  if (!ms.empty()) {
    std::vector<double> s = ms;
    std::sort(s.begin(), s.end());
    std::printf("enhanced %zu images (method %s, %d thread%s): median %.3f ms, p95 %.3f ms; dim %d, normal %d, bright %d\n",
                ms.size(), toString(params.method), std::max(threads, 1), threads > 1 ? "s" : "", s[s.size() / 2],
                s[std::min(s.size() - 1, s.size() * 95 / 100)], classes["dim"], classes["normal"], classes["bright"]);
    if (write) std::printf("output: %s\n", fs::absolute(out_dir).c_str());
  }
  const std::string skipped = asl.skippedSummary();  // ASL: counts the missing rows too
  if (!skipped.empty()) std::cerr << "iraf_vo_enhance: " << skipped << "\n";
  else if (unreadable) std::cerr << "iraf_vo_enhance: " << unreadable << " of " << files.size() << " images skipped (unreadable)\n";
  if (is_asl) failed += static_cast<int>(asl.missingCount() + asl.badRowCount());
  if (failed && ms.empty()) std::cerr << "iraf_vo_enhance: no image could be read\n";
  return failed ? 1 : 0;
}
