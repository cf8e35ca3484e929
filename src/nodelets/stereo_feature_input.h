// The tracker nodelet's right feature stream (stereo mode): subscribes `right/features`, holds the feature messages
// of both cameras until StereoPairing (pipeline/stereo_pairing.h) decides, and hands each left frame on with its right
// partner or alone. A left frame is never dropped: message_filters' synchronizers (ExactTime / ApproximateTime) drop
// a frame without a partner, so the rule is StereoPairing's, fed by the two subscriptions. A wall timer resolves
// left frames whose partner did not come within max_wait. With startImages(), it also holds the two cameras' enhanced
// images (enhanced_image_cache.h) that the stereo matcher's sub-pixel refinement needs, as iraf_vo_run --stereo has.
#pragma once

#include <ros/ros.h>

#include <algorithm>
#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "enhanced_image_cache.h"
#include "iraf_vo/Features.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/pipeline/stereo_pairing.h"

namespace iraf_vo {

class StereoFeatureInput {
 public:
  /// right == nullptr: the left frame goes alone.
  using Deliver = std::function<void(const iraf_vo::FeaturesConstPtr& left, const iraf_vo::FeaturesConstPtr& right)>;
  using Log = std::function<void(const SessionMessage&)>;
  using RightArrival = std::function<void(const iraf_vo::FeaturesConstPtr& right)>;

  void start(ros::NodeHandle& nh, int queue_size, const StereoPairingParams& params, Deliver deliver, Log log,
             RightArrival on_right) {
    pairing_ = StereoPairing(params);
    deliver_ = std::move(deliver);
    log_ = std::move(log);
    on_right_ = std::move(on_right);
    sub_ = nh.subscribe("right/features", queue_size, &StereoFeatureInput::rightCb, this);
    timer_ = nh.createWallTimer(ros::WallDuration(std::max(0.005, params.max_wait / 4)),
                                [this](const ros::WallTimerEvent&) { poll(); });
  }
  std::string rightTopic() const { return sub_.getTopic(); }

  /// Subscribes `image_enhanced` and `right/image_enhanced` (the enhance nodelets' outputs), keeping the newest
  /// `capacity` images of each camera.
  void startImages(ros::NodeHandle& nh, const ros::NodeHandle& pnh, size_t capacity) {
    it_ = std::make_shared<image_transport::ImageTransport>(nh);
    left_images_.start(*it_, "image_enhanced", capacity, pnh);
    right_images_.start(*it_, "right/image_enhanced", capacity, pnh);
  }
  bool withImages() const { return left_images_.started(); }
  std::string imageTopics() const { return left_images_.topic() + " and " + right_images_.topic(); }

  /// A pair's enhanced images into left->image and right->image (the sub-pixel refinement). false + *error when one
  /// is missing: the frames stay without images and the pair's matches are not refined (counted). Called from
  /// deliver_ (under mutex_): takes only the caches' own locks.
  bool attachImages(int64_t left_stamp_ns, int64_t right_stamp_ns, FeatureFrame* left, FeatureFrame* right,
                    std::string* error) {
    cv::Mat l = left_images_.take(left_stamp_ns, error);
    cv::Mat r = l.empty() ? cv::Mat() : right_images_.take(right_stamp_ns, error);
    if (l.empty() || r.empty()) return ++unrefined_pairs_, false;
    left->image = l;
    right->image = r;
    return true;
  }
  /// Pairs tracked without their images (matches not sub-pixel refined).
  long unrefinedPairs() const { return unrefined_pairs_; }

  void addLeft(const iraf_vo::FeaturesConstPtr& left) {
    std::lock_guard<std::mutex> lock(mutex_);
    left_.push_back(left);
    apply(pairing_.addLeft(static_cast<int64_t>(left->header.stamp.toNSec()), ros::WallTime::now().toSec()));
  }

  StereoCounters counters() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pairing_.counters();
  }
  bool rightMissing() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pairing_.rightMissing();
  }

 private:
  void rightCb(const iraf_vo::FeaturesConstPtr& right) {
    if (on_right_) on_right_(right);
    std::lock_guard<std::mutex> lock(mutex_);
    right_.push_back(right);
    apply(pairing_.addRight(static_cast<int64_t>(right->header.stamp.toNSec()), ros::WallTime::now().toSec()));
  }

  void poll() {
    std::lock_guard<std::mutex> lock(mutex_);
    apply(pairing_.poll(ros::WallTime::now().toSec()));
  }

  /// Under mutex_: the decisions consume the fronts of the two queues (StereoPairing's order).
  void apply(const std::vector<StereoPairing::Decision>& decisions) {
    for (const StereoPairing::Decision& d : decisions) {
      if (d.kind == StereoPairing::Kind::kDropRight) {
        right_.pop_front();
        continue;
      }
      const iraf_vo::FeaturesConstPtr left = left_.front();
      left_.pop_front();
      iraf_vo::FeaturesConstPtr right;
      if (d.kind == StereoPairing::Kind::kPair) right = right_.front(), right_.pop_front();
      deliver_(left, right);
    }
    for (const SessionMessage& m : pairing_.takeMessages()) log_(m);
  }

  mutable std::mutex mutex_;  // taken before the nodelet's own lock (deliver_ runs under it)
  StereoPairing pairing_;
  std::deque<iraf_vo::FeaturesConstPtr> left_, right_;
  Deliver deliver_;
  Log log_;
  RightArrival on_right_;
  ros::Subscriber sub_;
  ros::WallTimer timer_;
  std::shared_ptr<image_transport::ImageTransport> it_;
  EnhancedImageCache left_images_, right_images_;
  std::atomic<long> unrefined_pairs_{0};
};

}  // namespace iraf_vo
