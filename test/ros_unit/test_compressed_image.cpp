// toMono8(sensor_msgs::CompressedImage) (src/ros/image_conversion.cpp): jpeg / png, 8 / 16 bit, mono / colour
// become CV_8UC1; garbage, empty data and compressedDepth give an error naming the format, never a crash.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/ros/image_conversion.h"

using namespace iraf_vo;

namespace {

cv::Mat gradient(int w = 64, int h = 48) {
  cv::Mat img(h, w, CV_8UC1);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) img.at<uchar>(r, c) = static_cast<uchar>((3 * c + 2 * r) % 256);
  return img;
}

sensor_msgs::CompressedImage encode(const cv::Mat& img, const std::string& ext, const std::string& format) {
  sensor_msgs::CompressedImage msg;
  msg.format = format;
  EXPECT_TRUE(cv::imencode(ext, img, msg.data));
  return msg;
}

}  // namespace

TEST(CompressedImage, PngMono8IsLossless) {
  const cv::Mat img = gradient();
  cv::Mat gray;
  std::string err;
  ASSERT_TRUE(toMono8(encode(img, ".png", "mono8; png compressed mono8"), &gray, &err)) << err;
  ASSERT_EQ(gray.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(gray, img, cv::NORM_INF), 0.0);
}

TEST(CompressedImage, Png16BitScaledTo8Bit) {
  cv::Mat img16;
  gradient().convertTo(img16, CV_16U, 256.0);
  cv::Mat gray;
  std::string err;
  ASSERT_TRUE(toMono8(encode(img16, ".png", "mono16; png compressed mono16"), &gray, &err)) << err;
  ASSERT_EQ(gray.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(gray, gradient(), cv::NORM_INF), 0.0);
}

TEST(CompressedImage, JpegMonoAndColour) {
  const cv::Mat img = gradient();
  cv::Mat gray;
  std::string err;
  ASSERT_TRUE(toMono8(encode(img, ".jpg", "mono8; jpeg compressed mono8"), &gray, &err)) << err;
  ASSERT_EQ(gray.type(), CV_8UC1);
  ASSERT_EQ(gray.size(), img.size());
  EXPECT_LT(cv::norm(gray, img, cv::NORM_L1) / img.total(), 3.0);  // lossy but close
  cv::Mat bgr;
  cv::cvtColor(img, bgr, cv::COLOR_GRAY2BGR);
  ASSERT_TRUE(toMono8(encode(bgr, ".jpg", "bgr8; jpeg compressed bgr8"), &gray, &err)) << err;
  ASSERT_EQ(gray.type(), CV_8UC1);
  EXPECT_LT(cv::norm(gray, img, cv::NORM_L1) / img.total(), 3.0);
}

TEST(CompressedImage, BadDataGivesErrorNamingTheFormat) {
  cv::Mat gray;
  std::string err;
  sensor_msgs::CompressedImage msg;
  msg.format = "jpeg";
  EXPECT_FALSE(toMono8(msg, &gray, &err));
  EXPECT_NE(err.find("format 'jpeg'"), std::string::npos) << err;
  EXPECT_NE(err.find("no data"), std::string::npos) << err;
  msg.data = {0xff, 0xd8, 0xff, 0x00, 1, 2, 3, 4, 5};
  EXPECT_FALSE(toMono8(msg, &gray, &err));
  EXPECT_NE(err.find("cannot decode"), std::string::npos) << err;
  // A png cut in half.
  sensor_msgs::CompressedImage cut = encode(gradient(), ".png", "png");
  cut.data.resize(cut.data.size() / 2);
  EXPECT_FALSE(toMono8(cut, &gray, &err));
  EXPECT_NE(err.find("format 'png'"), std::string::npos) << err;
  sensor_msgs::CompressedImage depth = encode(gradient(), ".png", "16UC1; compressedDepth");
  EXPECT_FALSE(toMono8(depth, &gray, &err));
  EXPECT_NE(err.find("compressedDepth"), std::string::npos) << err;
}
