// ImageInput (src/ros/image_input.cpp) in a live ROS graph: compressed jpeg / png arrive decoded as mono8 with
// their header; a topic ending in /compressed (also through a remapping) needs no transport; image_transport plugins that Debian lacks
// ("theora") or that do not exist ("bogus") log an error and fall back to raw, which still delivers; lazy
// subscribe / shutdown; a bag written by `iraf_vo_asl_to_bag --compressed` played with `rosbag play` goes through.
#include <gtest/gtest.h>

#include "common/wait_for.h"
#include <ros/ros.h>

#include <cstdlib>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include "common/tmp_dir.h"
#include "iraf_vo/ros/bag_reader.h"
#include "iraf_vo/ros/image_input.h"

using namespace iraf_vo;

namespace {

struct Received {
  std::mutex m;
  std::vector<std::pair<std_msgs::Header, cv::Mat>> images;
  ImageInput::Callback callback() {
    return [this](const std_msgs::Header& h, const cv::Mat& gray) {
      std::lock_guard<std::mutex> lock(m);
      images.emplace_back(h, gray.clone());
    };
  }
  size_t size() {
    std::lock_guard<std::mutex> lock(m);
    return images.size();
  }
};

using iraf_vo::test::waitFor;

cv::Mat gradient(int w = 64, int h = 48) {
  cv::Mat img(h, w, CV_8UC1);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) img.at<uchar>(r, c) = static_cast<uchar>((3 * c + 2 * r) % 256);
  return img;
}

sensor_msgs::CompressedImage compressed(const cv::Mat& img, const std::string& ext, uint32_t seq) {
  sensor_msgs::CompressedImage msg;
  msg.header.seq = seq;
  msg.header.stamp = ros::Time(100 + seq);
  msg.header.frame_id = "cam0";
  msg.format = ext == ".png" ? "mono8; png compressed mono8" : "mono8; jpeg compressed mono8";
  cv::imencode(ext, img, msg.data);
  return msg;
}

sensor_msgs::Image raw(const cv::Mat& img, uint32_t seq) {
  sensor_msgs::Image msg;
  msg.header.seq = seq;
  msg.header.stamp = ros::Time(200 + seq);
  msg.header.frame_id = "cam0";
  msg.width = img.cols;
  msg.height = img.rows;
  msg.encoding = sensor_msgs::image_encodings::MONO8;
  msg.step = img.cols;
  msg.data.assign(img.datastart, img.dataend);
  return msg;
}

}  // namespace

TEST(ImageInput, CompressedJpegAndPng) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::CompressedImage>("/cam_a/image_raw/compressed", 10);
  Received rx;
  // Relative topic in a namespace: resolved before /compressed is appended.
  ImageInput input(ros::NodeHandle("cam_a"), "image_raw", "compressed", 10, rx.callback());
  EXPECT_FALSE(input.subscribed());
  input.subscribe();
  EXPECT_TRUE(input.subscribed());
  EXPECT_EQ(input.activeTransport(), "compressed");
  EXPECT_EQ(input.subscribedTopic(), "/cam_a/image_raw/compressed");
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }));
  const cv::Mat img = gradient();
  pub.publish(compressed(img, ".png", 1));
  pub.publish(compressed(img, ".jpg", 2));
  sensor_msgs::CompressedImage garbage = compressed(img, ".png", 3);
  garbage.data.assign(10, 7);
  pub.publish(garbage);  // dropped, counted, no crash
  pub.publish(compressed(img, ".png", 4));
  ASSERT_TRUE(waitFor([&] { return rx.size() == 3 && input.dropped() == 1; })) << rx.size() << " " << input.dropped();
  std::lock_guard<std::mutex> lock(rx.m);
  EXPECT_EQ(rx.images[0].first.stamp, ros::Time(101));  // (roscpp renumbers header.seq: compare stamps)
  EXPECT_EQ(rx.images[0].first.frame_id, "cam0");
  EXPECT_EQ(rx.images[0].second.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(rx.images[0].second, img, cv::NORM_INF), 0.0);  // png: lossless
  EXPECT_EQ(rx.images[1].first.stamp, ros::Time(102));
  EXPECT_LT(cv::norm(rx.images[1].second, img, cv::NORM_L1) / img.total(), 3.0);  // jpeg: close
  EXPECT_EQ(rx.images[2].first.stamp, ros::Time(104));
  EXPECT_NE(input.lastError().find("cannot decode"), std::string::npos) << input.lastError();
  EXPECT_NE(input.lastError().find("/cam_a/image_raw/compressed"), std::string::npos) << input.lastError();
}

TEST(ImageInput, TopicEndingInCompressedNeedsNoTransport) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::CompressedImage>("/cam_b/image_raw/compressed", 10);
  Received rx;
  ImageInput input(nh, "/cam_b/image_raw/compressed", "raw", 10, rx.callback());
  input.subscribe();
  EXPECT_EQ(input.activeTransport(), "compressed");
  EXPECT_EQ(input.subscribedTopic(), "/cam_b/image_raw/compressed");
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }));
  pub.publish(compressed(gradient(), ".png", 1));
  ASSERT_TRUE(waitFor([&] { return rx.size() == 1; }));
  // Lazy subscription: shutdown() disconnects, subscribe() reconnects.
  input.shutdown();
  EXPECT_FALSE(input.subscribed());
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() == 0; }));
  input.subscribe();
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }));
  pub.publish(compressed(gradient(), ".png", 2));
  ASSERT_TRUE(waitFor([&] { return rx.size() == 2; }));
}

TEST(ImageInput, RemappedCompressedTopicSelectsTheTransport) {
  // A launch file's `image:=/cam_d/image_raw/compressed` with ~image_transport raw: the transport follows the
  // resolved topic (an unresolved "image" looked raw and subscribed a sensor_msgs/Image to a CompressedImage topic).
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::CompressedImage>("/cam_d/image_raw/compressed", 10);
  const ros::NodeHandle remapped(ros::NodeHandle(), "", ros::M_string{{"image", "/cam_d/image_raw/compressed"}});
  ASSERT_EQ(remapped.resolveName("image"), "/cam_d/image_raw/compressed");
  Received rx;
  ImageInput input(remapped, "image", "raw", 10, rx.callback());
  input.subscribe();
  EXPECT_EQ(input.activeTransport(), "compressed");
  EXPECT_EQ(input.subscribedTopic(), "/cam_d/image_raw/compressed");
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }));
  pub.publish(compressed(gradient(), ".png", 1));
  ASSERT_TRUE(waitFor([&] { return rx.size() == 1; })) << "no image through the remapped compressed topic";
  EXPECT_EQ(input.dropped(), 0u);
}

TEST(ImageInput, MissingPluginFallsBackToRaw) {
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<sensor_msgs::Image>("/cam_c/image_raw", 10);
  for (const std::string transport : {"theora", "bogus"}) {
    Received rx;
    ImageInput input(nh, "/cam_c/image_raw", transport, 10, rx.callback());
    input.subscribe();  // must not throw / abort
    EXPECT_EQ(input.activeTransport(), "raw") << transport;
    EXPECT_NE(input.lastError().find("'" + transport + "'"), std::string::npos) << input.lastError();
    EXPECT_NE(input.lastError().find("falling back to raw"), std::string::npos) << input.lastError();
    EXPECT_NE(input.lastError().find("/cam_c/image_raw"), std::string::npos) << input.lastError();
    ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; })) << transport;
    const cv::Mat img = gradient();
    pub.publish(raw(img, 1));
    sensor_msgs::Image bad = raw(img, 2);
    bad.encoding = "yuv422";
    pub.publish(bad);  // unsupported encoding: dropped with an error naming it
    ASSERT_TRUE(waitFor([&] { return rx.size() == 1 && input.dropped() == 1; })) << transport;
    EXPECT_EQ(cv::norm(rx.images[0].second, img, cv::NORM_INF), 0.0);
    EXPECT_NE(input.lastError().find("yuv422"), std::string::npos) << input.lastError();
    // Re-subscribing after a failed plugin goes straight to raw.
    input.shutdown();
    input.subscribe();
    EXPECT_EQ(input.activeTransport(), "raw");
    input.shutdown();
    ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() == 0; })) << transport;
  }
}

TEST(ImageInput, CompressedBagPlayedThroughTheGraph) {
  // ASL folder -> aslToBag(--compressed png) -> `rosbag play` -> ImageInput("compressed").
  const std::string dir = tmpRoot() + "image_input_asl";
  ASSERT_EQ(std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "/mav0/cam0/data'").c_str()), 0);
  std::ofstream csv(dir + "/mav0/cam0/data.csv");
  csv << "#timestamp [ns],filename\n";
  const int n = 5;
  for (int k = 0; k < n; ++k) {
    const int64_t stamp = 1403636584763555584LL + k * 50000000LL;
    cv::Mat img = gradient() + k;
    cv::imwrite(dir + "/mav0/cam0/data/" + std::to_string(stamp) + ".png", img);
    csv << stamp << "," << stamp << ".png\n";
  }
  csv.close();
  AslToBagOptions opt;
  opt.topic = "/played/image_raw";
  opt.image_format = "png";
  std::string err;
  const std::string bag = dir + "/c.bag";
  ASSERT_EQ(aslToBag(dir, bag, opt, &err), static_cast<size_t>(n)) << err;
  Received rx;
  ros::NodeHandle nh;
  ImageInput input(nh, "/played/image_raw", "compressed", 10, rx.callback());
  input.subscribe();
  // --delay: the player waits after advertising so the subscription is connected before the first message.
  ASSERT_EQ(std::system(("rosbag play -q --delay=1.5 '" + bag + "' >/dev/null").c_str()), 0);
  ASSERT_TRUE(waitFor([&] { return rx.size() == static_cast<size_t>(n); })) << rx.size();
  std::lock_guard<std::mutex> lock(rx.m);
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(rx.images[k].first.stamp.toNSec(), static_cast<uint64_t>(1403636584763555584LL + k * 50000000LL));
    EXPECT_EQ(rx.images[k].first.frame_id, "cam0");
    EXPECT_EQ(cv::norm(rx.images[k].second, gradient() + k, cv::NORM_INF), 0.0) << k;
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "image_input_test");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
