// cameraFromCameraInfo / calibrationDiffers (src/ros/camera_info.cpp): sensor_msgs/CameraInfo -> core camera model.
// Round trip: the model from a CameraInfo holding the numbers of config/euroc_cam0.yaml (plumb_bob) and
// config/tumvi_cam0.yaml (equidistant) projects and unprojects exactly like the model loaded from the yaml.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/camera/kannala_brandt.h"
#include "iraf_vo/camera/pinhole_radtan.h"
#include "iraf_vo/ros/camera_info.h"

using namespace iraf_vo;

namespace {

sensor_msgs::CameraInfo makeInfo(const std::string& model, int w, int h, double fx, double fy, double cx, double cy,
                                 const std::vector<double>& D) {
  sensor_msgs::CameraInfo info;
  info.width = w;
  info.height = h;
  info.distortion_model = model;
  info.D = D;
  info.K = {fx, 0, cx, 0, fy, cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0};
  return info;
}

sensor_msgs::CameraInfo eurocInfo() {
  return makeInfo("plumb_bob", 752, 480, 458.654, 457.296, 367.215, 248.375,
                  {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0});
}

sensor_msgs::CameraInfo tumviInfo() {
  return makeInfo("equidistant", 512, 512, 190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504,
                  {0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182});
}

/// Both models project a grid of 3D points to the same pixels and unproject a pixel grid to the same bearings.
void expectSameProjection(const CameraModel& a, const CameraModel& b) {
  ASSERT_EQ(a.modelName(), b.modelName());
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  int n = 0;
  for (double x = -1.0; x <= 1.0; x += 0.25)
    for (double y = -0.8; y <= 0.8; y += 0.2) {
      const Eigen::Vector3d p(x, y, 1.5);
      Eigen::Vector2d ua, ub;
      const bool oka = a.project(p, &ua), okb = b.project(p, &ub);
      ASSERT_EQ(oka, okb) << p.transpose();
      if (oka) {
        EXPECT_LT((ua - ub).norm(), 1e-9) << p.transpose();
        ++n;
      }
    }
  EXPECT_GT(n, 20);
  for (int v = 0; v < a.height(); v += 40)
    for (int u = 0; u < a.width(); u += 40) {
      Eigen::Vector3d ba, bb;
      const Eigen::Vector2d uv(u, v);
      ASSERT_EQ(a.unproject(uv, &ba), b.unproject(uv, &bb)) << uv.transpose();
      EXPECT_LT((ba - bb).norm(), 1e-9) << uv.transpose();
    }
}

CameraModelPtr fromInfo(const sensor_msgs::CameraInfo& info, std::string* err, bool rectified = false) {
  CameraInfoOptions o;
  o.use_rectified = rectified;
  return cameraFromCameraInfo(info, err, o);
}

}  // namespace

/// The model from `info` is `model` and projects / unprojects like the one loaded from config/<yaml>.
void expectMatchesYaml(const sensor_msgs::CameraInfo& info, const std::string& yaml, const std::string& model) {
  std::string err;
  CameraModelPtr from_yaml = loadCamera(std::string(IRAF_VO_SOURCE_DIR) + "/config/" + yaml, &err);
  ASSERT_TRUE(from_yaml) << err;
  CameraModelPtr cam = fromInfo(info, &err);
  ASSERT_TRUE(cam) << yaml << ": " << err;
  EXPECT_EQ(cam->modelName(), model);
  expectSameProjection(*cam, *from_yaml);
}

TEST(CameraInfo, PlumbBobMatchesEurocYaml) {
  expectMatchesYaml(eurocInfo(), "euroc_cam0.yaml", "pinhole-radtan");
  // 4 coefficients (no k3) are accepted too.
  sensor_msgs::CameraInfo four = eurocInfo();
  four.D.resize(4);
  expectMatchesYaml(four, "euroc_cam0.yaml", "pinhole-radtan");
  // rational_polynomial with k4..k6 = 0 is the same model.
  sensor_msgs::CameraInfo rational = eurocInfo();
  rational.distortion_model = "rational_polynomial";
  rational.D.resize(8, 0.0);
  expectMatchesYaml(rational, "euroc_cam0.yaml", "pinhole-radtan");
}

TEST(CameraInfo, EquidistantMatchesTumviYaml) { expectMatchesYaml(tumviInfo(), "tumvi_cam0.yaml", "kannala-brandt"); }

TEST(CameraInfo, RectifiedUsesP) {
  // image_proc-style camera_info: K / D of the raw camera, P of the rectified image.
  sensor_msgs::CameraInfo info = eurocInfo();
  info.P = {400.0, 0, 370.0, 0, 0, 401.0, 250.0, 0, 0, 0, 1, 0};
  std::string err;
  auto check = [&](const sensor_msgs::CameraInfo& i, bool flag) {
    CameraModelPtr cam = fromInfo(i, &err, flag);
    ASSERT_TRUE(cam) << err;
    auto pin = std::dynamic_pointer_cast<const PinholeRadtan>(cam);
    ASSERT_TRUE(pin);
    EXPECT_EQ(pin->fx(), 400.0);
    EXPECT_EQ(pin->fy(), 401.0);
    EXPECT_EQ(pin->cx(), 370.0);
    EXPECT_EQ(pin->cy(), 250.0);
    EXPECT_EQ(pin->k1(), 0.0);
    EXPECT_EQ(pin->k2(), 0.0);
    EXPECT_EQ(pin->p1(), 0.0);
    EXPECT_EQ(pin->p2(), 0.0);
  };
  check(info, true);                 // user flag
  sensor_msgs::CameraInfo no_d = info;
  no_d.D.clear();                    // empty D: rectified
  check(no_d, false);
  sensor_msgs::CameraInfo zero_d = info;
  zero_d.D.assign(5, 0.0);           // all-zero D: rectified
  check(zero_d, false);
  // Without the flag the raw model (K + D) is used.
  CameraModelPtr raw = fromInfo(info, &err);
  ASSERT_TRUE(raw) << err;
  EXPECT_EQ(std::dynamic_pointer_cast<const PinholeRadtan>(raw)->fx(), 458.654);
  // Rectified fisheye stream (equidistant camera_info, use_rectified): pinhole from P.
  CameraModelPtr fish = fromInfo(tumviInfo(), &err, true);
  ASSERT_TRUE(fish) << err;
  EXPECT_EQ(fish->modelName(), "pinhole-radtan");
  // A driver that fills K only (P zero, D zero) still works; use_rectified with P zero is an error.
  sensor_msgs::CameraInfo k_only = eurocInfo();
  k_only.D.assign(5, 0.0);
  k_only.P.fill(0.0);
  ASSERT_TRUE(fromInfo(k_only, &err)) << err;
  EXPECT_FALSE(fromInfo(k_only, &err, true));
  EXPECT_NE(err.find("P is all zeros"), std::string::npos) << err;
}

TEST(CameraInfo, InvalidMessagesNameTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* name;
    std::function<void(sensor_msgs::CameraInfo*)> edit;
    const char* expect;
  };
  const std::vector<Case> cases = {
      {"zero size", [](sensor_msgs::CameraInfo* i) { i->width = 0; }, "width x height = 0x480"},
      {"uncalibrated", [](sensor_msgs::CameraInfo* i) { i->K.fill(0.0); }, "K is all zeros"},
      {"nan K", [&](sensor_msgs::CameraInfo* i) { i->K[2] = nan; }, "K[2] = nan is not finite"},
      {"nan D", [&](sensor_msgs::CameraInfo* i) { i->D[1] = nan; }, "D[1] = nan"},
      {"negative fx", [](sensor_msgs::CameraInfo* i) { i->K[0] = -458.0; }, "K: fx = -458 must be > 0"},
      {"skew", [](sensor_msgs::CameraInfo* i) { i->K[1] = 0.5; }, "K must be [fx 0 cx; 0 fy cy; 0 0 1]"},
      {"short D", [](sensor_msgs::CameraInfo* i) { i->D.resize(3); }, "D has 3 values; plumb_bob needs 4 or 5"},
      {"unknown model", [](sensor_msgs::CameraInfo* i) { i->distortion_model = "fov"; }, "distortion_model 'fov'"},
      {"rational k4", [](sensor_msgs::CameraInfo* i) {
         i->distortion_model = "rational_polynomial";
         i->D = {0.1, 0.01, 0, 0, 0, 0.2, 0, 0};
       }, "rational_polynomial with k4..k6"},
      {"equidistant D", [](sensor_msgs::CameraInfo* i) { i->distortion_model = "equidistant"; }, "equidistant needs 4"},
      {"binning", [](sensor_msgs::CameraInfo* i) { i->binning_x = 2; }, "binning"},
      {"roi", [](sensor_msgs::CameraInfo* i) { i->roi.width = 100; i->roi.height = 100; }, "roi 100x100"},
      {"huge k1", [](sensor_msgs::CameraInfo* i) { i->D[0] = 1e9; }, "D: k1 = "},
  };
  for (const Case& c : cases) {
    sensor_msgs::CameraInfo info = eurocInfo();
    c.edit(&info);
    std::string err;
    EXPECT_FALSE(fromInfo(info, &err)) << c.name;
    EXPECT_EQ(err.rfind("camera_info: ", 0), 0u) << c.name << ": " << err;
    EXPECT_NE(err.find(c.expect), std::string::npos) << c.name << ": " << err;
  }
}

TEST(CameraInfo, CalibrationDiffers) {
  const sensor_msgs::CameraInfo a = eurocInfo();
  sensor_msgs::CameraInfo b = a;
  b.header.stamp = ros::Time(12.5);
  b.header.frame_id = "other";
  b.header.seq = 7;
  std::string what;
  EXPECT_FALSE(calibrationDiffers(a, b, &what)) << "header changes are not calibration changes";
  const std::vector<std::pair<std::string, std::function<void(sensor_msgs::CameraInfo*)>>> changes = {
      {"D", [](sensor_msgs::CameraInfo* i) { i->D[0] += 1e-6; }},
      {"K", [](sensor_msgs::CameraInfo* i) { i->K[2] = 300.0; }},
      {"width x height", [](sensor_msgs::CameraInfo* i) { i->width = 640; }},
      {"P", [](sensor_msgs::CameraInfo* i) { i->P[0] = 1.0; }},
      {"distortion_model", [](sensor_msgs::CameraInfo* i) { i->distortion_model = "equidistant"; }},
      {"binning", [](sensor_msgs::CameraInfo* i) { i->binning_y = 2; }},
  };
  for (const auto& c : changes) {
    sensor_msgs::CameraInfo changed = a;
    c.second(&changed);
    EXPECT_TRUE(calibrationDiffers(a, changed, &what)) << c.first;
    EXPECT_EQ(what, c.first);
  }
}
