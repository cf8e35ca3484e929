// EnhanceNodelet: image -> image_enhanced (+ enhance_stats). Thin: converts messages, holds the
// dynamic_reconfigure server, calls iraf_vo::Enhancer (the ROS-free core).
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>

#include <boost/thread/recursive_mutex.hpp>
#include <memory>
#include <mutex>

#include "iraf_vo/EnhanceConfig.h"
#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

class EnhanceNodelet : public nodelet::Nodelet {
 public:
  ~EnhanceNodelet() override = default;

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("queue_size", queue_size_, 5);
    it_ = std::make_shared<image_transport::ImageTransport>(nh);

    reconfigure_ = std::make_shared<ReconfigureServer>(reconfigure_mutex_, pnh);
    reconfigure_->setCallback([this](iraf_vo::EnhanceConfig& c, uint32_t) { configure(c); });

    // Lazy subscription: subscribe to `image` only while someone listens to an output.
    std::lock_guard<std::mutex> lock(connect_mutex_);
    auto image_cb = [this](const image_transport::SingleSubscriberPublisher&) { connectCb(); };
    auto stats_cb = [this](const ros::SingleSubscriberPublisher&) { connectCb(); };
    pub_ = it_->advertise("image_enhanced", 1, image_cb, image_cb);
    stats_pub_ = nh.advertise<iraf_vo::EnhanceStats>("enhance_stats", 10, stats_cb, stats_cb);
  }

  void configure(const iraf_vo::EnhanceConfig& c) {
    EnhanceParams p;
    if (!parseEnhanceMethod(c.method, &p.method)) {
      NODELET_ERROR("enhance: unknown method '%s' (none | iraf | he | clahe); keeping the previous one",
                    c.method.c_str());
      std::lock_guard<std::mutex> lock(params_mutex_);
      p.method = params_.method;
    }
    p.gaussian_kernel_size = c.gaussian_kernel_size | 1;  // the kernel must be odd
    p.gaussian_sigma = c.gaussian_sigma;
    p.mu_expected = c.mu_expected;
    p.brightness_threshold = c.brightness_threshold;
    p.dim_lambda = c.dim_lambda;
    p.dim_tau = c.dim_tau;
    p.bright_lambda = c.bright_lambda;
    p.bright_tau = c.bright_tau;
    p.epsilon = c.epsilon;
    p.eta = c.eta;
    p.clahe_clip_limit = c.clahe_clip_limit;
    p.clahe_tiles = c.clahe_tiles;
    const std::string err = validate(p);
    if (!err.empty()) {
      NODELET_ERROR("enhance: rejected parameters: %s", err.c_str());
      return;
    }
    std::lock_guard<std::mutex> lock(params_mutex_);
    params_ = p;
    enabled_ = c.enabled;
  }

  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (pub_.getNumSubscribers() == 0 && stats_pub_.getNumSubscribers() == 0) {
      sub_.shutdown();
    } else if (!sub_) {
      image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
      sub_ = it_->subscribe("image", queue_size_, &EnhanceNodelet::imageCb, this, hints);
    }
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    EnhanceParams params;
    bool enabled;
    {
      std::lock_guard<std::mutex> lock(params_mutex_);
      params = params_;
      enabled = enabled_;
    }
    cv::Mat gray;
    std::string error;
    if (!toMono8(msg, &gray, &error)) {
      NODELET_ERROR_THROTTLE(5.0, "enhance: dropping frame (stamp %.3f, frame '%s'): %s", msg->header.stamp.toSec(),
                             msg->header.frame_id.c_str(), error.c_str());
      return;
    }
    if (!enabled) params.method = EnhanceMethod::kNone;

    EnhanceResult res;
    try {
      res = enhancer_.enhance(gray, params);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "enhance: dropping frame: %s", e.what());
      return;
    }
    NODELET_DEBUG_THROTTLE(2.0, "enhance: %s mu %.1f t %.2f %.2f ms", toString(res.brightness), res.mu, res.t, res.ms);

    if (pub_.getNumSubscribers() > 0) {
      sensor_msgs::ImagePtr out = boost::make_shared<sensor_msgs::Image>();
      out->header = msg->header;
      out->height = res.image.rows;
      out->width = res.image.cols;
      out->encoding = sensor_msgs::image_encodings::MONO8;
      out->is_bigendian = false;
      out->step = res.image.cols;
      out->data.resize(static_cast<size_t>(res.image.rows) * res.image.cols);
      for (int r = 0; r < res.image.rows; ++r)
        std::copy(res.image.ptr<uint8_t>(r), res.image.ptr<uint8_t>(r) + res.image.cols, &out->data[r * out->step]);
      pub_.publish(out);
    }
    if (stats_pub_.getNumSubscribers() > 0) {
      iraf_vo::EnhanceStatsPtr st = boost::make_shared<iraf_vo::EnhanceStats>();
      st->header = msg->header;
      st->method = toString(params.method);
      st->brightness = static_cast<int8_t>(res.brightness);
      st->mu = static_cast<float>(res.mu);
      st->t = static_cast<float>(res.t);
      st->ms = static_cast<float>(res.ms);
      stats_pub_.publish(st);
    }
  }

  using ReconfigureServer = dynamic_reconfigure::Server<iraf_vo::EnhanceConfig>;
  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
  image_transport::Publisher pub_;
  ros::Publisher stats_pub_;
  int queue_size_ = 5;
  std::mutex connect_mutex_;

  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<ReconfigureServer> reconfigure_;
  std::mutex params_mutex_;
  EnhanceParams params_;
  bool enabled_ = true;

  Enhancer enhancer_;  // used from imageCb only (one callback at a time per subscriber)
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::EnhanceNodelet, nodelet::Nodelet)
