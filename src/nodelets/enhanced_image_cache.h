// The enhanced images of one camera for the tracker nodelet's stereo sub-pixel refinement (stereo_refinement.h):
// the left-right matcher refines each right pixel on the two images the keypoints were detected on, which the
// Features messages do not carry. The tracker subscribes to the enhance nodelets' `image_enhanced` outputs (the
// feature nodelets' inputs: in one nodelet manager the same message, no copy), keeps the newest `capacity`
// messages and hands out the one whose stamp is the Features message's (the features keep the image header).
#pragma once

#include <image_transport/image_transport.h>
#include <ros/ros.h>

#include <algorithm>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>

#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

class EnhancedImageCache {
 public:
  void start(image_transport::ImageTransport& it, const std::string& topic, size_t capacity,
             const ros::NodeHandle& pnh) {
    capacity_ = std::max<size_t>(capacity, 1);
    image_transport::TransportHints hints("raw", ros::TransportHints(), pnh);
    sub_ = it.subscribe(topic, static_cast<uint32_t>(capacity_), &EnhancedImageCache::imageCb, this, hints);
  }
  bool started() const { return static_cast<bool>(sub_); }
  std::string topic() const { return sub_ ? sub_.getTopic() : std::string(); }

  /// The 8-bit image of this stamp (its own copy: the frame may outlive the message), empty when it did not come or
  /// cannot be converted (*error says why). Drops it and the images that came before it: frames are tracked in
  /// arrival order.
  cv::Mat take(int64_t stamp_ns, std::string* error) {
    sensor_msgs::ImageConstPtr msg;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto it = std::find_if(images_.begin(), images_.end(), [stamp_ns](const sensor_msgs::ImageConstPtr& m) {
        return static_cast<int64_t>(m->header.stamp.toNSec()) == stamp_ns;
      });
      if (it != images_.end()) msg = *it, images_.erase(images_.begin(), it + 1);  // and the older ones
    }
    cv::Mat gray;
    if (!msg) {
      *error = "no image with the features' stamp on " + topic();
      return gray;
    }
    if (!toMono8(msg, &gray, error)) return cv::Mat();
    return gray.clone();
  }

 private:
  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    images_.push_back(msg);
    while (images_.size() > capacity_) images_.pop_front();
  }

  std::mutex mutex_;
  std::deque<sensor_msgs::ImageConstPtr> images_;  // arrival order
  size_t capacity_ = 1;
  image_transport::Subscriber sub_;
};

}  // namespace iraf_vo
