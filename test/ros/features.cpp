// rostest of FeatureNodelet: lazy subscription, image in -> Features out (stamp, array sizes, message
// round trip to the core type), bad input dropped, debug image, live dynamic_reconfigure of a threshold.
#include <gtest/gtest.h>

#include "common/wait_for.h"

#include <dynamic_reconfigure/client.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <mutex>

#include "common/test_data.h"
#include "iraf_vo/EnhanceStats.h"
#include "iraf_vo/Features.h"
#include "iraf_vo/FeaturesConfig.h"
#include "iraf_vo/EnhanceConfig.h"
#include "iraf_vo/TrackerConfig.h"
#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/ros/feature_conversion.h"
#include "iraf_vo/tracking/tracker_params.h"
#include "../../src/nodelets/param_bridge.h"

namespace enc = sensor_msgs::image_encodings;
using iraf_vo::test::waitFor;

class FeatureNodeletTest : public ::testing::Test {
 protected:
  void SetUp() override {
    pub_ = nh_.advertise<sensor_msgs::Image>("image_enhanced", 10);
    stats_pub_ = nh_.advertise<iraf_vo::EnhanceStats>("enhance_stats", 10);
  }

  static ros::Time stampOf(uint32_t id) { return ros::Time(2000.0 + id * 0.05); }
  static uint32_t idOf(const ros::Time& t) { return static_cast<uint32_t>(std::lround((t.toSec() - 2000.0) / 0.05)); }

  void publish(const cv::Mat& gray, const std::string& encoding, uint32_t id) {
    sensor_msgs::Image m;
    m.header.stamp = stampOf(id);
    m.header.frame_id = "cam0";
    cv::Mat conv;
    if (encoding == enc::MONO8) conv = gray;
    else if (encoding == enc::BGR8) cv::cvtColor(gray, conv, cv::COLOR_GRAY2BGR);
    else gray.convertTo(conv, CV_32F);  // unsupported encoding: float data
    m.encoding = encoding;
    m.height = conv.rows;
    m.width = conv.cols;
    m.step = conv.cols * conv.elemSize();
    m.data.assign(conv.data, conv.data + conv.total() * conv.elemSize());
    pub_.publish(m);
  }

  iraf_vo::FeaturesConstPtr roundTrip(const cv::Mat& gray, const std::string& encoding, uint32_t id) {
    publish(gray, encoding, id);
    iraf_vo::FeaturesConstPtr out;
    waitFor([&] {
      std::lock_guard<std::mutex> l(mutex_);
      auto it = features_.find(id);
      if (it != features_.end()) out = it->second;
      return out != nullptr;
    }, 5.0);
    return out;
  }

  void reconfigure(const std::function<void(iraf_vo::FeaturesConfig&)>& change) {
    dynamic_reconfigure::Client<iraf_vo::FeaturesConfig> client("features");
    iraf_vo::FeaturesConfig cfg;
    ASSERT_TRUE(client.getCurrentConfiguration(cfg, ros::Duration(5.0)));
    change(cfg);
    ASSERT_TRUE(client.setConfiguration(cfg));
  }

  ros::NodeHandle nh_;
  ros::Publisher pub_, stats_pub_;
  ros::Subscriber feat_sub_, image_sub_;
  std::mutex mutex_;
  std::map<uint32_t, iraf_vo::FeaturesConstPtr> features_;
  std::map<uint32_t, sensor_msgs::ImageConstPtr> images_;
};

TEST_F(FeatureNodeletTest, FeaturesOutStampsSizesBadInputAndLiveTuning) {
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(pub_.getNumSubscribers(), 0u) << "FeatureNodelet subscribed although nobody listens";

  feat_sub_ = nh_.subscribe<iraf_vo::Features>("features", 20, [this](const iraf_vo::FeaturesConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    features_[idOf(m->header.stamp)] = m;
  });
  ASSERT_TRUE(waitFor([&] { return pub_.getNumSubscribers() > 0; }, 15.0)) << "nodelet never subscribed";
  ros::WallDuration(0.5).sleep();

  const cv::Mat img = iraf_vo_test::texturedImage(320, 240);
  uint32_t id = 1;
  for (const std::string& e : {enc::MONO8, enc::BGR8}) {
    const auto f = roundTrip(img, e, id);
    ASSERT_TRUE(f) << "no Features for encoding " << e;
    EXPECT_EQ(f->header.stamp, stampOf(id));
    EXPECT_EQ(f->header.frame_id, "cam0");
    EXPECT_EQ(f->width, 320u);
    EXPECT_EQ(f->height, 240u);
    const size_t n = f->x.size();
    EXPECT_GT(n, 50u);
    EXPECT_LE(n, 510u);  // n_features = 500 from the launch file
    EXPECT_EQ(f->y.size(), n);
    EXPECT_EQ(f->size.size(), n);
    EXPECT_EQ(f->angle.size(), n);
    EXPECT_EQ(f->response.size(), n);
    EXPECT_EQ(f->octave.size(), n);
    EXPECT_EQ(f->fast_threshold.size(), n);
    EXPECT_EQ(f->stability.size(), n);
    EXPECT_EQ(f->descriptors.size(), 32 * n);
    EXPECT_EQ(f->detected, static_cast<int>(n) + f->culled);
    EXPECT_GT(f->global_threshold, 0.f);
    EXPECT_LE(f->cell_threshold_min, f->cell_threshold_median);
    EXPECT_LE(f->cell_threshold_median, f->cell_threshold_max);
    // The message rebuilds a core FeatureFrame.
    iraf_vo::FeatureFrame core;
    std::string err;
    ASSERT_TRUE(iraf_vo::fromMsg(*f, &core, &err)) << err;
    EXPECT_EQ(core.keypoints.size(), n);
    EXPECT_EQ(core.descriptors.rows, static_cast<int>(n));
    EXPECT_NEAR(core.stamp, stampOf(id).toSec(), 1e-6);
    ++id;
  }
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(features_[1]->x, features_[2]->x) << "mono8 and bgr8 of the same image differ";
    EXPECT_EQ(features_[1]->brightness, 0) << "no EnhanceStats was published: unknown = 0";
  }

  // The enhancement class is taken from enhance_stats with the same stamp.
  ASSERT_TRUE(waitFor([&] { return stats_pub_.getNumSubscribers() > 0; }, 5.0)) << "no enhance_stats subscription";
  {
    const uint32_t dim_id = id++;
    iraf_vo::EnhanceStats st;
    st.header.stamp = stampOf(dim_id);
    st.brightness = iraf_vo::EnhanceStats::BRIGHTNESS_DIM;
    stats_pub_.publish(st);
    ros::WallDuration(0.2).sleep();
    const auto f = roundTrip(img, enc::MONO8, dim_id);
    ASSERT_TRUE(f);
    EXPECT_EQ(f->brightness, iraf_vo::EnhanceStats::BRIGHTNESS_DIM);
  }

  // Bad input is dropped; the next good frame still arrives.
  const uint32_t bad = id++, empty = id++;
  publish(img, enc::TYPE_32FC1, bad);
  publish(cv::Mat(0, 0, CV_8U), enc::MONO8, empty);
  ASSERT_TRUE(roundTrip(img, enc::MONO8, id++)) << "nodelet stopped after bad input";
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(features_.count(bad), 0u);
    EXPECT_EQ(features_.count(empty), 0u);
  }

  // Debug image: bgr8, same size, published only while subscribed.
  image_sub_ = nh_.subscribe<sensor_msgs::Image>("features_image", 5, [this](const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> l(mutex_);
    images_[idOf(m->header.stamp)] = m;
  });
  ros::WallDuration(0.5).sleep();
  const uint32_t dbg = id++;
  ASSERT_TRUE(roundTrip(img, enc::MONO8, dbg));
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(mutex_); return images_.count(dbg) > 0; }, 5.0));
  {
    std::lock_guard<std::mutex> l(mutex_);
    EXPECT_EQ(images_[dbg]->encoding, enc::BGR8);
    EXPECT_EQ(images_[dbg]->width, 320u);
    EXPECT_EQ(images_[dbg]->height, 240u);
  }

  // Live tuning: adaptive off with a fixed threshold of 45 -> reported thresholds follow.
  const auto before = roundTrip(img, enc::MONO8, id++);
  ASSERT_TRUE(before);
  reconfigure([](iraf_vo::FeaturesConfig& c) {
    c.adaptive_threshold = false;
    c.ini_th_fast = 45;
    c.min_th_fast = 45;
    c.culling = false;
  });
  const auto after = roundTrip(img, enc::MONO8, id++);
  ASSERT_TRUE(after);
  EXPECT_FLOAT_EQ(after->global_threshold, 45.f);
  EXPECT_FLOAT_EQ(after->cell_threshold_min, 45.f);
  EXPECT_FLOAT_EQ(after->cell_threshold_max, 45.f);
  EXPECT_EQ(after->culled, 0);
  EXPECT_NE(after->global_threshold, before->global_threshold);
  for (int16_t t : after->fast_threshold) EXPECT_EQ(t, 45);
  EXPECT_LT(after->x.size(), before->x.size());
}

TEST(FeatureConversion, RoundTripAndInconsistentMessages) {
  iraf_vo::FeatureFrame f;
  f.width = 64;
  f.height = 48;
  f.keypoints = {cv::KeyPoint(10.5f, 20.25f, 37.2f, 123.f, 55.f, 1, 17), cv::KeyPoint(30.f, 40.f, 31.f, 5.f, 9.f, 0, 7)};
  f.descriptors = cv::Mat(2, 32, CV_8U);
  cv::randu(f.descriptors, 0, 256);
  f.stability = {0.9f, 0.45f};
  f.stats.global_threshold = 19.5;
  f.stats.culled = 3;
  f.stats.detected = 5;
  f.stats.brightness = -1;
  f.scale_factor = 1.3;
  f.signal.measured = true;
  f.signal.mean = 248.5;
  f.signal.snr = 3.25;
  f.signal.clipped = 0.875;  // the tracker's "washed out" check reads it
  std_msgs::Header h;
  h.stamp = ros::Time(12.5);
  iraf_vo::Features m;
  iraf_vo::toMsg(f, h, &m);
  iraf_vo::FeatureFrame g;
  std::string err;
  ASSERT_TRUE(iraf_vo::fromMsg(m, &g, &err)) << err;
  EXPECT_DOUBLE_EQ(g.stamp, 12.5);
  EXPECT_EQ(g.width, 64);
  ASSERT_EQ(g.keypoints.size(), 2u);
  EXPECT_EQ(g.keypoints[0].pt, f.keypoints[0].pt);
  EXPECT_FLOAT_EQ(g.keypoints[0].angle, 123.f);
  EXPECT_EQ(g.keypoints[0].octave, 1);
  EXPECT_EQ(g.keypoints[0].class_id, 17);
  EXPECT_EQ(cv::norm(g.descriptors, f.descriptors, cv::NORM_INF), 0.0);
  EXPECT_EQ(g.stability, f.stability);
  EXPECT_DOUBLE_EQ(g.stats.global_threshold, 19.5);
  EXPECT_EQ(g.stats.culled, 3);
  EXPECT_EQ(g.stats.brightness, -1);
  EXPECT_DOUBLE_EQ(m.scale_factor, 1.3);
  EXPECT_DOUBLE_EQ(g.scale_factor, 1.3);  // the pyramid scale travels with the features
  EXPECT_TRUE(g.signal.measured);
  EXPECT_DOUBLE_EQ(g.signal.mean, 248.5);
  EXPECT_DOUBLE_EQ(g.signal.snr, 3.25);
  EXPECT_DOUBLE_EQ(g.signal.clipped, 0.875);

  // A sender without scale_factor (0): estimated from the keypoint sizes (37.2 = 31 * 1.2 at octave 1), warned.
  iraf_vo::Features old = m;
  old.scale_factor = 0.0;
  std::string warning;
  ASSERT_TRUE(iraf_vo::fromMsg(old, &g, &err, &warning)) << err;
  EXPECT_NEAR(g.scale_factor, 1.2, 1e-5);
  EXPECT_NE(warning.find("scale_factor"), std::string::npos) << warning;
  old.octave = {0, 0};  // nothing to estimate from: the ORB-SLAM default
  ASSERT_TRUE(iraf_vo::fromMsg(old, &g, &err, &warning)) << err;
  EXPECT_DOUBLE_EQ(g.scale_factor, 1.2);

  iraf_vo::Features bad = m;
  bad.scale_factor = 0.5;
  EXPECT_FALSE(iraf_vo::fromMsg(bad, &g, &err));
  EXPECT_NE(err.find("scale_factor"), std::string::npos) << err;
  bad = m;
  bad.y.pop_back();
  EXPECT_FALSE(iraf_vo::fromMsg(bad, &g, &err));
  EXPECT_NE(err.find("differ in length"), std::string::npos) << err;
  bad = m;
  bad.descriptors.resize(40);
  EXPECT_FALSE(iraf_vo::fromMsg(bad, &g, &err));
  EXPECT_NE(err.find("descriptors"), std::string::npos) << err;
  bad = m;
  bad.x[1] = std::nanf("");
  EXPECT_FALSE(iraf_vo::fromMsg(bad, &g, &err));
  EXPECT_NE(err.find("non-finite"), std::string::npos) << err;
}

// The typed dynamic_reconfigure bridge of the stage nodelets (src/nodelets/param_bridge.h): the generated Configs'
// defaults become the structs' defaults for every table entry, without errors; odd fields are rounded up; a bad enum
// name keeps the previous value and names the parameter.
template <class S, class Config>
void expectConfigDefaultsAreStructDefaults(const iraf_vo::ParamTable<S>& table) {
  S p;
  std::vector<std::string> errors;
  iraf_vo::configToParams(table, Config::__getDefault__(), &p, &errors);
  EXPECT_TRUE(errors.empty()) << errors.front();
  const S defaults{};
  for (const iraf_vo::ParamEntry<S>& e : table.entries()) EXPECT_EQ(table.get(p, e), table.get(defaults, e)) << e.name;
}

TEST(ParamBridge, ConfigsMapOntoTheParameterTables) {
  expectConfigDefaultsAreStructDefaults<iraf_vo::EnhanceParams, iraf_vo::EnhanceConfig>(iraf_vo::enhanceParamTable());
  expectConfigDefaultsAreStructDefaults<iraf_vo::FeatureParams, iraf_vo::FeaturesConfig>(iraf_vo::featureParamTable());
  expectConfigDefaultsAreStructDefaults<iraf_vo::TrackerParams, iraf_vo::TrackerConfig>(iraf_vo::trackerParamTable());

  iraf_vo::FeaturesConfig fc = iraf_vo::FeaturesConfig::__getDefault__();
  fc.center_window = 4;
  fc.ini_th_fast = 33;
  fc.culling = false;
  fc.h_th = 9.5;
  iraf_vo::FeatureParams fp;
  std::vector<std::string> errors;
  iraf_vo::configToParams(iraf_vo::featureParamTable(), fc, &fp, &errors);
  EXPECT_TRUE(errors.empty());
  EXPECT_EQ(fp.center_window, 5);  // sliders may give even sizes: rounded up to odd
  EXPECT_EQ(fp.ini_th_fast, 33);
  EXPECT_FALSE(fp.culling);
  EXPECT_DOUBLE_EQ(fp.h_th, 9.5);

  iraf_vo::EnhanceConfig ec = iraf_vo::EnhanceConfig::__getDefault__();
  ec.method = "fancy";
  ec.mu_expected = 80.0;
  iraf_vo::EnhanceParams ep;
  ep.method = iraf_vo::EnhanceMethod::kClahe;
  iraf_vo::configToParams(iraf_vo::enhanceParamTable(), ec, &ep, &errors);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].find("fancy"), std::string::npos) << errors[0];
  EXPECT_EQ(ep.method, iraf_vo::EnhanceMethod::kClahe);  // kept
  EXPECT_DOUBLE_EQ(ep.mu_expected, 80.0);               // the other fields still apply
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "feature_nodelet_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
