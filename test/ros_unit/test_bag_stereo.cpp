// A stereo ASL folder -> rosbag (aslToBag writes cam1 beside cam0) -> the offline bag FrameSource with a right topic:
// each left image comes with its right partner, pixel for pixel; left images without one (a right image missing, one
// 20 ms off, the right camera stopping early) come alone and are counted; a folder without cam1 gives a mono bag.
#include <gtest/gtest.h>

#include <cstdlib>
#include <opencv2/core.hpp>

#include "common/tmp_dir.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/pipeline/bag_frame_source.h"
#include "iraf_vo/ros/bag_reader.h"

using namespace iraf_vo;

namespace {

constexpr int64_t kT0 = 1403636580000000000LL, kPeriod = 50000000LL;  // 20 Hz

cv::Mat image(int k, int camera) {
  cv::Mat img(24, 32, CV_8UC1, cv::Scalar(0));
  img.at<uchar>(0, 0) = static_cast<uchar>(k);
  img.at<uchar>(0, 1) = static_cast<uchar>(camera);
  return img;
}

/// cam0: frames 0-7. cam1: frames 0, 1, 3 (2 missing), frame 4 stamped 20 ms late, 5; nothing after 5.
std::string makeStereoAsl(bool with_cam1) {
  const std::string root = tmpRoot() + (with_cam1 ? "stereo_asl" : "mono_asl");
  std::system(("rm -rf '" + root + "'").c_str());
  std::string err;
  AslImageWriter left, right;
  EXPECT_TRUE(left.open(root, &err, nullptr, "cam0")) << err;
  for (int k = 0; k < 8; ++k) EXPECT_TRUE(left.write(kT0 + k * kPeriod, image(k, 0), &err)) << err;
  left.close();
  if (!with_cam1) return root;
  EXPECT_TRUE(right.open(root, &err, nullptr, "cam1")) << err;
  for (int k : {0, 1, 3, 4, 5})
    EXPECT_TRUE(right.write(kT0 + k * kPeriod + (k == 4 ? 20000000LL : 0), image(k, 1), &err)) << err;
  right.close();
  return root;
}

TEST(BagStereo, AslToBagWritesCam1AndTheBagSourcePairsByStamp) {
  const std::string bag = tmpRoot() + "stereo.bag";
  std::string err;
  std::vector<std::string> warnings;
  size_t n_right = 0;
  ASSERT_EQ(aslToBag(makeStereoAsl(true), bag, AslToBagOptions(), &err, &warnings, &n_right), 8u) << err;
  EXPECT_EQ(n_right, 5u);

  BagSourceOptions o;
  o.topic = "/cam0/image_raw";
  o.right_topic = "/cam1/image_raw";
  std::unique_ptr<FrameSource> source = openBagFrameSource(bag, o, &err);
  ASSERT_TRUE(source) << err;
  ASSERT_EQ(source->size(), 8u);
  std::vector<int> paired;
  for (long i = 0; i < 8; ++i) {
    SourceImage im;
    ASSERT_TRUE(source->read(i, &im)) << i;
    EXPECT_EQ(im.gray.at<uchar>(0, 0), i);
    EXPECT_EQ(im.gray.at<uchar>(0, 1), 0);
    if (im.right.empty()) continue;
    EXPECT_EQ(im.right.at<uchar>(0, 0), i) << "the right image of left frame " << i;
    EXPECT_EQ(im.right.at<uchar>(0, 1), 1);
    paired.push_back(static_cast<int>(i));
  }
  SourceImage end;
  EXPECT_FALSE(source->read(8, &end));
  EXPECT_EQ(paired, (std::vector<int>{0, 1, 3, 5}));
  const std::string summary = source->skippedSummary();
  EXPECT_NE(summary.find("4 left image(s) without a right partner"), std::string::npos) << summary;
  EXPECT_NE(summary.find("1 right image(s) without a left partner dropped"), std::string::npos) << summary;

  // Reading from a later first frame skips the earlier pairs consistently.
  std::unique_ptr<FrameSource> again = openBagFrameSource(bag, o, &err);
  ASSERT_TRUE(again) << err;
  SourceImage im5;
  ASSERT_TRUE(again->read(5, &im5));
  ASSERT_FALSE(im5.right.empty());
  EXPECT_EQ(im5.right.at<uchar>(0, 0), 5);
}

TEST(BagStereo, MonoFolderAndBadRightTopic) {
  const std::string bag = tmpRoot() + "mono.bag";
  std::string err;
  size_t n_right = 7;
  ASSERT_EQ(aslToBag(makeStereoAsl(false), bag, AslToBagOptions(), &err, nullptr, &n_right), 8u) << err;
  EXPECT_EQ(n_right, 0u);
  BagSourceOptions o;
  o.topic = "/cam0/image_raw";
  std::unique_ptr<FrameSource> mono = openBagFrameSource(bag, o, &err);
  ASSERT_TRUE(mono) << err;
  SourceImage im;
  ASSERT_TRUE(mono->read(0, &im));
  EXPECT_TRUE(im.right.empty());
  o.right_topic = "/cam1/image_raw";
  EXPECT_FALSE(openBagFrameSource(bag, o, &err));
  EXPECT_NE(err.find("/cam1/image_raw"), std::string::npos) << err;
}

}  // namespace
