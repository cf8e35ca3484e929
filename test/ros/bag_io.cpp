// Bag round trip: a temp ASL folder written here -> rosbag (aslToBag and the iraf_vo_asl_to_bag tool) ->
// BagImageReader; pixels and stamps must come back exactly. Bad bags give errors, never crashes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <ros/time.h>
#include <sensor_msgs/CompressedImage.h>
#include <sys/stat.h>

#include "iraf_vo/ros/bag_reader.h"

using namespace iraf_vo;

#include "common/tmp_dir.h"

namespace {

std::string tmpDir(const std::string& name) {
  const std::string d = tmpRoot() + "iraf_vo_bag_" + name;
  std::system(("rm -rf '" + d + "' && mkdir -p '" + d + "'").c_str());
  return d;
}

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

const int64_t kStamps[] = {1403636584763555584LL, 1403636584813555456LL, 1403636584863555584LL,
                           1403636584913555456LL, 1403636584963555584LL};

cv::Mat makeImage(int k) {
  cv::Mat img(24, 32, CV_8UC1);
  cv::randu(img, cv::Scalar(0), cv::Scalar(256));
  img.at<uchar>(0, 0) = static_cast<uchar>(k);
  return img;
}

/// ASL folder with 5 images; image 3 is stored as colour (converted to gray on read), image 4's file is corrupt.
std::string makeAsl(std::vector<cv::Mat>* expected) {
  const std::string root = tmpDir("asl");
  const std::string cam = root + "/mav0/cam0";
  std::system(("mkdir -p '" + cam + "/data'").c_str());
  std::ofstream csv(cam + "/data.csv");
  csv << "#timestamp [ns],filename\n";
  cv::theRNG().state = 1234;
  for (int k = 0; k < 5; ++k) {
    const std::string name = std::to_string(kStamps[k]) + ".png";
    csv << kStamps[k] << "," << name << "\n";
    cv::Mat img = makeImage(k);
    if (k == 3) {
      cv::Mat bgr;
      cv::Mat ch[] = {img, img, img};
      cv::merge(ch, 3, bgr);  // equal channels: gray conversion gives img back exactly
      cv::imwrite(cam + "/data/" + name, bgr);
    } else if (k == 4) {
      std::ofstream(cam + "/data/" + name) << "corrupt";
      continue;
    } else {
      cv::imwrite(cam + "/data/" + name, img);
    }
    expected->push_back(img);
  }
  return root;
}

void readBack(const std::string& bag, const std::string& topic, const std::vector<cv::Mat>& expected,
              const std::string& frame_note) {
  BagImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(bag, topic, &err)) << err;
  EXPECT_EQ(reader.size(), expected.size());
  ros::Time stamp;
  cv::Mat gray;
  size_t n = 0;
  while (reader.next(&stamp, &gray)) {
    ASSERT_LT(n, expected.size());
    EXPECT_EQ(static_cast<int64_t>(stamp.toNSec()), kStamps[n]) << frame_note << " image " << n;
    ASSERT_EQ(gray.type(), CV_8UC1);
    ASSERT_EQ(gray.size(), expected[n].size());
    EXPECT_EQ(cv::norm(gray, expected[n], cv::NORM_INF), 0.0) << frame_note << " image " << n;
    ++n;
  }
  EXPECT_EQ(n, expected.size());
  EXPECT_TRUE(reader.error().empty()) << reader.error();
}

}  // namespace

TEST(BagIO, AslToBagRoundTrip) {
  std::vector<cv::Mat> expected;
  const std::string root = makeAsl(&expected);
  const std::string bag = tmpDir("out") + "/cam.bag";
  AslToBagOptions opt;
  std::string err;
  std::vector<std::string> warnings;
  ASSERT_EQ(aslToBag(root, bag, opt, &err, &warnings), 4u) << err;
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find(std::to_string(kStamps[4]) + ".png"), std::string::npos) << warnings[0];
  readBack(bag, "/cam0/image_raw", expected, "library");
  const std::vector<std::string> topics = BagImageReader::imageTopics(bag, &err);
  ASSERT_EQ(topics.size(), 1u);
  EXPECT_EQ(topics[0], "/cam0/image_raw");

  // lz4 compression reads back the same.
  opt.compression = "lz4";
  opt.topic = "/cam/other";
  ASSERT_EQ(aslToBag(root + "/mav0/cam0", bag + ".lz4.bag", opt, &err), 4u) << err;
  readBack(bag + ".lz4.bag", "/cam/other", expected, "lz4");
}

TEST(BagIO, Tool) {
  const std::string tool = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_asl_to_bag";
  if (!exists(tool)) GTEST_SKIP() << "tool not built: " << tool;
  std::vector<cv::Mat> expected;
  const std::string root = makeAsl(&expected);
  const std::string bag = tmpDir("tool") + "/tool.bag";
  ASSERT_EQ(std::system((tool + " '" + root + "' '" + bag + "' --topic /x/image --frame-id camx 2>/dev/null >/dev/null").c_str()), 0);
  readBack(bag, "/x/image", expected, "tool");
  // Bad input: non-zero exit.
  EXPECT_NE(std::system((tool + " /nonexistent/asl '" + bag + ".2' 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " '" + root + "' 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " '" + root + "' '" + bag + ".3' --compression zip 2>/dev/null").c_str()), 0);
  // --compressed: sensor_msgs/CompressedImage on TOPIC/compressed; png is lossless, jpeg close.
  ASSERT_EQ(std::system((tool + " '" + root + "' '" + bag + ".png.bag' --topic /x/image --compressed >/dev/null").c_str()), 0);
  readBack(bag + ".png.bag", "/x/image/compressed", expected, "tool --compressed");
  ASSERT_EQ(std::system((tool + " '" + root + "' '" + bag + ".jpg.bag' --compressed=jpeg --jpeg-quality 90 >/dev/null").c_str()), 0);
  BagImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(bag + ".jpg.bag", "/cam0/image_raw/compressed", &err)) << err;
  ros::Time t;
  cv::Mat gray;
  for (size_t n = 0; n < expected.size(); ++n) {
    ASSERT_TRUE(reader.next(&t, &gray)) << n;
    EXPECT_EQ(static_cast<int64_t>(t.toNSec()), kStamps[n]);
    EXPECT_LT(cv::norm(gray, expected[n], cv::NORM_L1) / gray.total(), 40.0) << n;  // random pixels: jpeg's worst case
  }
  EXPECT_FALSE(reader.next(&t, &gray));
  EXPECT_NE(std::system((tool + " '" + root + "' '" + bag + ".4' --compressed=gif 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " '" + root + "' '" + bag + ".5' --compressed=jpeg --jpeg-quality 0 2>/dev/null").c_str()), 0);
}

TEST(BagIO, CompressedImages) {
  const std::string bag = tmpDir("compressed") + "/c.bag";
  std::vector<cv::Mat> expected;
  {
    rosbag::Bag b(bag, rosbag::bagmode::Write);
    cv::theRNG().state = 99;
    for (int k = 0; k < 3; ++k) {
      sensor_msgs::CompressedImage msg;
      msg.header.stamp.fromNSec(kStamps[k]);
      msg.format = "png";
      cv::Mat img = makeImage(k);
      cv::imencode(".png", img, msg.data);
      b.write("/cam0/image_raw/compressed", msg.header.stamp, msg);
      expected.push_back(img);
    }
    sensor_msgs::CompressedImage broken;
    broken.header.stamp.fromNSec(kStamps[3]);
    broken.format = "png";
    broken.data = {1, 2, 3};
    b.write("/cam0/image_raw/compressed", broken.header.stamp, broken);
  }
  BagImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(bag, "/cam0/image_raw/compressed", &err)) << err;
  ros::Time stamp;
  cv::Mat gray;
  size_t n = 0;
  while (reader.next(&stamp, &gray)) {
    EXPECT_EQ(static_cast<int64_t>(stamp.toNSec()), kStamps[n]);
    EXPECT_EQ(cv::norm(gray, expected[n], cv::NORM_INF), 0.0);
    ++n;
  }
  EXPECT_EQ(n, 3u);
  ASSERT_EQ(reader.warnings().size(), 1u);
  EXPECT_NE(reader.warnings()[0].find("cannot decode"), std::string::npos) << reader.warnings()[0];
}

TEST(BagIO, BadBags) {
  BagImageReader reader;
  std::string err;
  EXPECT_FALSE(reader.open("/nonexistent/x.bag", "/cam0/image_raw", &err));
  EXPECT_NE(err.find("/nonexistent/x.bag"), std::string::npos) << err;
  const std::string d = tmpDir("bad");
  std::ofstream(d + "/garbage.bag") << "#ROSBAG V2.0\nthis is not a bag at all";
  EXPECT_FALSE(reader.open(d + "/garbage.bag", "/cam0/image_raw", &err));
  EXPECT_NE(err.find("garbage.bag"), std::string::npos) << err;
  ros::Time t;
  cv::Mat m;
  EXPECT_FALSE(reader.next(&t, &m));  // not open: no crash
  std::vector<cv::Mat> expected;
  ASSERT_EQ(aslToBag(makeAsl(&expected), d + "/good.bag", AslToBagOptions(), &err), 4u) << err;
  // Wrong topic: the error lists the image topics present.
  EXPECT_FALSE(reader.open(d + "/good.bag", "/nope", &err));
  EXPECT_NE(err.find("/cam0/image_raw"), std::string::npos) << err;
}

namespace {
std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }
}  // namespace

// A bag cut short (copy interrupted) or never indexed (recording killed): the intact messages are read, open()
// says how many and suggests `rosbag reindex`.
TEST(BagIO, TruncatedAndUnindexedBags) {
  const std::string d = tmpDir("trunc");
  std::vector<cv::Mat> expected;
  const std::string root = makeAsl(&expected);
  std::string err;
  for (const std::string format : {"raw", "png"}) {
    AslToBagOptions opt;
    opt.image_format = format;
    const std::string topic = format == "raw" ? "/cam0/image_raw" : "/cam0/image_raw/compressed";
    const std::string good = d + "/good_" + format + ".bag";
    ASSERT_EQ(aslToBag(root, good, opt, &err), 4u) << err;
    const std::string bytes = readBytes(good);
    // Find where the 3rd message's record starts: cut inside it -> 2 intact messages.
    const size_t third = bytes.find("op=\x02", bytes.find("op=\x02", bytes.find("op=\x02") + 1) + 1);
    ASSERT_NE(third, std::string::npos);
    const std::string trunc = d + "/trunc_" + format + ".bag";
    writeBytes(trunc, bytes.substr(0, third + 40));
    // Unindexed: the complete chunk data but index_pos = 0 in the bag header (as a killed `rosbag record` leaves it).
    std::string unindexed_bytes = bytes;
    const size_t ip = unindexed_bytes.find("index_pos=");
    ASSERT_NE(ip, std::string::npos);
    unindexed_bytes.replace(ip + 10, 8, std::string(8, '\0'));
    const std::string unindexed = d + "/unindexed_" + format + ".bag";
    writeBytes(unindexed, unindexed_bytes);
    for (const auto& c : {std::make_pair(trunc, size_t(2)), std::make_pair(unindexed, size_t(4))}) {
      BagImageReader reader;
      ASSERT_TRUE(reader.open(c.first, topic, &err)) << c.first << ": " << err;
      EXPECT_EQ(reader.size(), c.second) << c.first;
      const std::string expect_notice = "bag " + c.first + " is truncated/unindexed after " + std::to_string(c.second) +
                                        " messages on " + topic;
      EXPECT_NE(reader.notice().find(expect_notice), std::string::npos) << reader.notice();
      EXPECT_NE(reader.notice().find("run `rosbag reindex " + c.first + "`"), std::string::npos) << reader.notice();
      ros::Time stamp;
      cv::Mat gray;
      size_t n = 0;
      while (reader.next(&stamp, &gray)) {
        ASSERT_LT(n, c.second);
        EXPECT_EQ(static_cast<int64_t>(stamp.toNSec()), kStamps[n]) << c.first;
        EXPECT_EQ(cv::norm(gray, expected[n], cv::NORM_INF), 0.0) << c.first << " image " << n;
        ++n;
      }
      EXPECT_EQ(n, c.second) << c.first;
      EXPECT_EQ(reader.skippedSummary(), "") << c.first;
      // The topic list of the intact part is known too.
      const std::vector<std::string> topics = BagImageReader::imageTopics(c.first, &err);
      ASSERT_EQ(topics.size(), 1u) << c.first;
      EXPECT_EQ(topics[0], topic);
    }
    // Wrong topic on a truncated bag: error names the bag, the topics of the intact part and rosbag reindex.
    BagImageReader reader;
    EXPECT_FALSE(reader.open(trunc, "/nope", &err));
    EXPECT_NE(err.find(trunc), std::string::npos) << err;
    EXPECT_NE(err.find(topic), std::string::npos) << err;
    EXPECT_NE(err.find("rosbag reindex"), std::string::npos) << err;
  }
  // Cut inside the bag header: nothing intact, a clear error.
  writeBytes(d + "/stub.bag", readBytes(d + "/good_raw.bag").substr(0, 100));
  BagImageReader reader;
  EXPECT_FALSE(reader.open(d + "/stub.bag", "/cam0/image_raw", &err));
  EXPECT_NE(err.find("stub.bag"), std::string::npos) << err;
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::Time::init();
  return RUN_ALL_TESTS();
}
