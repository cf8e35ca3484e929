// StereoMatcher: left-right matches of unrectified pairs through the epipolar constraint on bearings, triangulated
// and checked (synthetic pairs of both camera models with known points; EuRoC MH_01 frame 0).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/pipeline/front_end.h"
#include "iraf_vo/tracking/stereo_matcher.h"
#include "unit/tracking_test_utils.h"

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

/// A rig with a 0.12 m baseline and a 2 deg toe-in (not rectified).
StereoRig syntheticRig(CameraModelPtr cam) {
  StereoRig rig;
  rig.left = cam;
  rig.right = cam;
  rig.T_r_l = makePose(Eigen::Vector3d(0.5, -2.0, 0.3), Eigen::Vector3d(-0.12, 0.004, 0.002));
  return rig;
}

/// Renders the same world into both cameras, matches, and checks the matched points against the truth.
void checkSyntheticPair(CameraModelPtr cam) {
  const StereoRig rig = syntheticRig(cam);
  SyntheticWorld world;
  world.addBox(600, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  const Eigen::Isometry3d T_w_l = Eigen::Isometry3d::Identity();
  FeatureFrame fl = world.render(*cam, T_w_l, 0.0, 0.3, 4);
  FeatureFrame fr = world.render(*cam, T_w_l * rig.T_r_l.inverse(), 0.0, 0.3, 4);
  TrackerParams p;
  Frame left, right;
  std::string err;
  ASSERT_TRUE(Frame::fromFeatures(fl, *cam, 0, &left, &err)) << err;
  ASSERT_TRUE(Frame::fromFeatures(fr, *cam, 0, &right, &err)) << err;
  const StereoMatcher matcher(rig, p);
  const std::vector<StereoMatch> matches = matcher.match(left, right);
  // Which world point each keypoint shows: the nearest projection.
  auto pointOf = [&](const FeatureFrame& f, const Eigen::Isometry3d& T_w_c, int k) {
    int best = -1;
    double bd = 1e9;
    for (size_t i = 0; i < world.points.size(); ++i) {
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = T_w_c.inverse() * world.points[i];
      if (pc.z() < 0.1 || !cam->project(pc, &uv)) continue;
      const double d = (uv - Eigen::Vector2d(f.keypoints[k].pt.x, f.keypoints[k].pt.y)).norm();
      if (d < bd) bd = d, best = static_cast<int>(i);
    }
    return best;
  };
  int correct = 0;
  std::vector<double> rel_err;
  for (const StereoMatch& m : matches) {
    const int a = pointOf(fl, T_w_l, m.left), b = pointOf(fr, T_w_l * rig.T_r_l.inverse(), m.right);
    if (a != b) continue;
    ++correct;
    rel_err.push_back((m.p_l - world.points[a]).norm() / world.points[a].norm());
  }
  const size_t both = std::min(fl.keypoints.size(), fr.keypoints.size());
  EXPECT_GT(matches.size(), 0.7 * both) << cam->modelName() << ": " << matches.size() << " of " << both;
  EXPECT_GE(correct, static_cast<int>(0.98 * matches.size())) << cam->modelName();
  // 0.3 px noise per image, a 0.12 m baseline, points at 1-4.5 m: the depth error is ~0.42 px / disparity, ~2 %
  // (f 450) or ~5 % (fisheye f 200) at the median depth, ~10-40 % at the far end (4.5 m at the fisheye's periphery:
  // ~2 px of disparity).
  ASSERT_FALSE(rel_err.empty());
  std::sort(rel_err.begin(), rel_err.end());
  EXPECT_LT(rel_err[rel_err.size() / 2], 0.06) << cam->modelName();
  EXPECT_LT(rel_err[rel_err.size() * 95 / 100], 0.25) << cam->modelName();
  for (const StereoMatch& m : matches) EXPECT_LE(m.depth(), matcher.maxDepth());
}

}  // namespace

TEST(StereoMatcher, SyntheticPinholePair) {
  checkSyntheticPair(std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0));
}

TEST(StereoMatcher, SyntheticFisheyePair) {
  checkSyntheticPair(std::make_shared<TestFisheye>(640, 640, 200.0, 320.0, 320.0));
}

TEST(StereoMatcher, NoMatchesWhenTheRightImageShowsOtherPoints) {
  auto cam = std::make_shared<TestPinhole>(640, 480, 450.0, 320.0, 240.0);
  const StereoRig rig = syntheticRig(cam);
  SyntheticWorld a, b;
  b.rng.seed(99);
  a.addBox(400, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  b.addBox(400, Eigen::Vector3d(-3, -2, 1.0), Eigen::Vector3d(3, 2, 4.5));
  Frame left, right;
  std::string err;
  ASSERT_TRUE(Frame::fromFeatures(a.render(*cam, Eigen::Isometry3d::Identity(), 0.0), *cam, 0, &left, &err));
  ASSERT_TRUE(Frame::fromFeatures(b.render(*cam, rig.T_r_l.inverse(), 0.0), *cam, 0, &right, &err));
  TrackerParams p;
  EXPECT_LT(StereoMatcher(rig, p).match(left, right).size(), 5u);  // random descriptors: chance matches only
}

TEST(StereoMatcher, EurocFrameZero) {
  const std::string dir = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/";
  if (!std::ifstream(dir + "cam1/sensor.yaml")) GTEST_SKIP() << "no EuRoC cam1 at " << dir;
  StereoRig rig;
  std::string err;
  ASSERT_TRUE(loadStereoRig(dir + "cam0/sensor.yaml", dir + "cam1/sensor.yaml", &rig, &err)) << err;
  const std::string name = "1403636584763555584.png";
  cv::Mat il, ir;
  ASSERT_TRUE(readMono8(dir + "cam0/data/" + name, &il, &err) && readMono8(dir + "cam1/data/" + name, &ir, &err)) << err;
  EnhanceParams ep;
  FeatureParams fp;
  applyFrontEndMode(FrontEndMode::kIraf, &ep, &fp);
  FrontEnd fe_l(ep, fp), fe_r(ep, fp);
  const FeatureFrame fl = fe_l.process(il, 0.0), fr = fe_r.process(ir, 0.0);
  TrackerParams p;
  Frame left, right;
  ASSERT_TRUE(Frame::fromFeatures(fl, *rig.left, 0, &left, &err)) << err;
  ASSERT_TRUE(Frame::fromFeatures(fr, *rig.right, 0, &right, &err)) << err;
  const std::vector<StereoMatch> matches = StereoMatcher(rig, p).match(left, right);
  std::vector<double> depth;
  for (const StereoMatch& m : matches) depth.push_back(m.depth());
  std::sort(depth.begin(), depth.end());
  ASSERT_GE(matches.size(), 250u) << "of " << left.size() << " / " << right.size() << " keypoints";
  const double median = depth[depth.size() / 2];
  std::printf("EuRoC frame 0: %zu stereo matches of %zu / %zu keypoints; depth p10 %.2f median %.2f p90 %.2f m\n",
              matches.size(), left.size(), right.size(), depth[depth.size() / 10], median,
              depth[depth.size() * 9 / 10]);
  // The machine hall at frame 0: ~1-10 m away (up to stereo_max_depth_baselines x 0.11 m here).
  EXPECT_GT(median, 1.5);
  EXPECT_LT(depth.back(), 0.11 * p.stereo_max_depth_baselines + 0.01);
}
