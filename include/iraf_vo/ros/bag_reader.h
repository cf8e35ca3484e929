// ROS glue (libiraf_vo_ros, not the core): read images from a rosbag and write ASL folders to a rosbag.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <ros/time.h>
#include <string>
#include <vector>

namespace rosbag {
class Bag;
class View;
}  // namespace rosbag

namespace iraf_vo {

/// Iterates the sensor_msgs/Image and sensor_msgs/CompressedImage messages of one topic of a bag, converting
/// each to CV_8UC1 with toMono8 (raw) or cv::imdecode + gray conversion (compressed).
/// Messages that cannot be converted are skipped and reported in warnings(); a missing / corrupt bag gives
/// false + error (never an exception).
class BagImageReader {
 public:
  BagImageReader();
  ~BagImageReader();

  /// Opens `path` and selects `topic`. false + *error when the bag cannot be read or the topic has no
  /// Image / CompressedImage message (the error lists the image topics that exist).
  /// A truncated / unindexed bag (killed recording, cut copy) is read up to its last intact record
  /// (UnindexedBagScanner): open() succeeds and notice() = warnings()[0] says "bag X is truncated/unindexed after
  /// N messages on TOPIC (...): reading the intact part; run `rosbag reindex X` to repair it".
  bool open(const std::string& path, const std::string& topic, std::string* error);
  /// "" for a healthy bag, else the truncated/unindexed message above.
  const std::string& notice() const { return notice_; }

  /// Next converted image; stamp = header.stamp (bag receive time if the header stamp is zero).
  /// false at the end or on a read error (then error() is non-empty).
  bool next(ros::Time* stamp, cv::Mat* gray);

  /// Number of messages on the topic (including ones that may fail to convert).
  size_t size() const { return size_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// "" when no message was skipped so far, else "N of M messages on TOPIC in BAG skipped (first: ...)".
  std::string skippedSummary() const;
  /// Read error met during next(), "" otherwise.
  const std::string& error() const { return error_; }

  /// Topics of type sensor_msgs/Image or sensor_msgs/CompressedImage in a bag ("" + *error on failure).
  static std::vector<std::string> imageTopics(const std::string& path, std::string* error);

 private:
  bool openUnindexed(const std::string& path, const std::string& topic, const std::string& why, std::string* error);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  size_t size_ = 0;
  std::vector<std::string> warnings_;
  std::string error_, notice_;
};

struct AslToBagOptions {
  std::string topic = "/cam0/image_raw";
  std::string frame_id = "cam0";
  std::string camera = "cam0";        ///< camera folder inside mav0
  std::string compression = "none";   ///< none | bz2 | lz4 (bag chunk compression)
  /// raw: sensor_msgs/Image on `topic`; png | jpeg: sensor_msgs/CompressedImage on `topic`/compressed, as
  /// image_transport's compressed plugin writes it (format "mono8; png compressed mono8").
  std::string image_format = "raw";
  int jpeg_quality = 95;              ///< 1..100, image_format jpeg
  /// The right camera of a stereo folder: written too when DIR/mav0/<right_camera>/data.csv exists ("" = never),
  /// on right_topic (same image_format) with right_frame_id.
  std::string right_camera = "cam1";
  std::string right_topic = "/cam1/image_raw";
  std::string right_frame_id = "cam1";
};

/// Writes every readable image of an ASL folder (see AslImageReader) as mono8 sensor_msgs/Image (or
/// CompressedImage, see AslToBagOptions::image_format) with header.stamp from data.csv and bag time = header stamp.
/// Missing / unreadable images are skipped and listed in *warnings. A stereo folder (options.right_camera present)
/// also gets its right images (*right_written of them). Returns the number of left images written; 0 + *error when
/// nothing could be written.
size_t aslToBag(const std::string& asl_dir, const std::string& bag_path, const AslToBagOptions& options,
                std::string* error, std::vector<std::string>* warnings = nullptr, size_t* right_written = nullptr);

}  // namespace iraf_vo
