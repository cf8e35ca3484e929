// ASL / EuRoC / TUM-VI image folder reader (ROS-free):
//   <DIR>/mav0/cam0/data.csv   "#timestamp [ns],filename" rows
//   <DIR>/mav0/cam0/data/<filename>.png
//   <DIR>/mav0/cam0/sensor.yaml  (optional camera calibration, see camera_loader.h)
// open() accepts DIR, DIR/mav0 or DIR/mav0/cam0. Images are loaded lazily as CV_8UC1.
#pragma once

#include <cstdint>
#include <fstream>
#include <mutex>
#include <set>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"

namespace iraf_vo {

/// Reads any image file as CV_8UC1: colour -> gray (BGR order), 16-bit -> value / 256 (as cv_bridge does).
/// false + *error naming the file when it is missing, unreadable or of an unsupported depth.
bool readMono8(const std::string& path, cv::Mat* gray, std::string* error);

/// Converts an in-memory image (CV_8U/CV_16U, 1/3/4 channels) to CV_8UC1. false + *error otherwise.
bool toGray8(const cv::Mat& in, cv::Mat* gray, std::string* error);

struct ImageEntry {
  int64_t stamp_ns = 0;  ///< timestamp from data.csv
  std::string path;      ///< absolute or DIR-relative path of the image file
  int csv_line = 0;      ///< line of data.csv the entry comes from (1-based; 0 when not from a csv)
  double stamp() const { return static_cast<double>(stamp_ns) * 1e-9; }  ///< seconds
};

class AslImageReader {
 public:
  /// Parses data.csv. Malformed rows (reported with their line number) and rows whose image file does not
  /// exist (reported with the file name) are skipped and listed in warnings(). Rows are sorted by time;
  /// duplicated timestamps are dropped with a warning. false + *error when the folder / csv is unusable
  /// or holds no usable row.
  bool open(const std::string& dir, std::string* error, const std::string& camera = "cam0");

  const std::vector<ImageEntry>& entries() const { return entries_; }
  size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  /// Folder holding data.csv (DIR/mav0/cam0).
  const std::string& cameraDir() const { return cam_dir_; }
  /// DIR/mav0/cam0/sensor.yaml, or "" when there is none.
  std::string sensorYamlPath() const;
  /// The root DIR (parent of mav0), e.g. to find mav0/state_groundtruth_estimate0/data.csv.
  const std::string& rootDir() const { return root_dir_; }
  /// Loads sensor.yaml with loadCamera(); nullptr + *error when absent or bad.
  CameraModelPtr loadCamera(std::string* error) const;

  /// Loads entry i as CV_8UC1. false + *error ("<data.csv>:<line>: <file>: unreadable image ...") when unreadable;
  /// each failure is counted for skippedSummary(). Never throws.
  bool loadImage(size_t i, cv::Mat* gray, std::string* error) const;

  /// Sequential iteration skipping unreadable images (each is added to warnings()). false at the end.
  bool next(ImageEntry* entry, cv::Mat* gray);
  void rewind() { cursor_ = 0; }

  /// Problems found so far (csv rows, missing / unreadable images), one message each.
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// data.csv rows skipped by open() because their image file is missing / malformed or duplicated rows.
  size_t missingCount() const { return missing_; }
  size_t badRowCount() const { return bad_rows_; }
  /// Entries that failed to load so far in loadImage() / next() (unreadable or corrupt files), each counted once.
  size_t unreadableCount() const;
  /// "" when nothing was skipped, else e.g. "3 of 600 data.csv rows skipped: 1 image file missing, 2 unreadable".
  std::string skippedSummary() const;

 private:
  std::string root_dir_, cam_dir_;
  std::vector<ImageEntry> entries_;
  std::vector<std::string> warnings_;
  size_t cursor_ = 0;
  size_t rows_ = 0, missing_ = 0, bad_rows_ = 0;
  mutable std::mutex unreadable_mutex_;  // loadImage() may run on a reader thread
  mutable std::set<size_t> unreadable_;
};

/// Writes an ASL folder readable by AslImageReader: DIR/mav0/<camera>/data.csv, data/<stamp_ns>.png (lossless)
/// and, when a camera is given, sensor.yaml (saveCamera). Stamps must be strictly increasing.
class AslImageWriter {
 public:
  /// Creates the folders and data.csv (overwrites an existing data.csv). false + *error naming the path.
  bool open(const std::string& dir, std::string* error, const CameraModel* camera = nullptr,
            const std::string& camera_name = "cam0");
  /// Writes one image (CV_8U or CV_16U, 1/3/4 channels; stored as is). false + *error on a bad image,
  /// non-increasing stamp or write failure.
  bool write(int64_t stamp_ns, const cv::Mat& image, std::string* error);
  size_t count() const { return n_; }
  /// Folder holding data.csv.
  const std::string& cameraDir() const { return cam_dir_; }
  void close() { csv_.close(); }

 private:
  std::string cam_dir_;
  std::ofstream csv_;
  size_t n_ = 0;
  int64_t last_stamp_ = -1;
};

}  // namespace iraf_vo
