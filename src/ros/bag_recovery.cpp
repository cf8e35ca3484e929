#include "iraf_vo/ros/bag_recovery.h"

#include <cstring>

namespace iraf_vo {

namespace {

// rosbag 2.0 record ops (http://wiki.ros.org/Bags/Format/2.0).
constexpr uint8_t kOpMessageData = 0x02;
constexpr uint8_t kOpChunk = 0x05;
constexpr uint8_t kOpConnection = 0x07;
const char kMagic[] = "#ROSBAG V2.0\n";

uint32_t le32(const std::string& s, size_t off = 0) {
  uint32_t v = 0;
  if (s.size() >= off + 4) std::memcpy(&v, s.data() + off, 4);  // rosbag is little-endian, as is every ROS host
  return v;
}

/// Header fields "name=value" each preceded by a uint32 length. false when the lengths do not add up.
bool parseFields(const std::string& buf, std::map<std::string, std::string>* fields) {
  size_t p = 0;
  while (p < buf.size()) {
    if (p + 4 > buf.size()) return false;
    const uint32_t len = le32(buf, p);
    p += 4;
    if (len > buf.size() - p) return false;
    const std::string f = buf.substr(p, len);
    p += len;
    const size_t eq = f.find('=');
    if (eq == std::string::npos) return false;
    (*fields)[f.substr(0, eq)] = f.substr(eq + 1);
  }
  return true;
}

}  // namespace

bool UnindexedBagScanner::open(const std::string& path, std::string* error) {
  in_.close();
  in_.clear();
  conn_topic_.clear();
  topic_types_.clear();
  stop_reason_.clear();
  done_ = false;
  chunk_end_ = 0;
  in_.open(path, std::ios::binary);
  if (!in_) {
    if (error) *error = path + ": cannot open";
    return false;
  }
  in_.seekg(0, std::ios::end);
  file_size_ = static_cast<uint64_t>(in_.tellg());
  in_.seekg(0);
  char magic[sizeof(kMagic) - 1] = {};
  in_.read(magic, sizeof(magic));
  if (!in_ || std::memcmp(magic, kMagic, sizeof(magic)) != 0) {
    if (error) *error = path + ": not a rosbag 2.0 file (no '#ROSBAG V2.0' line)";
    return false;
  }
  pos_ = sizeof(magic);
  return true;
}

bool UnindexedBagScanner::stop(const std::string& reason) {
  done_ = true;
  stop_reason_ = reason;
  return false;
}

bool UnindexedBagScanner::readRecord(uint64_t limit, Record* r) {
  const uint64_t start = pos_;
  std::string len4(4, '\0');
  if (pos_ + 4 > limit) return false;
  in_.seekg(static_cast<std::streamoff>(pos_));
  in_.read(&len4[0], 4);
  const uint32_t header_len = le32(len4);
  if (!in_ || header_len > (16u << 20) || pos_ + 8 + header_len > limit) return false;
  std::string header(header_len, '\0');
  in_.read(&header[0], header_len);
  in_.read(&len4[0], 4);
  r->data_len = le32(len4);
  r->data_pos = pos_ + 8 + header_len;
  r->header.clear();
  if (!in_ || !parseFields(header, &r->header) || r->header["op"].size() != 1) {
    stop("record at byte " + std::to_string(start) + " has a corrupt header");
    return false;
  }
  pos_ = r->data_pos + r->data_len;  // may lie beyond `limit`: the caller checks
  return true;
}

bool UnindexedBagScanner::next(const std::string& topic, std::string* datatype, ros::Time* time,
                               std::vector<uint8_t>* data) {
  while (!done_) {
    if (chunk_end_ != 0 && pos_ >= chunk_end_) {
      pos_ = chunk_end_;
      chunk_end_ = 0;
    }
    const uint64_t limit = chunk_end_ != 0 ? chunk_end_ : file_size_;
    if (pos_ >= file_size_) return stop("");
    const uint64_t start = pos_;
    Record r;
    if (!readRecord(limit, &r)) {
      if (done_) return false;
      return stop("record at byte " + std::to_string(start) + " is cut off (file ends at byte " +
                  std::to_string(file_size_) + ")");
    }
    const uint8_t op = static_cast<uint8_t>(r.header["op"][0]);
    if (op == kOpChunk) {
      const std::string compression = r.header["compression"];
      if (compression != "none")
        return stop("chunk at byte " + std::to_string(start) + " is " + compression +
                    "-compressed (only uncompressed chunks can be read without the index)");
      // A chunk rosbag record never finished has sizes 0: its records run to the end of the file.
      chunk_end_ = r.data_len == 0 ? file_size_ : std::min<uint64_t>(r.data_pos + r.data_len, file_size_);
      pos_ = r.data_pos;
      continue;
    }
    if (r.data_pos + r.data_len > limit)
      return stop("record at byte " + std::to_string(start) + " is cut off (file ends at byte " +
                  std::to_string(file_size_) + ")");
    if (op == kOpConnection) {
      const uint32_t conn = le32(r.header["conn"]);
      std::string body(r.data_len, '\0');
      in_.seekg(static_cast<std::streamoff>(r.data_pos));
      in_.read(&body[0], r.data_len);
      std::map<std::string, std::string> fields;
      if (!in_ || !parseFields(body, &fields)) return stop("connection record at byte " + std::to_string(start) + " is corrupt");
      conn_topic_[conn] = r.header["topic"];
      topic_types_[r.header["topic"]] = fields["type"];
      continue;
    }
    if (op != kOpMessageData) continue;  // bag header, index data, chunk info
    const auto c = conn_topic_.find(le32(r.header["conn"]));
    if (c == conn_topic_.end() || (!topic.empty() && c->second != topic)) continue;
    const std::string& t = r.header["time"];
    if (time) *time = ros::Time(le32(t, 0), le32(t, 4));
    if (datatype) *datatype = topic_types_[c->second];
    if (data) {
      data->resize(r.data_len);
      in_.seekg(static_cast<std::streamoff>(r.data_pos));
      in_.read(reinterpret_cast<char*>(data->data()), r.data_len);
      if (!in_) return stop("message at byte " + std::to_string(start) + " cannot be read");
    }
    return true;
  }
  return false;
}

}  // namespace iraf_vo
