#include "iraf_vo/ros/bag_reader.h"

#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <cstring>
#include <set>

#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

struct BagImageReader::Impl {
  rosbag::Bag bag;
  std::unique_ptr<rosbag::View> view;
  rosbag::View::iterator it;
  std::string path, topic;
};

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
    if (error) *error = path + ": cannot read bag: " + e.what();
    return {};
  }
  return std::vector<std::string>(topics.begin(), topics.end());
}

bool BagImageReader::open(const std::string& path, const std::string& topic, std::string* error) {
  impl_.reset(new Impl);
  size_ = 0;
  warnings_.clear();
  error_.clear();
  impl_->path = path;
  impl_->topic = topic;
  try {
    impl_->bag.open(path, rosbag::bagmode::Read);
    impl_->view.reset(new rosbag::View(impl_->bag, rosbag::TopicQuery(topic)));
    size_ = impl_->view->size();
    impl_->it = impl_->view->begin();
  } catch (const std::exception& e) {
    if (error) *error = path + ": cannot read bag: " + e.what();
    impl_.reset(new Impl);
    return false;
  }
  if (size_ == 0) {
    std::string err;
    const std::vector<std::string> topics = imageTopics(path, &err);
    std::string list;
    for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
    if (error) *error = path + ": topic '" + topic + "' has no message (image topics in the bag: " + (list.empty() ? "none" : list) + ")";
    impl_.reset(new Impl);
    return false;
  }
  return true;
}

bool BagImageReader::next(ros::Time* stamp, cv::Mat* gray) {
  if (!impl_->view) return false;
  try {
    while (impl_->it != impl_->view->end()) {
      const rosbag::MessageInstance m = *impl_->it;  // copy: the iterator reuses its instance
      ++impl_->it;
      const std::string where = impl_->path + ": " + impl_->topic + " message at " + std::to_string(m.getTime().toSec()) + ": ";
      if (sensor_msgs::ImageConstPtr img = m.instantiate<sensor_msgs::Image>()) {
        std::string err;
        cv::Mat shared;
        if (!toMono8(img, &shared, &err)) {
          warnings_.push_back(where + err + ", skipped");
          continue;
        }
        // toMono8 may share the message buffer, which dies with `img`: own the pixels.
        *gray = shared.data == img->data.data() ? shared.clone() : shared;
        *stamp = img->header.stamp.isZero() ? m.getTime() : img->header.stamp;
        return true;
      }
      if (sensor_msgs::CompressedImageConstPtr c = m.instantiate<sensor_msgs::CompressedImage>()) {
        cv::Mat raw;
        try {
          raw = cv::imdecode(c->data, cv::IMREAD_UNCHANGED);
        } catch (const cv::Exception& e) {
          raw.release();
        }
        std::string err;
        if (raw.empty()) {
          warnings_.push_back(where + "cannot decode compressed image (format '" + c->format + "'), skipped");
          continue;
        }
        if (!toGray8(raw, gray, &err)) {
          warnings_.push_back(where + err + ", skipped");
          continue;
        }
        *stamp = c->header.stamp.isZero() ? m.getTime() : c->header.stamp;
        return true;
      }
      warnings_.push_back(where + "type " + m.getDataType() + " is not an image, skipped");
    }
  } catch (const std::exception& e) {
    error_ = impl_->path + ": bag read error: " + e.what();
    impl_->view.reset();
  }
  return false;
}

size_t aslToBag(const std::string& asl_dir, const std::string& bag_path, const AslToBagOptions& o, std::string* error,
                std::vector<std::string>* warnings) {
  AslImageReader reader;
  std::string err;
  if (!reader.open(asl_dir, &err, o.camera)) {
    if (error) *error = err;
    return 0;
  }
  if (warnings) warnings->insert(warnings->end(), reader.warnings().begin(), reader.warnings().end());
  if (o.topic.empty() || o.topic[0] != '/') {
    if (error) *error = "topic '" + o.topic + "' must be an absolute name (start with '/')";
    return 0;
  }
  size_t n = 0;
  try {
    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    if (o.compression == "bz2") bag.setCompression(rosbag::compression::BZ2);
    else if (o.compression == "lz4") bag.setCompression(rosbag::compression::LZ4);
    else if (o.compression != "none") {
      if (error) *error = "compression '" + o.compression + "': expected none, bz2 or lz4";
      return 0;
    }
    ImageEntry e;
    cv::Mat gray;
    const size_t n_warn_before = reader.warnings().size();
    while (reader.next(&e, &gray)) {
      sensor_msgs::Image msg;
      msg.header.stamp.fromNSec(static_cast<uint64_t>(e.stamp_ns));
      msg.header.frame_id = o.frame_id;
      msg.header.seq = static_cast<uint32_t>(n);
      msg.height = gray.rows;
      msg.width = gray.cols;
      msg.encoding = sensor_msgs::image_encodings::MONO8;
      msg.is_bigendian = 0;
      msg.step = gray.cols;
      msg.data.resize(static_cast<size_t>(gray.rows) * gray.cols);
      for (int r = 0; r < gray.rows; ++r) std::memcpy(&msg.data[static_cast<size_t>(r) * gray.cols], gray.ptr(r), gray.cols);
      bag.write(o.topic, msg.header.stamp, msg);
      ++n;
    }
    if (warnings)
      warnings->insert(warnings->end(), reader.warnings().begin() + n_warn_before, reader.warnings().end());
    bag.close();
  } catch (const std::exception& ex) {
    if (error) *error = bag_path + ": cannot write bag: " + ex.what();
    return 0;
  }
  if (n == 0 && error) *error = asl_dir + ": no readable image (see warnings)";
  return n;
}

}  // namespace iraf_vo
