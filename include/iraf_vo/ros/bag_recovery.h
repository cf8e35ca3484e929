// ROS glue (libiraf_vo_ros): read the intact part of a rosbag (format 2.0) whose index is missing or cut off.
//
// rosbag's reader needs the index at the end of the file: a recording that was killed (`.bag.active`, never
// closed) or a bag cut short by a copy fails whole ("Bag unindexed", read errors). The messages themselves sit in
// chunks from the start of the file, so BagImageReader falls back to this scanner: it walks the records from the
// start and stops at the first incomplete one. Uncompressed chunks only (rosbag record's default); a bz2 / lz4 chunk
// stops the scan with a reason. `rosbag reindex X.bag` repairs the file for good.
#pragma once

#include <ros/time.h>

#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace iraf_vo {

class UnindexedBagScanner {
 public:
  /// false + *error when the file cannot be opened or is no rosbag 2.0 file.
  bool open(const std::string& path, std::string* error);

  /// Next message on `topic` (all topics when empty): its datatype ("sensor_msgs/Image"), receive time and
  /// serialized bytes (only when data is non-null). false at the end of the intact part (see stopReason()).
  bool next(const std::string& topic, std::string* datatype, ros::Time* time, std::vector<uint8_t>* data);

  /// Why the scan ended: "" (still going / complete file), e.g. "record at byte 123456 is cut off".
  const std::string& stopReason() const { return stop_reason_; }
  /// Topics seen so far, with their datatype.
  const std::map<std::string, std::string>& topics() const { return topic_types_; }

 private:
  struct Record {
    std::map<std::string, std::string> header;
    uint64_t data_pos = 0;
    uint32_t data_len = 0;
  };
  bool readRecord(uint64_t limit, Record* r);
  bool stop(const std::string& reason);

  std::ifstream in_;
  uint64_t file_size_ = 0, pos_ = 0, chunk_end_ = 0;
  std::map<uint32_t, std::string> conn_topic_;
  std::map<std::string, std::string> topic_types_;
  std::string stop_reason_;
  bool done_ = false;
};

}  // namespace iraf_vo
