// Scale prediction in the projection searches (predictOctave, TrackerParams::predict_scale): a point created at
// one octave shows at another when the camera comes closer or moves away; ORB-SLAM predicts the octave from the
// distance and skips views more than 60 deg off. Checked on the formula and through Matcher::searchByProjection.
#include <iraf_vo/tracking/map.h>
#include <iraf_vo/tracking/matcher.h>

#include <gtest/gtest.h>

#include <cmath>

#include "unit/tracking_test_utils.h"

namespace iraf_vo {
namespace {

LocalPoint pointSeenFrom(const Eigen::Vector3d& p_w, const Eigen::Vector3d& ref_center, int octave) {
  LocalPoint lp{1, p_w, {}, octave, -1.f};
  lp.ref_center = ref_center;
  lp.ref_octave = octave;
  lp.has_ref = true;
  return lp;
}

TEST(ScalePrediction, OctaveFollowsTheDistance) {
  const double s = 1.2;
  const Eigen::Vector3d p(0, 0, 4);
  const LocalPoint lp = pointSeenFrom(p, Eigen::Vector3d::Zero(), 2);  // 4 m away at octave 2
  int o = -1;
  ASSERT_TRUE(predictOctave(lp, Eigen::Vector3d(0, 0, 4 - 4 / std::pow(s, 2)), 0.0, s, &o));  // 1.2^2 closer
  EXPECT_EQ(o, 4);
  ASSERT_TRUE(predictOctave(lp, Eigen::Vector3d(0, 0, 4 - 4 * std::pow(s, 2)), 0.0, s, &o));  // 1.2^2 farther
  EXPECT_EQ(o, 0);
  ASSERT_TRUE(predictOctave(lp, Eigen::Vector3d(0, 0, 4 - 4 * std::pow(s, 2.9)), 0.0, s, &o));  // level -0.9: kept at 0
  EXPECT_EQ(o, 0);
  EXPECT_FALSE(predictOctave(lp, Eigen::Vector3d(0, 0, 4 - 4 * std::pow(s, 3.2)), 0.0, s, &o));  // level -1.2: too far
  ASSERT_TRUE(predictOctave(lp, Eigen::Vector3d(0.1, 0.1, 0), 0.0, s, &o));  // same distance, small turn
  EXPECT_EQ(o, 2);
}

TEST(ScalePrediction, ViewsMoreThanSixtyDegreesOffAreSkipped) {
  const Eigen::Vector3d p(0, 0, 4);
  const LocalPoint lp = pointSeenFrom(p, Eigen::Vector3d::Zero(), 1);
  int o = -1;
  auto from = [&](double deg) {  // a camera 4 m from the point, the ray turned by deg about the y axis
    const double a = deg * M_PI / 180.0;
    return Eigen::Vector3d(p - 4.0 * Eigen::Vector3d(std::sin(a), 0, std::cos(a)));
  };
  EXPECT_TRUE(predictOctave(lp, from(55), 0.0, 1.2, &o));
  EXPECT_EQ(o, 1);
  EXPECT_FALSE(predictOctave(lp, from(65), 0.0, 1.2, &o));
  LocalPoint unknown = lp;
  unknown.has_ref = false;  // no creating keyframe: the point's own octave, from any side
  EXPECT_TRUE(predictOctave(unknown, from(65), 0.0, 1.2, &o));
  EXPECT_EQ(o, 1);
}

// Pixels per metre facing the camera: f / d on the axis for both models; 60 deg off the axis a pinhole
// stretches by cos^-1.5 (radial 1 / cos^2, tangential 1 / cos), the equidistant fisheye by sqrt(theta / sin).
TEST(ScalePrediction, ImageScaleFollowsTheLens) {
  test::TestPinhole pin(752, 480, 450.0, 376.0, 240.0);
  test::TestFisheye fish(512, 512, 190.0, 256.0, 256.0);
  auto scaleOf = [](const CameraModel& cam, const Eigen::Vector3d& p) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    EXPECT_TRUE(cam.project(p, &uv, &J));
    return imageScale(J);
  };
  EXPECT_NEAR(scaleOf(pin, Eigen::Vector3d(0, 0, 2)), 450.0 / 2, 1e-9);
  EXPECT_NEAR(scaleOf(fish, Eigen::Vector3d(0, 0, 2)), 190.0 / 2, 1e-6);
  const double a = M_PI / 3;
  const Eigen::Vector3d off(2 * std::sin(a), 0, 2 * std::cos(a));
  EXPECT_NEAR(scaleOf(pin, off), 450.0 / 2 * std::pow(std::cos(a), -1.5), 1e-6);
  EXPECT_NEAR(scaleOf(fish, off), 190.0 / 2 * std::sqrt(a / std::sin(a)), 1e-3);
  // The octave follows the image scale: the same 4 m, seen at the axis from the reference and at 60 deg now,
  // is 1.2^~5.7 larger in the pinhole image (octave 2 -> 8) and 1.2^~0.5 in the fisheye one (octave 2 -> 3).
  LocalPoint lp = pointSeenFrom(Eigen::Vector3d(0, 0, 4), Eigen::Vector3d::Zero(), 2);
  lp.ref_scale = 450.0 / 4;
  int o = -1;
  ASSERT_TRUE(predictOctave(lp, Eigen::Vector3d(0.1, 0, 0), 450.0 / 4 * std::pow(std::cos(a), -1.5), 1.2, &o));
  EXPECT_EQ(o, 2 + static_cast<int>(std::lround(std::log(std::pow(std::cos(a), -1.5)) / std::log(1.2))));
  EXPECT_GE(o, 7);
}

// Points created at octave 0 from 4.8 m; the frame sees them from 1.2^4 closer, where the keypoints sit at
// octave 4. With the prediction every point matches its keypoint; without it (octave 0 +- 1) none does.
TEST(ScalePrediction, ProjectionSearchFindsPointsAtThePredictedOctave) {
  test::TestPinhole cam(752, 480, 450.0, 376.0, 240.0);
  test::SyntheticWorld w;
  const int n = 60;
  w.addBox(n, Eigen::Vector3d(-0.3, -0.2, 4.8), Eigen::Vector3d(0.3, 0.2, 4.8));
  const double closer = 4.8 - 4.8 / std::pow(1.2, 4);
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
  T_c_w.translation() = Eigen::Vector3d(0, 0, -closer);
  FeatureFrame ff;
  ff.width = 752;
  ff.height = 480;
  ff.descriptors.create(n, 32, CV_8U);
  std::vector<LocalPoint> local;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(T_c_w * w.points[i], &uv));
    ff.keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f * 2.07f, 0.f, 1.f, 4);
    std::memcpy(ff.descriptors.ptr<uint8_t>(i), w.desc[i].data(), 32);
    LocalPoint lp = pointSeenFrom(w.points[i], Eigen::Vector3d::Zero(), 0);
    lp.id = i;
    std::memcpy(lp.desc.data(), w.desc[i].data(), 32);
    local.push_back(lp);
  }
  Frame f;
  std::string err;
  ASSERT_TRUE(Frame::fromFeatures(ff, cam, 0, &f, &err)) << err;

  for (bool predict : {true, false}) {
    TrackerParams p;
    p.predict_scale = predict;
    Matcher matcher(cam, p);
    MatchSet matches(f.size(), local.size());
    const int found = matcher.searchByProjection(f, T_c_w, local, p.search_radius_px, 1, &matches, nullptr);
    if (predict) {
      EXPECT_EQ(found, n);
      for (int i = 0; i < n; ++i) EXPECT_EQ(matches.pointOf(i), i);
    } else {
      EXPECT_EQ(found, 0);
    }
  }
}

}  // namespace
}  // namespace iraf_vo
