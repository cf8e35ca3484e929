#include "iraf_vo/ros/bag_reader.h"

#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <boost/make_shared.hpp>

#include <cstring>
#include <set>

#include "iraf_vo/common/file_util.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/ros/bag_recovery.h"
#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

struct BagImageReader::Impl {
  rosbag::Bag bag;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  std::unique_ptr<UnindexedBagScanner> scanner;  // set when the bag has no usable index (truncated / unindexed)
  std::string path, topic;
};

namespace {

/// Image or CompressedImage (either may be null) -> CV_8UC1 owning its pixels; false + warning otherwise.
bool convert(const sensor_msgs::ImageConstPtr& img, const sensor_msgs::CompressedImageConstPtr& c,
             const ros::Time& receive_time, const std::string& where, ros::Time* stamp, cv::Mat* gray,
             std::vector<std::string>* warnings) {
  std::string err;
  if (img) {
    cv::Mat shared;
    if (!toMono8(img, &shared, &err)) {
      warnings->push_back(where + err + ", skipped");
      return false;
    }
    // toMono8 may share the message buffer, which dies with `img`: own the pixels.
    *gray = shared.data == img->data.data() ? shared.clone() : shared;
    *stamp = img->header.stamp.isZero() ? receive_time : img->header.stamp;
    return true;
  }
  if (!toMono8(*c, gray, &err)) {
    warnings->push_back(where + err + ", skipped");
    return false;
  }
  *stamp = c->header.stamp.isZero() ? receive_time : c->header.stamp;
  return true;
}

template <typename M>
boost::shared_ptr<M> deserialize(std::vector<uint8_t>& bytes) {
  auto msg = boost::make_shared<M>();
  ros::serialization::IStream stream(bytes.data(), static_cast<uint32_t>(bytes.size()));
  ros::serialization::deserialize(stream, *msg);
  return msg;
}

std::string joinTopics(const std::vector<std::string>& topics) {
  std::string list;
  for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
  return list.empty() ? "none" : list;
}

}  // namespace

BagImageReader::BagImageReader() : impl_(new Impl) {}
BagImageReader::~BagImageReader() = default;

std::vector<std::string> BagImageReader::imageTopics(const std::string& path, std::string* error) {
  std::set<std::string> topics;
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::ConnectionInfo* c : view.getConnections()) {
      if (c->datatype == "sensor_msgs/Image" || c->datatype == "sensor_msgs/CompressedImage") topics.insert(c->topic);
    }
  } catch (const std::exception& e) {
    // No usable index: the topics of the intact part.
    UnindexedBagScanner scanner;
    if (!scanner.open(path, nullptr)) {
      if (error) *error = path + ": cannot read bag: " + e.what();
      return {};
    }
    while (scanner.next("", nullptr, nullptr, nullptr)) {
    }
    for (const auto& kv : scanner.topics())
      if (kv.second == "sensor_msgs/Image" || kv.second == "sensor_msgs/CompressedImage") topics.insert(kv.first);
  }
  return std::vector<std::string>(topics.begin(), topics.end());
}

bool BagImageReader::openUnindexed(const std::string& path, const std::string& topic, const std::string& why,
                                   std::string* error) {
  auto fail = [&](const std::string& msg) {
    if (error) *error = path + ": cannot read bag: " + why + msg;
    impl_.reset(new Impl);
    return false;
  };
  UnindexedBagScanner count;
  if (!count.open(path, nullptr)) return fail("");
  size_t n = 0;
  while (count.next(topic, nullptr, nullptr, nullptr)) ++n;
  const std::string reason = count.stopReason().empty() ? "no index" : count.stopReason();
  if (n == 0) {
    std::vector<std::string> topics;
    for (const auto& kv : count.topics()) topics.push_back(kv.first + " (" + kv.second + ")");
    return fail("; its intact part (" + reason + ") has no message on '" + topic + "' (topics: " + joinTopics(topics) +
                "); try `rosbag reindex " + path + "`");
  }
  impl_->scanner.reset(new UnindexedBagScanner);
  impl_->scanner->open(path, nullptr);
  size_ = n;
  notice_ = "bag " + path + " is truncated/unindexed after " + std::to_string(n) + " messages on " + topic + " (" +
            reason + "): reading the intact part; run `rosbag reindex " + path + "` to repair it";
  warnings_.push_back(notice_);
  return true;
}

bool BagImageReader::open(const std::string& path, const std::string& topic, std::string* error) {
  impl_.reset(new Impl);
  size_ = 0;
  warnings_.clear();
  error_.clear();
  notice_.clear();
  impl_->path = path;
  impl_->topic = topic;
  try {
    impl_->bag.open(path, rosbag::bagmode::Read);
    impl_->view.reset(new rosbag::View(impl_->bag, rosbag::TopicQuery(topic)));
    size_ = impl_->view->size();
    impl_->it = impl_->view->begin();
  } catch (const std::exception& e) {
    impl_.reset(new Impl);
    impl_->path = path;
    impl_->topic = topic;
    return openUnindexed(path, topic, e.what(), error);
  }
  if (size_ == 0) {
    std::string err;
    if (error) *error = path + ": topic '" + topic + "' has no message (image topics in the bag: " + joinTopics(imageTopics(path, &err)) + ")";
    impl_.reset(new Impl);
    return false;
  }
  return true;
}

std::string BagImageReader::skippedSummary() const {
  const size_t skipped = warnings_.size() - (notice_.empty() ? 0 : 1);
  if (skipped == 0) return "";
  return std::to_string(skipped) + " of " + std::to_string(size_) + " messages on " + impl_->topic + " in " + impl_->path +
         " skipped (first: " + warnings_[notice_.empty() ? 0 : 1] + ")";
}

bool BagImageReader::next(ros::Time* stamp, cv::Mat* gray) {
  if (impl_->scanner) {
    std::string datatype;
    ros::Time t;
    std::vector<uint8_t> bytes;
    while (impl_->scanner->next(impl_->topic, &datatype, &t, &bytes)) {
      const std::string where = impl_->path + ": " + impl_->topic + " message at " + std::to_string(t.toSec()) + ": ";
      try {
        if (datatype == "sensor_msgs/Image" &&
            convert(deserialize<sensor_msgs::Image>(bytes), nullptr, t, where, stamp, gray, &warnings_))
          return true;
        if (datatype == "sensor_msgs/CompressedImage" &&
            convert(nullptr, deserialize<sensor_msgs::CompressedImage>(bytes), t, where, stamp, gray, &warnings_))
          return true;
        if (datatype != "sensor_msgs/Image" && datatype != "sensor_msgs/CompressedImage")
          warnings_.push_back(where + "type " + datatype + " is not an image, skipped");
      } catch (const std::exception& e) {
        warnings_.push_back(where + "cannot deserialize (" + e.what() + "), skipped");
      }
    }
    return false;
  }
  if (!impl_->view) return false;
  try {
    while (impl_->it != impl_->view->end()) {
      const rosbag::MessageInstance m = *impl_->it;  // copy: the iterator reuses its instance
      ++impl_->it;
      const std::string where = impl_->path + ": " + impl_->topic + " message at " + std::to_string(m.getTime().toSec()) + ": ";
      sensor_msgs::ImageConstPtr img = m.instantiate<sensor_msgs::Image>();
      sensor_msgs::CompressedImageConstPtr c = img ? sensor_msgs::CompressedImageConstPtr() : m.instantiate<sensor_msgs::CompressedImage>();
      if (!img && !c) {
        warnings_.push_back(where + "type " + m.getDataType() + " is not an image, skipped");
        continue;
      }
      if (convert(img, c, m.getTime(), where, stamp, gray, &warnings_)) return true;
    }
  } catch (const std::exception& e) {
    error_ = impl_->path + ": bag read error: " + e.what() + " (truncated or corrupt? try `rosbag reindex " + impl_->path + "`)";
    impl_->view.reset();
  }
  return false;
}

namespace {

/// Writes the readable images of `reader` on `topic` (raw) or `topic`/compressed. Throws on bag errors; false +
/// *error when an image cannot be encoded.
bool writeCameraImages(AslImageReader* reader, rosbag::Bag* bag, const std::string& topic, const std::string& frame_id,
                       const AslToBagOptions& o, size_t* n, std::string* error) {
  const bool compressed = o.image_format != "raw";
  const std::vector<int> encode_params =
      o.image_format == "jpeg" ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality} : std::vector<int>{};
  ImageEntry e;
  cv::Mat gray;
  uint32_t seq = 0;
  while (reader->next(&e, &gray)) {
    if (compressed) {
      sensor_msgs::CompressedImage msg;
      msg.header.stamp.fromNSec(static_cast<uint64_t>(e.stamp_ns));
      msg.header.frame_id = frame_id;
      msg.header.seq = seq++;
      msg.format = "mono8; " + o.image_format + " compressed mono8";
      if (!cv::imencode(o.image_format == "png" ? ".png" : ".jpg", gray, msg.data, encode_params)) {
        if (error) *error = e.path + ": cannot encode as " + o.image_format;
        return false;
      }
      bag->write(topic + "/compressed", msg.header.stamp, msg);
      ++*n;
      continue;
    }
    sensor_msgs::Image msg;
    msg.header.stamp.fromNSec(static_cast<uint64_t>(e.stamp_ns));
    msg.header.frame_id = frame_id;
    msg.header.seq = seq++;
    msg.height = gray.rows;
    msg.width = gray.cols;
    msg.encoding = sensor_msgs::image_encodings::MONO8;
    msg.is_bigendian = 0;
    msg.step = gray.cols;
    msg.data.resize(static_cast<size_t>(gray.rows) * gray.cols);
    for (int r = 0; r < gray.rows; ++r) std::memcpy(&msg.data[static_cast<size_t>(r) * gray.cols], gray.ptr(r), gray.cols);
    bag->write(topic, msg.header.stamp, msg);
    ++*n;
  }
  return true;
}

bool absoluteTopic(const std::string& topic, std::string* error) {
  if (!topic.empty() && topic[0] == '/') return true;
  if (error) *error = "topic '" + topic + "' must be an absolute name (start with '/')";
  return false;
}

}  // namespace

size_t aslToBag(const std::string& asl_dir, const std::string& bag_path, const AslToBagOptions& o, std::string* error,
                std::vector<std::string>* warnings, size_t* right_written) {
  if (right_written) *right_written = 0;
  AslImageReader reader;
  std::string err;
  if (!reader.open(asl_dir, &err, o.camera)) {
    if (error) *error = err;
    return 0;
  }
  if (warnings) warnings->insert(warnings->end(), reader.warnings().begin(), reader.warnings().end());
  if (!absoluteTopic(o.topic, error)) return 0;
  if (o.image_format != "png" && o.image_format != "jpeg" && o.image_format != "raw") {
    if (error) *error = "image format '" + o.image_format + "': expected raw, png or jpeg";
    return 0;
  }
  if (o.jpeg_quality < 1 || o.jpeg_quality > 100) {
    if (error) *error = "jpeg quality " + std::to_string(o.jpeg_quality) + ": expected 1..100";
    return 0;
  }
  // The right camera of a stereo folder (DIR/mav0/<right_camera>/data.csv), when there is one.
  AslImageReader right;
  bool stereo = false;
  if (!o.right_camera.empty() && o.right_camera != o.camera &&
      isFile(reader.rootDir() + "/mav0/" + o.right_camera + "/data.csv")) {
    if (!right.open(reader.rootDir(), &err, o.right_camera)) {
      if (error) *error = err;
      return 0;
    }
    if (!absoluteTopic(o.right_topic, error)) return 0;
    if (warnings) warnings->insert(warnings->end(), right.warnings().begin(), right.warnings().end());
    stereo = true;
  }
  size_t n = 0, n_right = 0;
  try {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    if (o.compression == "bz2") bag.setCompression(rosbag::compression::BZ2);
    else if (o.compression == "lz4") bag.setCompression(rosbag::compression::LZ4);
    else if (o.compression != "none") {
      if (error) *error = "compression '" + o.compression + "': expected none, bz2 or lz4";
      return 0;
    }
    const size_t n_warn_before = reader.warnings().size();
    if (!writeCameraImages(&reader, &bag, o.topic, o.frame_id, o, &n, error)) return 0;
    if (warnings)
      warnings->insert(warnings->end(), reader.warnings().begin() + n_warn_before, reader.warnings().end());
    if (stereo) {
      const size_t right_warn_before = right.warnings().size();
      if (!writeCameraImages(&right, &bag, o.right_topic, o.right_frame_id, o, &n_right, error)) return 0;
      if (warnings)
        warnings->insert(warnings->end(), right.warnings().begin() + right_warn_before, right.warnings().end());
    }
    bag.close();
  } catch (const std::exception& ex) {
    if (error) *error = bag_path + ": cannot write bag: " + ex.what();
    return 0;
  }
  if (n == 0 && error) *error = asl_dir + ": no readable image (see warnings)";
  if (right_written) *right_written = n_right;
  return n;
}

}  // namespace iraf_vo
