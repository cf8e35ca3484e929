// stereoExtrinsicsFromCameraInfo (src/ros/camera_info.cpp): the left -> right transform of a stereo pair from the R
// and P of its two camera_info messages. Oracle: OpenCV's stereoRectify on the EuRoC pair (config/euroc_cam0.yaml +
// euroc_cam1.yaml, T_r_l from their T_BS) writes R1 R2 P1 P2 as camera_calibration's stereo calibrator does; the
// transform read back from them is the yaml one.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/ros/camera_info.h"

using namespace iraf_vo;

namespace {

const std::string kConfig = std::string(IRAF_VO_SOURCE_DIR) + "/config/";

struct RectifiedPair {
  StereoRig rig;
  sensor_msgs::CameraInfo left, right;
};

sensor_msgs::CameraInfo toInfo(const cv::Mat& R, const cv::Mat& P) {
  sensor_msgs::CameraInfo info;
  info.width = 752;
  info.height = 480;
  for (int i = 0; i < 9; ++i) info.R[i] = R.at<double>(i / 3, i % 3);
  for (int i = 0; i < 12; ++i) info.P[i] = P.at<double>(i / 4, i % 4);
  return info;
}

RectifiedPair eurocPair() {
  RectifiedPair p;
  std::string err;
  EXPECT_TRUE(loadStereoRig(kConfig + "euroc_cam0.yaml", kConfig + "euroc_cam1.yaml", &p.rig, &err)) << err;
  const cv::Matx33d K1(458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1);
  const cv::Matx33d K2(457.587, 0, 379.999, 0, 456.134, 255.238, 0, 0, 1);
  const cv::Vec4d D1(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05);
  const cv::Vec4d D2(-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05);
  cv::Mat R, T, R1, R2, P1, P2, Q;
  const Eigen::Matrix3d Re = p.rig.T_r_l.linear();
  const Eigen::Vector3d te = p.rig.T_r_l.translation();
  cv::eigen2cv(Re, R);
  cv::eigen2cv(te, T);
  cv::stereoRectify(K1, D1, K2, D2, cv::Size(752, 480), R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0);
  p.left = toInfo(R1, P1);
  p.right = toInfo(R2, P2);
  return p;
}

TEST(StereoCameraInfo, RawPairGivesTheCalibratedTransform) {
  const RectifiedPair p = eurocPair();
  Eigen::Isometry3d T;
  std::string err;
  ASSERT_TRUE(stereoExtrinsicsFromCameraInfo(p.left, p.right, false, &T, &err)) << err;
  EXPECT_LT((T.linear() - p.rig.T_r_l.linear()).norm(), 1e-9);
  EXPECT_LT((T.translation() - p.rig.T_r_l.translation()).norm(), 1e-9) << T.translation().transpose();
  EXPECT_NEAR(T.translation().norm(), 0.1101, 1e-3);
}

TEST(StereoCameraInfo, RectifiedImagesArePureBaseline) {
  const RectifiedPair p = eurocPair();
  Eigen::Isometry3d T;
  std::string err;
  ASSERT_TRUE(stereoExtrinsicsFromCameraInfo(p.left, p.right, true, &T, &err)) << err;
  EXPECT_LT((T.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(T.translation().x(), -p.rig.baseline(), 1e-9) << "the right camera is +baseline along x";
  EXPECT_NEAR(T.translation().y(), 0.0, 1e-9);
}

TEST(StereoCameraInfo, NotAStereoCalibrationIsNamed) {
  RectifiedPair p = eurocPair();
  Eigen::Isometry3d T;
  std::string err;
  p.right.P[3] = 0.0;
  p.right.P[7] = 0.0;
  EXPECT_FALSE(stereoExtrinsicsFromCameraInfo(p.left, p.right, false, &T, &err));
  EXPECT_NE(err.find("no baseline"), std::string::npos) << err;
  p = eurocPair();
  p.left.R[0] = 2.0;
  EXPECT_FALSE(stereoExtrinsicsFromCameraInfo(p.left, p.right, false, &T, &err));
  EXPECT_NE(err.find("left R is not a rotation"), std::string::npos) << err;
  p = eurocPair();
  p.right.P[0] = 0.0;
  EXPECT_FALSE(stereoExtrinsicsFromCameraInfo(p.left, p.right, false, &T, &err));
  EXPECT_NE(err.find("right P has no focal length"), std::string::npos) << err;
}

}  // namespace
