// rostest of EnhanceNodelet: encodings, bad input, lazy subscription, live dynamic_reconfigure (rejected values
// reverted in the server, changes logged).
#include <gtest/gtest.h>

#include "common/wait_for.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/client.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <map>
#include <mutex>

#include "common/test_data.h"
#include "iraf_vo/EnhanceConfig.h"
#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/common/param_table.h"

namespace enc = sensor_msgs::image_encodings;
using iraf_vo::test::waitFor;

class EnhanceNodeletTest : public ::testing::Test {
 protected:
  void SetUp() override {
    pub_ = nh_.advertise<sensor_msgs::Image>("image", 10);
  }

  void subscribeOutputs() {
    out_sub_ = nh_.subscribe<sensor_msgs::Image>("image_enhanced", 20, [this](const sensor_msgs::ImageConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex_);
      outputs_[idOf(m->header.stamp)] = m;
    });
    stats_sub_ = nh_.subscribe<iraf_vo::EnhanceStats>("enhance_stats", 20, [this](const iraf_vo::EnhanceStatsConstPtr& m) {
      std::lock_guard<std::mutex> l(mutex_);
      stats_[idOf(m->header.stamp)] = m;
    });
  }

  // roscpp overwrites header.seq on publish, so frames are identified by their stamp.
  static ros::Time stampOf(uint32_t id) { return ros::Time(1000.0 + id * 0.05); }
  static uint32_t idOf(const ros::Time& t) { return static_cast<uint32_t>(std::lround((t.toSec() - 1000.0) / 0.05)); }

  // Publishes `img` (converted to `encoding`) with stamp stampOf(id); returns the enhanced output or null.
  sensor_msgs::ImageConstPtr roundTrip(const cv::Mat& gray, const std::string& encoding, uint32_t id, double timeout = 5.0) {
    publish(gray, encoding, id);
    sensor_msgs::ImageConstPtr out;
    waitFor([&] {
      std::lock_guard<std::mutex> l(mutex_);
      auto it = outputs_.find(id);
      if (it != outputs_.end()) out = it->second;
      return out != nullptr;
    }, timeout);
    return out;
  }

  void publish(const cv::Mat& gray, const std::string& encoding, uint32_t id) {
    sensor_msgs::Image m;
    m.header.stamp = stampOf(id);
    m.header.frame_id = "cam0";
    cv::Mat conv;
    if (encoding == enc::MONO8) conv = gray;
    else if (encoding == enc::MONO16) gray.convertTo(conv, CV_16U, 256.0);
    else if (encoding == enc::BGR8) cv::cvtColor(gray, conv, cv::COLOR_GRAY2BGR);
    else if (encoding == enc::RGB8) cv::cvtColor(gray, conv, cv::COLOR_GRAY2RGB);
    else if (encoding == enc::BGRA8) cv::cvtColor(gray, conv, cv::COLOR_GRAY2BGRA);
    else gray.convertTo(conv, CV_32F);  // any unsupported encoding: float data
    m.encoding = encoding;
    m.height = conv.rows;
    m.width = conv.cols;
    m.step = conv.cols * conv.elemSize();
    m.data.assign(conv.data, conv.data + conv.total() * conv.elemSize());
    pub_.publish(m);
  }

  static cv::Mat toMat(const sensor_msgs::Image& m) {
    return cv::Mat(m.height, m.width, CV_8UC1, const_cast<uint8_t*>(m.data.data()), m.step).clone();
  }

  void reconfigure(const std::function<void(iraf_vo::EnhanceConfig&)>& change) {
    dynamic_reconfigure::Client<iraf_vo::EnhanceConfig> client("enhance");
    iraf_vo::EnhanceConfig cfg;
    ASSERT_TRUE(client.getCurrentConfiguration(cfg, ros::Duration(5.0)));
    change(cfg);
    ASSERT_TRUE(client.setConfiguration(cfg));
  }

  ros::NodeHandle nh_;
  ros::Publisher pub_;
  ros::Subscriber out_sub_, stats_sub_;
  std::mutex mutex_;
  std::map<uint32_t, sensor_msgs::ImageConstPtr> outputs_;
  std::map<uint32_t, iraf_vo::EnhanceStatsConstPtr> stats_;
};

TEST_F(EnhanceNodeletTest, LazySubscriptionEncodingsBadInputAndLiveTuning) {
  // Lazy: nobody listens to the outputs -> the nodelet does not subscribe to `image`.
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(pub_.getNumSubscribers(), 0u) << "EnhanceNodelet subscribed although nobody listens";

  subscribeOutputs();
  ASSERT_TRUE(waitFor([&] { return pub_.getNumSubscribers() > 0; }, 15.0)) << "nodelet never subscribed to image";
  ros::WallDuration(0.5).sleep();

  const cv::Mat img = iraf_vo_test::texturedImage(160, 120);
  uint32_t id = 1;
  // Every accepted encoding arrives as mono8 with the input header.
  for (const std::string& e : {enc::MONO8, enc::MONO16, enc::BGR8, enc::RGB8, enc::BGRA8}) {
    const auto out = roundTrip(img, e, id);
    ASSERT_TRUE(out) << "no output for encoding " << e;
    EXPECT_EQ(out->header.stamp, stampOf(id)) << e;
    EXPECT_EQ(out->header.frame_id, "cam0") << e;
    EXPECT_EQ(out->encoding, enc::MONO8) << e;
    EXPECT_EQ(out->width, 160u);
    EXPECT_EQ(out->height, 120u);
    ++id;
  }
  // Same gray content -> same output whatever the encoding.
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(cv::norm(toMat(*outputs_[1]), toMat(*outputs_[3]), cv::NORM_INF), 0.0);
    // mono16 -> mono8 goes through cv_bridge (scale 255/65535), one level off at most before enhancement.
    EXPECT_LE(cv::norm(toMat(*outputs_[1]), toMat(*outputs_[2]), cv::NORM_INF), 3.0);
  }

  // A bad encoding and an empty image are dropped; the next good frame still arrives.
  const uint32_t bad = id++, empty = id++, good = id++;
  publish(img, enc::TYPE_32FC1, bad);
  publish(cv::Mat(0, 0, CV_8U), enc::MONO8, empty);
  ASSERT_TRUE(roundTrip(img, enc::MONO8, good)) << "nodelet stopped after bad input";
  ros::WallDuration(0.3).sleep();
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(outputs_.count(bad), 0u) << "32FC1 image was not dropped";
    EXPECT_EQ(outputs_.count(empty), 0u) << "empty image was not dropped";
    ASSERT_TRUE(stats_.count(good));
    EXPECT_EQ(stats_[good]->brightness, iraf_vo::EnhanceStats::BRIGHTNESS_NORMAL);
    EXPECT_EQ(stats_[good]->method, "iraf");
  }

  // Live tuning 1: raise mu_expected so the same image is classified dim -> output gets brighter.
  const double mean_normal = cv::mean(toMat(*roundTrip(img, enc::MONO8, id++)))[0];
  reconfigure([](iraf_vo::EnhanceConfig& c) { c.mu_expected = 250.0; });
  const uint32_t dim_id = id++;
  const auto dim_out = roundTrip(img, enc::MONO8, dim_id);
  ASSERT_TRUE(dim_out);
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(mutex_); return stats_.count(dim_id) > 0; }, 2.0));
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(stats_[dim_id]->brightness, iraf_vo::EnhanceStats::BRIGHTNESS_DIM);
    EXPECT_LT(stats_[dim_id]->t, -0.3);
  }
  EXPECT_GT(cv::mean(toMat(*dim_out))[0], mean_normal + 10.0);

  // Live tuning 2: enabled=false passes the image through untouched.
  reconfigure([](iraf_vo::EnhanceConfig& c) { c.enabled = false; });
  const auto passthrough = roundTrip(img, enc::MONO8, id++);
  ASSERT_TRUE(passthrough);
  EXPECT_EQ(cv::norm(toMat(*passthrough), img, cv::NORM_INF), 0.0);
}

// A camera that stops publishing: a ROS_WARN naming the topic within 3 periods of the last frame, /diagnostics
// "enhance: input" ERROR naming it after ~input_timeout (1 s here), not any more when frames return (the earlier
// test's bad frames keep it at WARN "frames rejected").
TEST_F(EnhanceNodeletTest, AStoppedCameraIsReported) {
  std::mutex m;
  std::vector<rosgraph_msgs::LogConstPtr> log;
  diagnostic_msgs::DiagnosticStatus input;
  ros::Subscriber rosout = nh_.subscribe<rosgraph_msgs::Log>("/rosout", 200, [&](const rosgraph_msgs::LogConstPtr& l) {
    std::lock_guard<std::mutex> lock(m);
    if (l->msg.find("no image on") != std::string::npos) log.push_back(l);
  });
  ros::Subscriber diag = nh_.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50,
                                                                         [&](const diagnostic_msgs::DiagnosticArrayConstPtr& a) {
    std::lock_guard<std::mutex> lock(m);
    for (const auto& st : a->status)
      if (st.name == "enhance: input") input = st;
  });
  subscribeOutputs();
  ASSERT_TRUE(waitFor([&] { return pub_.getNumSubscribers() > 0; }, 15.0));
  const cv::Mat img = iraf_vo_test::texturedImage(160, 120);
  ros::WallTime last;
  for (uint32_t id = 500; id < 540; ++id) {  // 2 s at 20 Hz
    publish(img, enc::MONO8, id);
    last = ros::WallTime::now();
    ros::WallDuration(0.05).sleep();
  }
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> lock(m); return !log.empty(); }, 2.0)) << "no warning";
  {
    std::lock_guard<std::mutex> lock(m);
    EXPECT_EQ(log[0]->level, rosgraph_msgs::Log::WARN);
    EXPECT_NE(log[0]->msg.find("/image"), std::string::npos) << log[0]->msg;
    const double after = (ros::WallTime(log[0]->header.stamp.sec, log[0]->header.stamp.nsec) - last).toSec();
    EXPECT_LT(after, 0.15 + 0.05) << "warned " << after << " s after the last frame (3 periods: 0.15 s) " << log[0]->msg;
  }
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> lock(m); return input.level == diagnostic_msgs::DiagnosticStatus::ERROR; }, 4.0))
      << "diagnostics: " << input.message;
  {
    std::lock_guard<std::mutex> lock(m);
    EXPECT_NE(input.message.find("no image on /image"), std::string::npos) << input.message;
  }
  bool ok = false;
  for (uint32_t id = 600; id < 660 && !ok; ++id) {  // frames again (up to 3 s): OK at the next diagnostics update
    publish(img, enc::MONO8, id);
    ros::WallDuration(0.05).sleep();
    std::lock_guard<std::mutex> lock(m);
    ok = input.level != diagnostic_msgs::DiagnosticStatus::ERROR && input.message.find("no image") == std::string::npos;
  }
  EXPECT_TRUE(ok) << "diagnostics after the frames returned: " << input.message;
}

// dynamic_reconfigure shows the values in use: a rejected value (unknown enum name, NaN) is logged with its reason
// and reverted in the server, other fields of the same or later requests still apply, and every accepted change is
// logged as "enhance: <name> <old> -> <new>".
TEST_F(EnhanceNodeletTest, RejectedReconfigureValuesAreRevertedAndChangesLogged) {
  std::mutex log_mutex;
  std::vector<std::string> log;
  ros::Subscriber rosout = nh_.subscribe<rosgraph_msgs::Log>("/rosout", 200, [&](const rosgraph_msgs::LogConstPtr& m) {
    std::lock_guard<std::mutex> l(log_mutex);
    log.push_back(m->msg);
  });
  const auto logged = [&](const std::string& text) {
    return waitFor([&] {
      std::lock_guard<std::mutex> l(log_mutex);
      for (const std::string& m : log)
        if (m.find(text) != std::string::npos) return true;
      return false;
    }, 5.0);
  };
  dynamic_reconfigure::Client<iraf_vo::EnhanceConfig> client("enhance");
  iraf_vo::EnhanceConfig in_use, cfg;
  ASSERT_TRUE(client.getCurrentConfiguration(in_use, ros::Duration(5.0)));
  const auto current = [&] {
    iraf_vo::EnhanceConfig c;
    EXPECT_TRUE(client.getCurrentConfiguration(c, ros::Duration(5.0)));
    return c;
  };

  // An unknown method in the same request as a valid mu_expected change: the method is rejected and reverted,
  // mu_expected applies.
  cfg = in_use;
  cfg.method = "bogus";
  cfg.mu_expected = 60.0;
  ASSERT_TRUE(client.setConfiguration(cfg));
  ASSERT_TRUE(waitFor([&] { return current().mu_expected == 60.0; }, 5.0)) << current().mu_expected;
  EXPECT_EQ(current().method, in_use.method) << "the server still shows the rejected method";
  EXPECT_TRUE(logged("bogus")) << "the rejection is not logged";
  EXPECT_TRUE(logged("enhance: mu_expected " + iraf_vo::formatDouble(in_use.mu_expected) + " -> 60"));

  // NaN fails validation: reverted, logged with the reason; a later change of another field is not blocked.
  cfg = current();
  cfg.mu_expected = std::nan("");
  ASSERT_TRUE(client.setConfiguration(cfg));
  EXPECT_TRUE(logged("rejected mu_expected = nan"));
  ASSERT_TRUE(waitFor([&] { return current().mu_expected == 60.0; }, 5.0)) << current().mu_expected;
  cfg = current();
  cfg.brightness_threshold = in_use.brightness_threshold + 0.05;
  ASSERT_TRUE(client.setConfiguration(cfg));
  EXPECT_TRUE(logged("enhance: brightness_threshold " + iraf_vo::formatDouble(in_use.brightness_threshold) + " -> " +
                     iraf_vo::formatDouble(in_use.brightness_threshold + 0.05)));
  EXPECT_NEAR(current().brightness_threshold, in_use.brightness_threshold + 0.05, 1e-12);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "enhance_nodelet_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);  // callbacks (outputs, dynamic_reconfigure updates) run while the test waits
  spinner.start();
  return RUN_ALL_TESTS();
}
