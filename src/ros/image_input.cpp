#include "iraf_vo/ros/image_input.h"

#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

ImageInput::ImageInput(const ros::NodeHandle& nh, const std::string& topic, const std::string& transport,
                       uint32_t queue_size, Callback callback)
    : nh_(nh), topic_(topic), transport_(transport.empty() ? "raw" : transport), queue_size_(queue_size),
      callback_(std::move(callback)) {}

ImageInput::~ImageInput() { shutdown(); }

bool ImageInput::usesCompressed(const std::string& topic, const std::string& transport) {
  return transport == "compressed" || endsWith(topic, "/compressed");
}

std::string ImageInput::resolvedTopic() const {
  try {
    return nh_.resolveName(topic_);  // remappings applied: `image:=/cam0/image_raw/compressed` arrives here
  } catch (const std::exception&) {  // ros::InvalidNameException: subscribe() reports it
    return topic_;
  }
}

void ImageInput::subscribe() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!active_.empty()) return;
  // The transport follows the RESOLVED topic (image_transport convention: base topic + transport). A topic ending
  // in /compressed is the compressed transport of its base topic, whatever ~image_transport says.
  const std::string resolved_topic = resolvedTopic();
  if (usesCompressed(resolved_topic, transport_)) {
    std::string resolved = resolved_topic;
    if (!endsWith(resolved, "/compressed")) {
      resolved += "/compressed";
    } else if (transport_ != "compressed" && !compressed_logged_) {
      ROS_INFO("%s is a compressed topic: subscribing with the compressed transport of %s (sensor_msgs/"
               "CompressedImage, decoded with OpenCV) instead of '%s'",
               resolved.c_str(), resolved.substr(0, resolved.size() - std::string("/compressed").size()).c_str(),
               transport_.c_str());
      compressed_logged_ = true;
    }
    try {
      compressed_sub_ = nh_.subscribe(resolved, queue_size_, &ImageInput::compressedCallback, this);
      active_ = "compressed";
      subscribed_topic_ = resolved;
    } catch (const std::exception& e) {  // ros::InvalidNameException and the like
      last_error_ = "cannot subscribe to " + resolved + ": " + e.what();
      ROS_ERROR("%s", last_error_.c_str());
    }
    return;
  }
  if (!it_) it_.reset(new image_transport::ImageTransport(nh_));
  // The transport is given explicitly: a parameter name that is never set keeps TransportHints from re-reading
  // `~image_transport` (which would bring the failed plugin back on the fallback).
  auto trySubscribe = [&](const std::string& transport) {
    const image_transport::TransportHints hints(transport, ros::TransportHints(), nh_, "iraf_vo_image_input_no_param");
    it_sub_ = it_->subscribe(topic_, queue_size_, &ImageInput::rawCallback, this, hints);
    active_ = transport;
    subscribed_topic_ = it_sub_.getTopic();
  };
  const std::string first = plugin_failed_ ? "raw" : transport_;
  try {
    trySubscribe(first);
    return;
  } catch (const std::exception& e) {  // image_transport::TransportLoadException, pluginlib, ros exceptions
    last_error_ = "image_transport '" + first + "' for topic " + nh_.resolveName(topic_) + " failed to load (" + e.what() +
                  "); falling back to raw" + (first == "raw" ? "" : " (for compressed images use ~image_transport: compressed)");
  } catch (...) {
    last_error_ = "image_transport '" + first + "' for topic " + nh_.resolveName(topic_) + " failed to load; falling back to raw";
  }
  ROS_ERROR("%s", last_error_.c_str());
  plugin_failed_ = true;
  if (first == "raw") return;
  try {
    trySubscribe("raw");
  } catch (const std::exception& e) {
    last_error_ = "image_transport 'raw' for topic " + nh_.resolveName(topic_) + " failed too: " + e.what() + "; no input";
    ROS_ERROR("%s", last_error_.c_str());
  }
}

void ImageInput::shutdown() {
  // Shut down outside the lock: roscpp waits for a running callback, which may be waiting for mutex_ in drop().
  image_transport::Subscriber it_sub;
  ros::Subscriber compressed_sub;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::swap(it_sub, it_sub_);
    std::swap(compressed_sub, compressed_sub_);
    active_.clear();
    subscribed_topic_.clear();
  }
  it_sub.shutdown();
  compressed_sub.shutdown();
}

bool ImageInput::subscribed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return !active_.empty();
}

std::string ImageInput::activeTransport() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return active_;
}

std::string ImageInput::subscribedTopic() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return subscribed_topic_;
}

std::string ImageInput::lastError() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_error_;
}

void ImageInput::drop(const std::string& problem) {
  ++dropped_;
  std::string topic;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    topic = subscribed_topic_;
    last_error_ = topic + ": " + problem + ", dropped";
  }
  ROS_ERROR_THROTTLE(5.0, "%s: %s, dropped (%zu so far)", topic.c_str(), problem.c_str(), dropped_.load());
}

void ImageInput::rawCallback(const sensor_msgs::ImageConstPtr& msg) {
  cv::Mat gray;
  std::string err;
  if (!toMono8(msg, &gray, &err)) {
    drop(err);
    return;
  }
  ++received_;
  callback_(msg->header, gray);
}

void ImageInput::compressedCallback(const sensor_msgs::CompressedImageConstPtr& msg) {
  cv::Mat gray;
  std::string err;
  if (!toMono8(*msg, &gray, &err)) {
    drop(err);
    return;
  }
  ++received_;
  callback_(msg->header, gray);
}

}  // namespace iraf_vo
