// FeatureNodelet: image_enhanced -> features (iraf_vo/Features) + lazily features_image (debug, bgr8).
// Thin: converts messages and calls iraf_vo::FeatureExtractor (the ROS-free core); parameters and lazy subscription
// come from StageNodelet.
#include <algorithm>
#include <deque>
#include <opencv2/imgproc.hpp>
#include <pluginlib/class_list_macros.hpp>

#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/FeaturesConfig.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/features/image_signal.h"
#include "iraf_vo/pipeline/pipeline_params.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/ros/image_conversion.h"
#include "stage_nodelet.h"

namespace iraf_vo {

class FeatureNodelet : public StageNodelet<FeatureParams, iraf_vo::FeaturesConfig> {
 public:
  FeatureNodelet() : StageNodelet(featureParamTable()) {}

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    getPrivateNodeHandle().param("queue_size", queue_size_, 5);
    getPrivateNodeHandle().param("resolution_rule", resolution_rule_, true);
    it_ = std::make_shared<image_transport::ImageTransport>(nh);
    startReconfigure();
    std::lock_guard<std::mutex> lock(connectMutex());
    features_pub_ = advertiseLazy<iraf_vo::Features>(nh, "features", 10);
    image_pub_ = advertiseLazy(*it_, "features_image", 1);
  }

  bool hasListeners() override { return features_pub_.getNumSubscribers() > 0 || image_pub_.getNumSubscribers() > 0; }
  void subscribeInputs() override {
    image_transport::TransportHints hints("raw", ros::TransportHints(), getPrivateNodeHandle());
    sub_ = it_->subscribe("image_enhanced", queue_size_, &FeatureNodelet::imageCb, this, hints);
    // Optional: the enhancement class and the input signal of each frame, matched by stamp (Features.brightness,
    // Features.signal_*).
    stats_sub_ = getNodeHandle().subscribe("enhance_stats", 20, &FeatureNodelet::statsCb, this);
  }
  void unsubscribeInputs() override {
    sub_.shutdown();
    stats_sub_.shutdown();
  }

  void statsCb(const iraf_vo::EnhanceStatsConstPtr& msg) {
    std::lock_guard<std::mutex> lock(brightness_mutex_);
    if (msg->rejected) {
      ++rejected_since_published_;
      return;
    }
    brightness_.push_back(msg);
    while (brightness_.size() > 64) brightness_.pop_front();
  }

  void countRejected() {
    std::lock_guard<std::mutex> lock(brightness_mutex_);
    ++rejected_since_published_;
  }

  // The EnhanceStats of the frame with this stamp if they arrived, else null.
  iraf_vo::EnhanceStatsConstPtr enhanceStatsOf(const ros::Time& stamp) {
    std::lock_guard<std::mutex> lock(brightness_mutex_);
    for (auto it = brightness_.rbegin(); it != brightness_.rend(); ++it)
      if ((*it)->header.stamp == stamp) return *it;
    return nullptr;
  }

  // Enhancement class (0 if unknown) and the signal of the camera image: from the frame's EnhanceStats (measured
  // before enhancement); without an enhance stage (no EnhanceStats ever) measured on this input, the camera image.
  void addInputStats(const ros::Time& stamp, const cv::Mat& gray, FeatureFrame* frame) {
    const iraf_vo::EnhanceStatsConstPtr st = enhanceStatsOf(stamp);
    if (st) {
      frame->stats.brightness = st->brightness;
      frame->signal.measured = true;
      frame->signal.mean = st->mu;
      frame->signal.noise_sigma = st->signal_noise;
      frame->signal.contrast = st->signal_contrast;
      frame->signal.snr = st->signal_snr;
      frame->signal.clipped = st->signal_clipped;
    } else if (stats_sub_.getNumPublishers() == 0) {
      frame->signal = measureImageSignal(gray);
    }
  }

  // n_features, cell_size and n_levels from the image size (pipeline_params.h), once per size, unless given as
  // ~parameters; the values go to dynamic_reconfigure.
  void applyResolutionRule(int width, int height) {
    if (!resolution_rule_ || (width == rule_width_ && height == rule_height_) || width <= 0 || height <= 0) return;
    rule_width_ = width;
    rule_height_ = height;
    FeatureParams p = params();
    const std::string rule = applyFeatureResolutionRule(width, height, userSet(), &p);
    replaceParams(p);
    NODELET_INFO("features: resolution rule, %s (~parameters given are kept; ~resolution_rule false: off)",
                 rule.c_str());
  }

  void imageCb(const sensor_msgs::ImageConstPtr& msg) {
    applyResolutionRule(static_cast<int>(msg->width), static_cast<int>(msg->height));
    const FeatureParams p = params();
    cv::Mat gray;
    std::string error;
    if (!toMono8(msg, &gray, &error)) {
      countRejected();
      NODELET_ERROR_THROTTLE(5.0, "features: dropping frame (stamp %.3f, frame '%s'): %s", msg->header.stamp.toSec(),
                             msg->header.frame_id.c_str(), error.c_str());
      return;
    }
    const bool want_image = image_pub_.getNumSubscribers() > 0;
    CulledFeatures culled;
    FeatureFrame frame;
    try {
      frame = extractor_.extract(gray, msg->header.stamp.toSec(), p, want_image ? &culled : nullptr);
    } catch (const std::exception& e) {
      countRejected();
      NODELET_ERROR_THROTTLE(5.0, "features: dropping frame (stamp %.3f): %s", msg->header.stamp.toSec(), e.what());
      return;
    }
    // Looked up after the extraction: EnhanceNodelet publishes its stats right after the image.
    addInputStats(msg->header.stamp, gray, &frame);
    NODELET_DEBUG_THROTTLE(2.0, "features: %zu keypoints (%d culled), F_t^g %.1f, %.2f/%.2f/%.2f ms",
                           frame.keypoints.size(), frame.stats.culled, frame.stats.global_threshold,
                           frame.stats.ms_threshold, frame.stats.ms_detect, frame.stats.ms_cull);

    if (features_pub_.getNumSubscribers() > 0) {
      iraf_vo::FeaturesPtr out = boost::make_shared<iraf_vo::Features>();
      toMsg(frame, msg->header, out.get());
      {
        std::lock_guard<std::mutex> lock(brightness_mutex_);
        out->rejected_before = static_cast<uint32_t>(rejected_since_published_);
        rejected_since_published_ = 0;
      }
      features_pub_.publish(out);
    }
    if (want_image) image_pub_.publish(toImageMsg(debugImage(gray, frame, culled, p.s_min), msg->header));
  }

  // Kept keypoints coloured by stability S (red = s_min .. green = 1), culled ones in magenta.
  static cv::Mat debugImage(const cv::Mat& gray, const FeatureFrame& f, const CulledFeatures& culled, double s_min) {
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
    return bgr;
  }

  std::shared_ptr<image_transport::ImageTransport> it_;
  image_transport::Subscriber sub_;
  image_transport::Publisher image_pub_;
  ros::Publisher features_pub_;
  ros::Subscriber stats_sub_;
  std::mutex brightness_mutex_;
  std::deque<iraf_vo::EnhanceStatsConstPtr> brightness_;  // EnhanceStats of recent frames
  long rejected_since_published_ = 0;  // frames rejected upstream or here since the last Features (Features.rejected_before)
  int queue_size_ = 5;
  bool resolution_rule_ = true;
  int rule_width_ = 0, rule_height_ = 0;  // image size the rule was applied for
  FeatureExtractor extractor_;  // used from imageCb only (one callback at a time per subscriber)
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::FeatureNodelet, nodelet::Nodelet)
