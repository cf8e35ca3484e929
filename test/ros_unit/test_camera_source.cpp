// CameraSource (src/ros/camera_source.cpp): the calibration rules of the nodelets without a master: the first valid
// camera_info configures, an identical one is ignored, a changed one is reported (restart), an invalid one is reported
// once and keeps a previous calibration; ~camera_file errors give the reason published in tracking_status.
#include <gtest/gtest.h>

#include "iraf_vo/ros/camera_source.h"

using namespace iraf_vo;

namespace {

sensor_msgs::CameraInfo info(const std::string& model, const std::vector<double>& D, double fx = 400) {
  sensor_msgs::CameraInfo i;
  i.width = 376;
  i.height = 240;
  i.distortion_model = model;
  i.D = D;
  i.K = {fx, 0, 188, 0, fx, 120, 0, 0, 1};
  i.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  i.P = {fx, 0, 188, 0, 0, fx, 120, 0, 0, 0, 1, 0};
  return i;
}

}  // namespace

TEST(CameraSource, CameraInfoRules) {
  CameraSource src;
  src.useCameraInfo("/cam0/camera_info", CameraInfoOptions());
  EXPECT_FALSE(src.camera());
  EXPECT_NE(src.reason().find("waiting for camera_info on /cam0/camera_info"), std::string::npos) << src.reason();
  std::string msg;
  sensor_msgs::CameraInfo bad = info("plumb_bob", {0.1, 0.2, 0.0});
  EXPECT_EQ(src.onCameraInfo(bad, &msg), CameraSource::Event::kInvalid);
  EXPECT_NE(src.reason().find("invalid camera_info"), std::string::npos) << src.reason();
  EXPECT_EQ(src.onCameraInfo(bad, &msg), CameraSource::Event::kNone) << "the same error is reported once";

  EXPECT_EQ(src.onCameraInfo(info("plumb_bob", {-0.1, 0.01, 0, 0, 0}), &msg), CameraSource::Event::kConfigured);
  ASSERT_TRUE(src.camera());
  EXPECT_EQ(src.camera()->modelName(), "pinhole-radtan");
  EXPECT_EQ(src.reason(), "");
  sensor_msgs::CameraInfo same = info("plumb_bob", {-0.1, 0.01, 0, 0, 0});
  same.header.stamp = ros::Time(5.0);
  EXPECT_EQ(src.onCameraInfo(same, &msg), CameraSource::Event::kNone) << "only the header differs";

  EXPECT_EQ(src.onCameraInfo(info("equidistant", {0.01, 0.0, 0.0, 0.0}, 200), &msg), CameraSource::Event::kChanged);
  EXPECT_EQ(src.camera()->modelName(), "kannala-brandt");
  EXPECT_NE(msg.find("calibration changed"), std::string::npos) << msg;

  EXPECT_EQ(src.onCameraInfo(bad, &msg), CameraSource::Event::kInvalid);
  EXPECT_NE(msg.find("keeping the previous calibration"), std::string::npos) << msg;
  EXPECT_EQ(src.camera()->modelName(), "kannala-brandt");
}

TEST(CameraSource, FileErrorsNameTheFile) {
  CameraSource src;
  EXPECT_FALSE(src.loadFile("/nonexistent/cam.yaml"));
  EXPECT_NE(src.reason().find("/nonexistent/cam.yaml"), std::string::npos) << src.reason();
  EXPECT_TRUE(src.usesFile());
  sensor_msgs::CameraInfo i = info("plumb_bob", {0, 0, 0, 0});
  std::string msg;
  EXPECT_EQ(src.onCameraInfo(i, &msg), CameraSource::Event::kNone) << "file mode ignores camera_info";
  EXPECT_TRUE(src.loadFile(std::string(IRAF_VO_SOURCE_DIR) + "/test/ros/sim_cam0_376x240.yaml"));
  EXPECT_EQ(src.camera()->width(), 376);
}
