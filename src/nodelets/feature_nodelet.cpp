// FeatureNodelet: image_enhanced -> features (iraf_vo/Features) + lazily features_image (debug, bgr8).
// Thin: converts messages, holds the dynamic_reconfigure server, calls iraf_vo::FeatureExtractor (ROS-free core).
#include <dynamic_reconfigure/server.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>

#include <boost/thread/recursive_mutex.hpp>
#include <algorithm>
#include <deque>
#include <memory>
#include <mutex>

#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/FeaturesConfig.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/ros/image_conversion.h"

namespace iraf_vo {

namespace {

/// Copies a FeaturesConfig into FeatureParams (same field names).
FeatureParams toParams(const iraf_vo::FeaturesConfig& c) {
  FeatureParams p;
  p.n_features = c.n_features;
  p.scale_factor = c.scale_factor;
  p.n_levels = c.n_levels;
  p.cell_size = c.cell_size;
  p.adaptive_threshold = c.adaptive_threshold;
  p.ini_th_fast = c.ini_th_fast;
  p.min_th_fast = c.min_th_fast;
  p.alpha = c.alpha;
  p.beta = c.beta;
  p.delta = c.delta;
  p.ft_min = c.ft_min;
  p.center_window = c.center_window | 1;  // odd
  p.culling = c.culling;
  p.min_node_size = c.min_node_size;
  p.contrast_patch_size = c.contrast_patch_size | 1;  // odd
  p.rho = c.rho;
  p.h_th = c.h_th;
  p.k = c.k;
  p.d_opt = c.d_opt;
  p.w1 = c.w1;
  p.w2 = c.w2;
  p.s_min = c.s_min;
  p.min_features = c.min_features;
  p.eq23_literal = c.eq23_literal;
  return p;
}

}  // namespace

class FeatureNodelet : public nodelet::Nodelet {
 public:
  ~FeatureNodelet() override = default;

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("queue_size", queue_size_, 5);
    it_ = std::make_shared<image_transport::ImageTransport>(nh);

    reconfigure_ = std::make_shared<ReconfigureServer>(reconfigure_mutex_, pnh);
    reconfigure_->setCallback([this](iraf_vo::FeaturesConfig& c, uint32_t) { configure(c); });

    // Lazy subscription: subscribe to `image_enhanced` only while someone listens to an output.
    std::lock_guard<std::mutex> lock(connect_mutex_);
    auto image_cb = [this](const image_transport::SingleSubscriberPublisher&) { connectCb(); };
    auto feat_cb = [this](const ros::SingleSubscriberPublisher&) { connectCb(); };
    features_pub_ = nh.advertise<iraf_vo::Features>("features", 10, feat_cb, feat_cb);
    image_pub_ = it_->advertise("features_image", 1, image_cb, image_cb);
  }

  void configure(const iraf_vo::FeaturesConfig& c) {
    const FeatureParams p = toParams(c);
    const std::string err = validate(p);
    if (!err.empty()) {
      NODELET_ERROR("features: rejected parameters: %s", err.c_str());
      return;
    }
    std::lock_guard<std::mutex> lock(params_mutex_);
    params_ = p;
  }

  void connectCb() {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    if (features_pub_.getNumSubscribers() == 0 && image_pub_.getNumSubscribers() == 0) {
      sub_.shutdown();
      stats_sub_.shutdown();
    } else if (!sub_) {
      image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
      sub_ = it_->subscribe("image_enhanced", queue_size_, &FeatureNodelet::imageCb, this, hints);
      // Optional: the enhancement class of each frame, matched by stamp (Features.brightness, 0 if unknown).
      stats_sub_ = getNodeHandle().subscribe("enhance_stats", 20, &FeatureNodelet::statsCb, this);
    }
  }

  void statsCb(const iraf_vo::EnhanceStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(brightness_mutex_);
    brightness_.emplace_back(msg->header.stamp, msg->brightness);
    while (brightness_.size() > 64) brightness_.pop_front();
  }

  // Enhancement class of the frame with this stamp if its EnhanceStats arrived, else 0 (unknown).
  int brightnessOf(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(brightness_mutex_);
    for (auto it = brightness_.rbegin(); it != brightness_.rend(); ++it)
      if (it->first == stamp) return it->second;
    return 0;
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    FeatureParams params;
    {
      std::lock_guard<std::mutex> lock(params_mutex_);
      params = params_;
    }
    cv::Mat gray;
    std::string error;
    if (!toMono8(msg, &gray, &error)) {
      NODELET_ERROR_THROTTLE(5.0, "features: dropping frame (stamp %.3f, frame '%s'): %s", msg->header.stamp.toSec(),
                             msg->header.frame_id.c_str(), error.c_str());
      return;
    }
    const bool want_image = image_pub_.getNumSubscribers() > 0;
    CulledFeatures culled;
    FeatureFrame frame;
    try {
      frame = extractor_.extract(gray, msg->header.stamp.toSec(), params, want_image ? &culled : nullptr);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "features: dropping frame (stamp %.3f): %s", msg->header.stamp.toSec(), e.what());
      return;
    }
    // Looked up after the extraction: EnhanceNodelet publishes its stats right after the image.
    frame.stats.brightness = brightnessOf(msg->header.stamp);
    NODELET_DEBUG_THROTTLE(2.0, "features: %zu keypoints (%d culled), F_t^g %.1f, %.2f/%.2f/%.2f ms",
                           frame.keypoints.size(), frame.stats.culled, frame.stats.global_threshold,
                           frame.stats.ms_threshold, frame.stats.ms_detect, frame.stats.ms_cull);

    if (features_pub_.getNumSubscribers() > 0) {
      iraf_vo::FeaturesPtr out = boost::make_shared<iraf_vo::Features>();
      toMsg(frame, msg->header, out.get());
      features_pub_.publish(out);
    }
    if (want_image) image_pub_.publish(debugImage(gray, frame, culled, msg->header, params.s_min));
  }

  // Kept keypoints coloured by stability S (red = s_min .. green = 1), culled ones in magenta.
  static sensor_msgs::ImagePtr debugImage(const cv::Mat& gray, const FeatureFrame& f, const CulledFeatures& culled,
                                          const std_msgs::Header& header, double s_min) {
    cv::Mat bgr;
    cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
    for (size_t i = 0; i < f.keypoints.size(); ++i) {
      const cv::KeyPoint& k = f.keypoints[i];
      const double s = i < f.stability.size() ? f.stability[i] : 1.0;
      const double a = std::min(1.0, std::max(0.0, (s - s_min) / std::max(1e-6, 1.0 - s_min)));
      const cv::Scalar color(0, 255 * a, 255 * (1.0 - a));
      cv::circle(bgr, k.pt, 2 + k.octave, color, 1, cv::LINE_AA);
    }
    for (const cv::KeyPoint& k : culled.keypoints) {
      cv::drawMarker(bgr, k.pt, cv::Scalar(255, 0, 255), cv::MARKER_TILTED_CROSS, 6 + 2 * k.octave, 1);
    }
    sensor_msgs::ImagePtr out = boost::make_shared<sensor_msgs::Image>();
    out->header = header;
    out->height = bgr.rows;
    out->width = bgr.cols;
    out->encoding = sensor_msgs::image_encodings::BGR8;
    out->is_bigendian = false;
    out->step = bgr.cols * 3;
    out->data.resize(static_cast<size_t>(out->step) * bgr.rows);
    for (int r = 0; r < bgr.rows; ++r)
      std::copy(bgr.ptr<uint8_t>(r), bgr.ptr<uint8_t>(r) + out->step, &out->data[r * out->step]);
    return out;
  }

  using ReconfigureServer = dynamic_reconfigure::Server<iraf_vo::FeaturesConfig>;
  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
  image_transport::Publisher image_pub_;
  ros::Publisher features_pub_;
  ros::Subscriber stats_sub_;
  std::mutex brightness_mutex_;
  std::deque<std::pair<ros::Time, int>> brightness_;  // (stamp, EnhanceStats.brightness) of recent frames
  int queue_size_ = 5;
  std::mutex connect_mutex_;

  boost::recursive_mutex reconfigure_mutex_;
  std::shared_ptr<ReconfigureServer> reconfigure_;
  std::mutex params_mutex_;
  FeatureParams params_;

  FeatureExtractor extractor_;  // used from imageCb only (one callback at a time per subscriber)
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::FeatureNodelet, nodelet::Nodelet)
