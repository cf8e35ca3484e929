#include "iraf_vo/io/image_folder.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/common/file_util.h"
#include "iraf_vo/io/image_codecs.h"
#include "iraf_vo/io/png_gray8.h"

namespace iraf_vo {

namespace {

std::string stripSlash(std::string s) {
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return s;
}
std::string baseName(const std::string& p) {
  const size_t k = p.find_last_of('/');
  return k == std::string::npos ? p : p.substr(k + 1);
}
std::string parent(const std::string& p) {
  const size_t k = p.find_last_of('/');
  if (k == std::string::npos) return ".";
  return k == 0 ? "/" : p.substr(0, k);
}

}  // namespace

bool toGray8(const cv::Mat& in, cv::Mat* gray, std::string* error) {
  if (in.empty()) {
    if (error) *error = "empty image";
    return false;
  }
  cv::Mat src = in;
  if (src.depth() == CV_16U) {
    src.convertTo(src, CV_8U, 1.0 / 256.0);
  } else if (src.depth() != CV_8U) {
    if (error) *error = "unsupported image depth (OpenCV depth " + std::to_string(in.depth()) + "; need 8 or 16 bit)";
    return false;
  }
  switch (src.channels()) {
    case 1: *gray = src; break;
    case 3: cv::cvtColor(src, *gray, cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(src, *gray, cv::COLOR_BGRA2GRAY); break;
    default:
      if (error) *error = "unsupported channel count " + std::to_string(src.channels());
      return false;
  }
  return true;
}

bool readMono8(const std::string& path, cv::Mat* gray, std::string* error) {
  if (!isFile(path)) {
    if (error) *error = path + ": image file missing";
    return false;
  }
  thread_local std::vector<uint8_t> bytes;  // the file, reused from frame to frame
  if (!readFileBytes(path, &bytes)) {
    if (error) *error = path + ": cannot read image file";
    return false;
  }
  std::string opencv_error;
  const cv::Mat raw = decodeImage(bytes.data(), bytes.size(), &opencv_error);
  if (!opencv_error.empty()) {
    if (error) *error = path + ": OpenCV cannot read image: " + opencv_error;
    return false;
  }
  if (raw.empty()) {
    if (error) *error = path + ": unreadable image (corrupt or unknown format)";
    return false;
  }
  std::string e;
  if (!toGray8(raw, gray, &e)) {
    if (error) *error = path + ": " + e;
    return false;
  }
  return true;
}

bool AslImageReader::open(const std::string& dir_in, std::string* error, const std::string& camera) {
  entries_.clear();
  warnings_.clear();
  cursor_ = 0;
  rows_ = missing_ = bad_rows_ = 0;
  {
    std::lock_guard<std::mutex> lock(unreadable_mutex_);
    unreadable_.clear();
  }
  const std::string dir = stripSlash(dir_in);
  // Accept DIR, DIR/mav0 and DIR/mav0/<camera> (anything holding data.csv directly).
  if (isFile(dir + "/data.csv")) {
    cam_dir_ = dir;
    root_dir_ = baseName(parent(dir)) == "mav0" ? parent(parent(dir)) : parent(dir);
  } else if (isFile(dir + "/" + camera + "/data.csv")) {
    cam_dir_ = dir + "/" + camera;
    root_dir_ = parent(dir);
  } else if (isFile(dir + "/mav0/" + camera + "/data.csv")) {
    cam_dir_ = dir + "/mav0/" + camera;
    root_dir_ = dir;
  } else {
    if (error)
      *error = dir + ": no ASL image folder (looked for data.csv in " + dir + ", " + dir + "/" + camera + ", " + dir +
               "/mav0/" + camera + ")" + (isDir(dir) ? "" : " - directory does not exist");
    return false;
  }
  const std::string csv = cam_dir_ + "/data.csv";
  std::ifstream in(csv);
  if (!in) {
    if (error) *error = csv + ": cannot open";
    return false;
  }
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    ++rows_;
    const size_t comma = t.find(',');
    const std::string where = csv + ":" + std::to_string(line_no) + ": ";
    if (comma == std::string::npos) {
      warnings_.push_back(where + "malformed row '" + t + "' (expected 'timestamp_ns,filename'), skipped");
      ++bad_rows_;
      continue;
    }
    const std::string ts = trim(t.substr(0, comma));
    const std::string name = trim(t.substr(comma + 1));
    bool digits = !ts.empty() && ts.size() <= 19 && std::all_of(ts.begin(), ts.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
    int64_t stamp_ns = 0;  // from_chars: a 19-digit value above INT64_MAX is malformed (std::stoll threw)
    if (digits) {
      const auto res = std::from_chars(ts.data(), ts.data() + ts.size(), stamp_ns);
      digits = res.ec == std::errc() && res.ptr == ts.data() + ts.size();
    }
    if (!digits || name.empty() || name.find(',') != std::string::npos) {
      warnings_.push_back(where + "malformed row '" + t + "' (expected 'timestamp_ns,filename'), skipped");
      ++bad_rows_;
      continue;
    }
    ImageEntry e;
    e.stamp_ns = stamp_ns;
    e.path = cam_dir_ + "/data/" + name;
    e.csv_line = line_no;
    if (!isFile(e.path)) {
      warnings_.push_back(where + "image file missing: " + e.path + ", skipped");
      ++missing_;
      continue;
    }
    entries_.push_back(e);
  }
  std::stable_sort(entries_.begin(), entries_.end(),
                   [](const ImageEntry& a, const ImageEntry& b) { return a.stamp_ns < b.stamp_ns; });
  std::vector<ImageEntry> unique;
  for (const ImageEntry& e : entries_) {
    if (!unique.empty() && unique.back().stamp_ns == e.stamp_ns) {
      warnings_.push_back(csv + ":" + std::to_string(e.csv_line) + ": duplicate timestamp " + std::to_string(e.stamp_ns) +
                          " (" + e.path + "), skipped");
      ++bad_rows_;
      continue;
    }
    unique.push_back(e);
  }
  entries_.swap(unique);
  if (entries_.empty()) {
    if (error) *error = csv + ": no usable image rows" + (warnings_.empty() ? "" : " (first problem: " + warnings_.front() + ")");
    return false;
  }
  return true;
}

std::string AslImageReader::sensorYamlPath() const {
  const std::string p = cam_dir_ + "/sensor.yaml";
  return isFile(p) ? p : std::string();
}

CameraModelPtr AslImageReader::loadCamera(std::string* error) const {
  const std::string p = sensorYamlPath();
  if (p.empty()) {
    if (error) *error = cam_dir_ + "/sensor.yaml: missing";
    return nullptr;
  }
  return iraf_vo::loadCamera(p, error);
}

bool AslImageReader::loadImage(size_t i, cv::Mat* gray, std::string* error) const {
  if (i >= entries_.size()) {
    if (error) *error = "image index " + std::to_string(i) + " out of range (" + std::to_string(entries_.size()) + " images)";
    return false;
  }
  std::string err;
  if (readMono8(entries_[i].path, gray, &err)) return true;
  {
    std::lock_guard<std::mutex> lock(unreadable_mutex_);
    unreadable_.insert(i);
  }
  if (error) *error = cam_dir_ + "/data.csv:" + std::to_string(entries_[i].csv_line) + ": " + err;
  return false;
}

size_t AslImageReader::unreadableCount() const {
  std::lock_guard<std::mutex> lock(unreadable_mutex_);
  return unreadable_.size();
}

std::string AslImageReader::skippedSummary() const {
  const size_t unreadable = unreadableCount();
  if (missing_ + bad_rows_ + unreadable == 0) return "";
  std::vector<std::string> parts;
  if (missing_) parts.push_back(std::to_string(missing_) + " image file" + (missing_ > 1 ? "s" : "") + " missing");
  if (unreadable) parts.push_back(std::to_string(unreadable) + " unreadable");
  if (bad_rows_) parts.push_back(std::to_string(bad_rows_) + " malformed / duplicate row" + (bad_rows_ > 1 ? "s" : ""));
  std::string s = std::to_string(missing_ + bad_rows_ + unreadable) + " of " + std::to_string(rows_) + " rows of " +
                  cam_dir_ + "/data.csv skipped: ";
  for (size_t k = 0; k < parts.size(); ++k) s += (k ? ", " : "") + parts[k];
  return s;
}

bool AslImageReader::next(ImageEntry* entry, cv::Mat* gray) {
  while (cursor_ < entries_.size()) {
    const size_t i = cursor_++;
    std::string err;
    if (loadImage(i, gray, &err)) {
      *entry = entries_[i];
      return true;
    }
    warnings_.push_back(err + ", skipped");
  }
  return false;
}

bool AslImageWriter::open(const std::string& dir, std::string* error, const CameraModel* camera,
                          const std::string& camera_name) {
  n_ = 0;
  last_stamp_ = -1;
  csv_.close();
  cam_dir_ = stripSlash(dir) + "/mav0/" + camera_name;
  std::error_code ec;
  std::filesystem::create_directories(cam_dir_ + "/data", ec);
  if (ec) {
    if (error) *error = cam_dir_ + "/data: cannot create directory: " + ec.message();
    return false;
  }
  csv_.open(cam_dir_ + "/data.csv", std::ios::trunc);
  if (!csv_) {
    if (error) *error = cam_dir_ + "/data.csv: cannot open for writing";
    return false;
  }
  csv_ << "#timestamp [ns],filename\n";
  if (camera) {
    std::string err;
    if (!saveCamera(*camera, cam_dir_ + "/sensor.yaml", &err)) {
      if (error) *error = err;
      return false;
    }
  }
  return true;
}

bool AslImageWriter::write(int64_t stamp_ns, const cv::Mat& image, std::string* error) {
  if (!csv_.is_open()) {
    if (error) *error = "AslImageWriter: not open";
    return false;
  }
  if (image.empty() || (image.depth() != CV_8U && image.depth() != CV_16U) ||
      (image.channels() != 1 && image.channels() != 3 && image.channels() != 4)) {
    if (error) *error = cam_dir_ + ": image for stamp " + std::to_string(stamp_ns) + " is empty or not 8/16-bit 1/3/4-channel";
    return false;
  }
  if (stamp_ns <= last_stamp_) {
    if (error) *error = cam_dir_ + ": stamp " + std::to_string(stamp_ns) + " ns not after the previous " + std::to_string(last_stamp_);
    return false;
  }
  const std::string name = std::to_string(stamp_ns) + ".png";
  const std::string path = cam_dir_ + "/data/" + name;
  bool ok = false;
  std::string why;
  try {
    ok = codecs::imwrite(path, image);
  } catch (const cv::Exception& e) {
    ok = false;
    why = std::string(": ") + e.what();
  }
  if (!ok) {
    if (error) *error = path + ": cannot write image" + why;
    return false;
  }
  csv_ << stamp_ns << "," << name << "\n";
  csv_.flush();
  if (!csv_) {
    if (error) *error = cam_dir_ + "/data.csv: write failed";
    return false;
  }
  last_stamp_ = stamp_ns;
  ++n_;
  return true;
}

}  // namespace iraf_vo
