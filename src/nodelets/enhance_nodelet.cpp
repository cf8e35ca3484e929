// EnhanceNodelet: image -> image_enhanced (+ enhance_stats), the first nodelet of the graph. Thin: converts messages
// and calls iraf_vo::Enhancer (the ROS-free core); parameters and lazy subscription come from StageNodelet.
// Input: iraf_vo::ImageInput (raw, or sensor_msgs/CompressedImage decoded with OpenCV when ~image_transport is
// `compressed` or the topic ends in /compressed; a transport that cannot load falls back to raw with a ROS_ERROR).
// Size guard, before any enhancement / feature extraction: the expected size comes from ~camera_file, else from the
// camera's camera_info (first valid message), and until one is known an image above ~max_image_pixels is rejected.
// /diagnostics ("enhance: input"): transport, input / output rates, rejected and missed frames; a stopped camera
// (InputWatchdog: ROS_WARN after 2.2 periods, ROS_ERROR and ERROR after ~input_timeout s, OK again with the frames).
#include <atomic>
#include <pluginlib/class_list_macros.hpp>

#include "iraf_vo/EnhanceConfig.h"
#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/image_signal.h"
#include "iraf_vo/pipeline/input_watchdog.h"
#include "iraf_vo/ros/camera_source.h"
#include "iraf_vo/ros/image_conversion.h"
#include "iraf_vo/ros/image_input.h"
#include "stage_nodelet.h"

namespace iraf_vo {

class EnhanceNodelet : public StageNodelet<EnhanceParams, iraf_vo::EnhanceConfig> {
 public:
  EnhanceNodelet() : StageNodelet(enhanceParamTable()) {}
  ~EnhanceNodelet() override {
    if (input_) input_->shutdown();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    int queue_size = 5;
    std::string transport, camera_file;
    pnh.param("queue_size", queue_size, 5);
    pnh.param<std::string>("image_transport", transport, "raw");
    pnh.param<std::string>("camera_file", camera_file, "");
    pnh.param("max_image_pixels", max_pixels_, 4096.0 * 4096.0);
    double input_timeout = 3.0;
    pnh.param("input_timeout", input_timeout, 3.0);
    watchdog_.setDeadAfter(input_timeout);
    camera_src_.start(nh, camera_file, CameraInfoOptions(), [this](CameraSource::Event e, const std::string& text) {
      if (e == CameraSource::Event::kInvalid) NODELET_ERROR("enhance: %s; size guard: ~max_image_pixels", text.c_str());
      else NODELET_INFO("enhance: size guard: %s", text.c_str());
    });
    input_ = std::make_unique<ImageInput>(nh, "image", transport, queue_size,
                                          [this](const std_msgs::Header& h, const cv::Mat& g) { imageCb(h, g); });
    updater_ = makeUpdater(nh, pnh, getName());
    updater_->add("input", this, &EnhanceNodelet::diagnose);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->force_update(); });
    // The camera watchdog: a stopped publisher is reported within 2.2 periods + 25 ms.
    watchdog_timer_ = nh.createWallTimer(ros::WallDuration(0.025), [this](const ros::WallTimerEvent&) {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      logInput(watchdog_.check(ros::WallTime::now().toSec()));
    });
    startReconfigure();
    std::lock_guard<std::mutex> lock(connectMutex());
    it_ = std::make_shared<image_transport::ImageTransport>(nh);
    pub_ = advertiseLazy(*it_, "image_enhanced", 1);
    stats_pub_ = advertiseLazy<iraf_vo::EnhanceStats>(nh, "enhance_stats", 10);
  }

  void onParams(const EnhanceParams&, const iraf_vo::EnhanceConfig& c) override { enabled_ = c.enabled; }

  bool hasListeners() override { return pub_.getNumSubscribers() > 0 || stats_pub_.getNumSubscribers() > 0; }
  void subscribeInputs() override {
    input_->subscribe();
    std::lock_guard<std::mutex> lock(stats_mutex_);
    watchdog_.arm(input_->subscribedTopic(), ros::WallTime::now().toSec());
  }
  void unsubscribeInputs() override {
    input_->shutdown();
    std::lock_guard<std::mutex> lock(stats_mutex_);
    watchdog_.disarm();
  }
  void logInput(const std::vector<SessionMessage>& messages) {
    for (const SessionMessage& m : messages) {
      if (m.level == SessionMessage::Level::kInfo) NODELET_INFO("enhance: %s", m.text.c_str());
      else if (m.level == SessionMessage::Level::kWarn) NODELET_WARN("enhance: %s", m.text.c_str());
      else NODELET_ERROR("enhance: %s", m.text.c_str());
    }
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& d) {
    std::lock_guard<std::mutex> lock(stats_mutex_);
    const double now = ros::WallTime::now().toSec();
    HealthReport r = inputHealth(input_->activeTransport(), input_->subscribedTopic(), in_rate_.rate(now),
                                 out_rate_.rate(now), input_->dropped(), rejected_, gaps_.missed(),
                                 last_problem_.empty() ? input_->lastError() : last_problem_);
    std::string silence;
    const HealthReport::Level l = watchdog_.level(now, &silence);
    if (l >= r.level && l != HealthReport::kOk) r.level = l, r.summary = silence;
    fillDiagnostics(r, d);
  }

  /// The expected size problem of an image ("" when it may be processed).
  std::string sizeProblem(int width, int height) const {
    if (const CameraModelPtr cam = camera_src_.camera())
      return width == cam->width() && height == cam->height()
                 ? ""
                 : "image " + std::to_string(width) + "x" + std::to_string(height) + " but the calibration is " +
                       std::to_string(cam->width()) + "x" + std::to_string(cam->height());
    return static_cast<double>(width) * height <= max_pixels_
               ? ""
               : "image " + std::to_string(width) + "x" + std::to_string(height) + " above ~max_image_pixels " +
                     std::to_string(static_cast<long>(max_pixels_)) + " (no calibration known yet)";
  }

  void imageCb(const std_msgs::Header& header, const cv::Mat& gray) {
    const double now = ros::WallTime::now().toSec();
    {
      std::lock_guard<std::mutex> lock(stats_mutex_);
      in_rate_.tick(now);
      const int64_t stamp_ns = static_cast<int64_t>(header.stamp.toNSec());
      if (const long missing = gaps_.update(stamp_ns))
        NODELET_WARN_THROTTLE(5.0, "enhance: %s", missedFramesMessage(missing, stamp_ns, gaps_).text.c_str());
      logInput(watchdog_.onFrame(now, gaps_.period()));
      const std::string problem = sizeProblem(gray.cols, gray.rows);
      if (!problem.empty()) {
        ++rejected_;
        last_problem_ = problem;
        NODELET_ERROR_THROTTLE(5.0, "enhance: rejecting frame (stamp %.3f, frame '%s'): %s", header.stamp.toSec(),
                               header.frame_id.c_str(), problem.c_str());
        if (stats_pub_.getNumSubscribers() > 0) {  // the graph knows the frame arrived (not "missed")
          iraf_vo::EnhanceStatsPtr st = boost::make_shared<iraf_vo::EnhanceStats>();
          st->header = header;
          st->rejected = true;
          st->problem = problem;
          stats_pub_.publish(st);
        }
        return;
      }
    }
    EnhanceParams p = params();
    if (!enabled_) p.method = EnhanceMethod::kNone;  // republished untouched
    EnhanceResult res;
    try {
      res = enhancer_.enhance(gray, p);
    } catch (const std::exception& e) {
      NODELET_ERROR_THROTTLE(5.0, "enhance: dropping frame: %s", e.what());
      return;
    }
    NODELET_DEBUG_THROTTLE(2.0, "enhance: %s mu %.1f t %.2f %.2f ms", toString(res.brightness), res.mu, res.t, res.ms);

    if (pub_.getNumSubscribers() > 0) pub_.publish(toImageMsg(res.image, header));
    if (stats_pub_.getNumSubscribers() > 0) {
      iraf_vo::EnhanceStatsPtr st = boost::make_shared<iraf_vo::EnhanceStats>();
      st->header = header;
      st->method = toString(p.method);
      st->brightness = static_cast<int8_t>(res.brightness);
      st->mu = static_cast<float>(res.mu);
      st->t = static_cast<float>(res.t);
      st->ms = static_cast<float>(res.ms);
      const ImageSignal signal = res.signal.measured ? res.signal : measureImageSignal(gray);
      st->signal_noise = static_cast<float>(signal.noise_sigma);
      st->signal_contrast = static_cast<float>(signal.contrast);
      st->signal_snr = static_cast<float>(signal.snr);
      st->signal_clipped = static_cast<float>(signal.clipped);
      stats_pub_.publish(st);
    }
    std::lock_guard<std::mutex> lock(stats_mutex_);
    out_rate_.tick(ros::WallTime::now().toSec());
  }

  std::shared_ptr<image_transport::ImageTransport> it_;
  std::unique_ptr<ImageInput> input_;
  image_transport::Publisher pub_;
  ros::Publisher stats_pub_;
  ros::WallTimer timer_, watchdog_timer_;
  std::shared_ptr<diagnostic_updater::Updater> updater_;
  CameraSource camera_src_;
  double max_pixels_ = 4096.0 * 4096.0;
  std::atomic<bool> enabled_{true};
  Enhancer enhancer_;  // used from imageCb only (one callback at a time per subscriber)

  std::mutex stats_mutex_;  // below: rates and counters (image callback, diagnostics timer)
  RateMeter in_rate_, out_rate_;
  StampGapCounter gaps_;
  InputWatchdog watchdog_{"image"};
  long rejected_ = 0;
  std::string last_problem_;
};

}  // namespace iraf_vo

PLUGINLIB_EXPORT_CLASS(iraf_vo::EnhanceNodelet, nodelet::Nodelet)
