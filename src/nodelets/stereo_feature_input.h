// The tracker nodelet's right feature stream (stereo mode): subscribes `right/features`, holds the feature messages
// of both cameras until StereoPairing (pipeline/stereo_pairing.h) decides, and hands each left frame on with its right
// partner or alone. A left frame is never dropped: message_filters' synchronizers (ExactTime / ApproximateTime) drop
// a frame without a partner, so the rule is StereoPairing's, fed by the two subscriptions. A wall timer resolves
// left frames whose partner did not come within max_wait.
#pragma once

#include <ros/ros.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <mutex>
#include <string>

#include "iraf_vo/Features.h"
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
};

}  // namespace iraf_vo
