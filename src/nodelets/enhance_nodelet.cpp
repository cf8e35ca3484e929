// EnhanceNodelet: image -> image_enhanced (+ enhance_stats). Thin: converts messages and calls iraf_vo::Enhancer
// (the ROS-free core); parameters and lazy subscription come from StageNodelet.
#include <atomic>
#include <pluginlib/class_list_macros.hpp>

#include "iraf_vo/EnhanceConfig.h"
#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/enhance/enhance_params_io.h"
#include "iraf_vo/ros/image_conversion.h"
#include "stage_nodelet.h"

namespace iraf_vo {

class EnhanceNodelet : public StageNodelet<EnhanceParams, iraf_vo::EnhanceConfig> {
 public:
  EnhanceNodelet() : StageNodelet(enhanceParamTable()) {}

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    getPrivateNodeHandle().param("queue_size", queue_size_, 5);
    it_ = std::make_shared<image_transport::ImageTransport>(nh);
    startReconfigure();
    std::lock_guard<std::mutex> lock(connectMutex());
    pub_ = advertiseLazy(*it_, "image_enhanced", 1);
    stats_pub_ = advertiseLazy<iraf_vo::EnhanceStats>(nh, "enhance_stats", 10);
  }

  void onParams(const EnhanceParams&, const iraf_vo::EnhanceConfig& c) override { enabled_ = c.enabled; }

  bool hasListeners() override { return pub_.getNumSubscribers() > 0 || stats_pub_.getNumSubscribers() > 0; }
  void subscribeInputs() override {
    image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
    sub_ = it_->subscribe("image", queue_size_, &EnhanceNodelet::imageCb, this, hints);
  }
  void unsubscribeInputs() override { sub_.shutdown(); }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    EnhanceParams p = params();
    if (!enabled_) p.method = EnhanceMethod::kNone;
    cv::Mat gray;
    std::string error;
    if (!toMono8(msg, &gray, &error)) {
      NODELET_ERROR_THROTTLE(5.0, "enhance: dropping frame (stamp %.3f, frame '%s'): %s", msg->header.stamp.toSec(),
                             msg->header.frame_id.c_str(), error.c_str());
      return;
    }
    EnhanceResult res;
    try {
      res = enhancer_.enhance(gray, p);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "enhance: dropping frame: %s", e.what());
      return;
    }
    NODELET_DEBUG_THROTTLE(2.0, "enhance: %s mu %.1f t %.2f %.2f ms", toString(res.brightness), res.mu, res.t, res.ms);

    if (pub_.getNumSubscribers() > 0) pub_.publish(toImageMsg(res.image, msg->header));
    if (stats_pub_.getNumSubscribers() > 0) {
      iraf_vo::EnhanceStatsPtr st = boost::make_shared<iraf_vo::EnhanceStats>();
      st->header = msg->header;
      st->method = toString(p.method);
      st->brightness = static_cast<int8_t>(res.brightness);
      st->mu = static_cast<float>(res.mu);
      st->t = static_cast<float>(res.t);
      st->ms = static_cast<float>(res.ms);
      stats_pub_.publish(st);
    }
  }

  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
  image_transport::Publisher pub_;
  ros::Publisher stats_pub_;
  int queue_size_ = 5;
  std::atomic<bool> enabled_{true};
  Enhancer enhancer_;  // used from imageCb only (one callback at a time per subscriber)
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::EnhanceNodelet, nodelet::Nodelet)
