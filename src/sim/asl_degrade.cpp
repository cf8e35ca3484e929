#include "iraf_vo/sim/asl_degrade.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <opencv2/imgcodecs.hpp>  // IMREAD_* flags
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/common/error_out.h"
#include "iraf_vo/io/image_codecs.h"
#include "iraf_vo/sim/image_formation.h"
#include "iraf_vo/sim/sensor_model.h"
#include "iraf_vo/sim/sequence.h"

namespace iraf_vo {

namespace fs = std::filesystem;

namespace {
using AslRows = std::vector<std::pair<int64_t, std::string>>;
/// Forms an output image from the real image `img` (CV_8UC1); `index` is the cam0 row (cam1: the cam0 row
/// taken at the same time), `stamp_ns` the image's own timestamp.
using FormImage = std::function<void(int index, int64_t stamp_ns, const cv::Mat& img, cv::Mat* out)>;

/// For each row of `cam1`, the cam0 row nearest in time (both sorted by time as ASL csv files are).
std::vector<int> pairWithCam0(const AslRows& cam0, const AslRows& cam1) {
  std::vector<int> pair(cam1.size(), 0);
  for (size_t j = 0; j < cam1.size(); ++j) {
    const auto it = std::lower_bound(cam0.begin(), cam0.end(), cam1[j].first,
                                     [](const std::pair<int64_t, std::string>& r, int64_t t) { return r.first < t; });
    size_t k = static_cast<size_t>(it - cam0.begin());
    if (k == cam0.size() || (k > 0 && cam1[j].first - cam0[k - 1].first < cam0[k].first - cam1[j].first)) --k;
    pair[j] = static_cast<int>(k);
  }
  return pair;
}

/// Reads, forms and writes the images of the rows of in_cam (ASL camera folder) into out_cam with data.csv.
/// `index_of` maps a row to the index passed to `form`. Counts written and skipped images.
bool degradeCamera(const std::string& in_cam, const std::string& out_cam, const AslRows& rows,
                   const std::vector<int>& index_of, const FormImage& form, int* written, int* skipped,
                   std::string* error) {
  if (!makeDirs(out_cam + "/data", error)) return false;
  std::ofstream csv(out_cam + "/data.csv");
  if (!csv) {
    setError(error, out_cam + "/data.csv: cannot write");
    return false;
  }
  csv << "#timestamp [ns],filename\n";
  for (size_t i = 0; i < rows.size(); ++i) {
    const std::string src = in_cam + "/data/" + rows[i].second;
    cv::Mat img = codecs::imread(src, cv::IMREAD_UNCHANGED);
    if (!img.empty() && img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
    if (!img.empty() && img.depth() == CV_16U) img.convertTo(img, CV_8U, 1.0 / 256.0);
    if (img.empty() || img.type() != CV_8UC1) {
      std::cerr << "degrade: " << src << ": missing or unreadable image (row " << i << "), skipped\n";
      ++*skipped;
      continue;
    }
    cv::Mat out;
    form(index_of[i], rows[i].first, img, &out);
    const std::string dst = out_cam + "/data/" + rows[i].second;
    if (!codecs::imwrite(dst, out)) {
      std::cerr << "degrade: " << dst << ": cannot write, skipped\n";
      ++*skipped;
      continue;
    }
    csv << rows[i].first << ',' << rows[i].second << '\n';
    ++*written;
  }
  return true;
}

/// Degrades cam0 with `form` and, when in_dir has mav0/cam1/data.csv, cam1 with `form_right`; copies the rest.
bool degradeImages(const std::string& in_dir, const std::string& out_dir, const PhotometricParams& photometric,
                   const FormImage& form, const FormImage& form_right, DegradeReport* report, std::string* error) {
  const std::string in_cam = in_dir + "/mav0/cam0", out_cam = out_dir + "/mav0/cam0";
  const std::string in_right = in_dir + "/mav0/cam1", out_right = out_dir + "/mav0/cam1";
  if (!fs::is_regular_file(in_cam + "/data.csv")) {
    setError(error, in_dir + ": not an ASL sequence (missing " + in_cam + "/data.csv)");
    return false;
  }
  if (fs::exists(out_dir) && fs::equivalent(in_dir, out_dir)) {
    setError(error, out_dir + ": output must differ from the input");
    return false;
  }
  AslRows rows, right_rows;
  if (!readAslCsv(in_cam + "/data.csv", &rows, error)) return false;
  const bool stereo = fs::is_regular_file(in_right + "/data.csv");
  if (stereo && !readAslCsv(in_right + "/data.csv", &right_rows, error)) return false;
  if (!makeDirs(out_cam + "/data", error)) return false;

  DegradeReport rep;
  rep.images = static_cast<int>(rows.size());
  // Ground truth and calibration: copied unchanged (recursive for folders).
  std::error_code ec;
  auto copyOne = [&](const fs::path& src, const fs::path& rel) {
    const fs::path dst = fs::path(out_dir) / rel;
    fs::create_directories(dst.parent_path(), ec);
    fs::copy(src, dst, fs::copy_options::recursive | fs::copy_options::overwrite_existing, ec);
    if (ec) std::cerr << "degrade: cannot copy " << src << ": " << ec.message() << "\n";
    else rep.copied.push_back(rel.string());
  };
  for (const auto& entry : fs::directory_iterator(in_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == "mav0") continue;
    if (entry.is_regular_file() || (entry.is_directory() && name.find("groundtruth") != std::string::npos))
      copyOne(entry.path(), name);
  }
  for (const auto& entry : fs::directory_iterator(in_dir + "/mav0", ec)) {
    const std::string name = entry.path().filename().string();
    if (name == "cam0" || (stereo && name == "cam1")) continue;
    if (entry.is_regular_file() || entry.is_directory()) copyOne(entry.path(), fs::path("mav0") / name);
  }
  for (const std::string cam : {"cam0", "cam1"}) {
    if (cam == "cam1" && !stereo) break;
    for (const auto& entry : fs::directory_iterator(in_dir + "/mav0/" + cam, ec))
      if (entry.is_regular_file() && entry.path().filename() != "data.csv")
        copyOne(entry.path(), fs::path("mav0") / cam / entry.path().filename());
  }

  std::vector<int> index_of(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) index_of[i] = static_cast<int>(i);
  if (!degradeCamera(in_cam, out_cam, rows, index_of, form, &rep.written, &rep.skipped, error)) return false;
  if (stereo) {
    rep.right_images = static_cast<int>(right_rows.size());
    if (!rows.empty() &&
        !degradeCamera(in_right, out_right, right_rows, pairWithCam0(rows, right_rows), form_right, &rep.right_written,
                       &rep.right_skipped, error))
      return false;
  }
  if (!writeEventsCsv(out_dir + "/events.csv", photometric, rep.images, error)) return false;
  if (report) *report = rep;
  return true;
}
}  // namespace

bool degradeAslSequence(const std::string& in_dir, const std::string& out_dir, const PhotometricParams& photometric,
                        DegradeReport* report, std::string* error) {
  const std::string perr = validate(photometric);
  if (!perr.empty()) {
    setError(error, "photometric events: " + perr);
    return false;
  }
  // cam1: the same events at the same times, its own noise.
  PhotometricParams right_photometric = photometric;
  right_photometric.seed = mixSeed(photometric.seed ^ 0xD1B54A32D192ED03ULL);
  auto form = [&](int index, int64_t, const cv::Mat& img, cv::Mat* out) {
    applyPhotometric(img, index, photometric, out);
  };
  auto form_right = [&](int index, int64_t, const cv::Mat& img, cv::Mat* out) {
    applyPhotometric(img, index, right_photometric, out);
  };
  return degradeImages(in_dir, out_dir, photometric, form, form_right, report, error);
}

bool degradeAslSequence(const std::string& in_dir, const std::string& out_dir, const LightProfile& light,
                        DegradeReport* report, std::string* error) {
  const std::string lerr = validate(light);
  if (!lerr.empty()) {
    setError(error, "light profile '" + light.name + "': " + lerr);
    return false;
  }
  std::string cam_err;
  ImageFormation formation(light, loadCamera(in_dir + "/mav0/cam0/sensor.yaml", &cam_err));
  // cam1 takes cam0's exposure, gain and image motion of the same instant, with its own sensor noise.
  const ImageFormation right_formation(light, loadCamera(in_dir + "/mav0/cam1/sensor.yaml", &cam_err), 1);
  struct Taken {
    bool formed = false;
    Exposure exposure;
    cv::Point2d motion;
    double period = 0.05;
  };
  std::vector<Taken> taken;
  std::vector<FrameLight> lights;
  cv::Mat prev, cur;
  int64_t prev_ns = 0;
  auto form = [&](int index, int64_t stamp_ns, const cv::Mat& img, cv::Mat* out) {
    img.convertTo(cur, CV_32F);
    if (lights.empty()) formation.settle(cur, nullptr);
    cv::Point2d motion(0.0, 0.0);
    double period = 0.05;
    // The image motion of the frame, for the blur of an exposure longer than the reference.
    if (!prev.empty() && prev.size() == cur.size() &&
        formation.nextExposure().time_s > light.sensor.reference_exposure_s) {
      double response = 0.0;
      motion = cv::phaseCorrelate(prev, cur, cv::noArray(), &response);
      if (!(response > 0.05)) motion = cv::Point2d(0.0, 0.0);  // no consistent shift between the images
      const double dt = (stamp_ns - prev_ns) * 1e-9;
      if (dt > 1e-3 && dt < 1.0) period = dt;
    }
    FrameLight rec;
    formation.capture(index, cur, nullptr, out, &rec, motion, period);
    lights.push_back(rec);
    if (taken.size() <= static_cast<size_t>(index)) taken.resize(index + 1);
    taken[index] = Taken{true, rec.exposure, motion, period};
    std::swap(prev, cur);
    prev_ns = stamp_ns;
  };
  auto form_right = [&](int index, int64_t, const cv::Mat& img, cv::Mat* out) {
    // The cam0 image of that instant, or the nearest earlier one that was formed (a missing cam0 image).
    int k = std::min(index, static_cast<int>(taken.size()) - 1);
    while (k >= 0 && !taken[k].formed) --k;
    const Taken t = k >= 0 ? taken[k] : Taken{true, formation.nextExposure(), {0.0, 0.0}, 0.05};
    cv::Mat radiance;
    img.convertTo(radiance, CV_32F);
    right_formation.captureWithExposure(index, t.exposure, radiance, nullptr, out, nullptr, t.motion, t.period);
  };
  if (!degradeImages(in_dir, out_dir, light.scene, form, form_right, report, error)) return false;
  return writeExposureCsv(out_dir + "/exposure.csv", lights, error);
}

}  // namespace iraf_vo
