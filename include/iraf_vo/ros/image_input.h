// ROS glue (libiraf_vo_ros): one camera image input for a nodelet, whatever the transport.
//
// Debian 12 ships only image_transport's `raw` plugin, yet most recorded bags carry `.../image_raw/compressed`.
// ImageInput subscribes
//  - to `<topic>/compressed` (sensor_msgs/CompressedImage, decoded with OpenCV: jpeg / png) when the transport is
//    "compressed", or to `topic` itself when its RESOLVED name (after remapping, e.g. a launch file's
//    `image:=/cam0/image_raw/compressed`) ends in "/compressed", whatever the transport (logged once);
//  - otherwise through image_transport with that transport ("raw", or a plugin such as "theora"). A plugin that
//    fails to load gives one ROS_ERROR naming it and the topic, and the input falls back to "raw": the nodelet
//    manager never aborts.
// Every image reaches the callback as CV_8UC1 (raw: toMono8 encodings; compressed: 8/16 bit, mono / colour).
// Unusable messages are dropped with a throttled ROS_ERROR naming the topic and the problem, and counted.
//
//   input_ = std::make_unique<ImageInput>(getNodeHandle(), "image", pnh.param("image_transport", "raw"s), 5,
//                                         [this](const std_msgs::Header& h, const cv::Mat& gray) { ... });
//   input_->subscribe();   // in the connect callback when the first output subscriber appears
//   input_->shutdown();    // when the last one leaves (lazy subscription)
#pragma once

#include <image_transport/image_transport.h>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/Header.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>

namespace iraf_vo {

class ImageInput {
 public:
  /// `mono8` may share the message's buffer: valid during the call only (clone it to keep it).
  using Callback = std::function<void(const std_msgs::Header& header, const cv::Mat& mono8)>;

  /// nh: node handle the topic is resolved in (a nodelet's getNodeHandle(); remappings apply to `topic`).
  /// transport: the `~image_transport` value ("raw", "compressed", "theora", ...; "" = "raw").
  ImageInput(const ros::NodeHandle& nh, const std::string& topic, const std::string& transport, uint32_t queue_size,
             Callback callback);
  ~ImageInput();
  ImageInput(const ImageInput&) = delete;
  ImageInput& operator=(const ImageInput&) = delete;

  /// Subscribes (no-op when subscribed). Never throws.
  void subscribe();
  /// Unsubscribes (no-op when not subscribed). Call it before destroying what the callback uses.
  void shutdown();
  bool subscribed() const;

  /// Transport in use: "compressed" (OpenCV decoding), "raw" (also after a plugin failed to load) or the plugin.
  std::string activeTransport() const;
  /// Resolved topic subscribed to, e.g. "/cam0/image_raw/compressed" ("" when not subscribed).
  std::string subscribedTopic() const;
  /// Images delivered to the callback / messages dropped (bad encoding, undecodable data) so far.
  size_t received() const { return received_; }
  size_t dropped() const { return dropped_; }
  /// Last problem (plugin load failure or dropped message), "" if none.
  std::string lastError() const;

  /// True when (topic, transport) selects the built-in CompressedImage decoding: transport "compressed" or a
  /// topic ending in "/compressed". subscribe() asks it about the resolved topic (after remapping).
  static bool usesCompressed(const std::string& topic, const std::string& transport);

 private:
  void rawCallback(const sensor_msgs::ImageConstPtr& msg);
  void compressedCallback(const sensor_msgs::CompressedImageConstPtr& msg);
  void drop(const std::string& problem);
  /// topic_ resolved in nh_ (remappings applied); topic_ itself when it is not a valid name.
  std::string resolvedTopic() const;

  ros::NodeHandle nh_;
  std::string topic_, transport_;
  uint32_t queue_size_;
  Callback callback_;

  mutable std::mutex mutex_;  // guards the subscribers, active_, subscribed_topic_, last_error_
  std::unique_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber it_sub_;
  ros::Subscriber compressed_sub_;
  std::string active_, subscribed_topic_, last_error_;
  bool plugin_failed_ = false;
  bool compressed_logged_ = false;  // the "/compressed topic" note is logged once
  std::atomic<size_t> received_{0}, dropped_{0};
};

}  // namespace iraf_vo
