// Unit tests of the tracker's matching: the match set's links, the descriptor distance and the epipolar search
// for triangulation.
#include <iraf_vo/tracking/map.h>
#include <iraf_vo/tracking/matcher.h>

#include <gtest/gtest.h>

#include "unit/tracking_test_utils.h"

namespace iraf_vo {
namespace {

TEST(MatchSetTest, LinkReplacesAndUnlinks) {
  MatchSet m(5, 4);
  m.link(0, 2);
  m.link(1, 3);
  EXPECT_EQ(m.size(), 2);
  m.link(0, 1);  // keypoint 0 moves from point 2 to point 1
  EXPECT_EQ(m.keypointOf(2), -1);
  EXPECT_EQ(m.keypointOf(1), 0);
  m.unlinkKeypoint(1);
  EXPECT_EQ(m.keypointOf(3), -1);
  EXPECT_EQ(m.size(), 1);
}

TEST(MatcherTest, HammingDistanceEqualsOpenCVNorm) {
  cv::RNG rng(3);
  cv::Mat d(64, 32, CV_8U);
  rng.fill(d, cv::RNG::UNIFORM, 0, 256);
  for (int i = 0; i < d.rows; ++i)
    for (int j = 0; j < d.rows; ++j)
      ASSERT_EQ(hammingDistance(d.ptr<uint8_t>(i), d.ptr<uint8_t>(j)),
                static_cast<int>(cv::norm(d.row(i), d.row(j), cv::NORM_HAMMING)));
}

// Keyframe 2 sees the points of keyframe 1 from 0.3 m to the side; every point also has a decoy in keyframe 2 with
// the same descriptor but far from its epipolar line. The epipolar search must pick the true keypoint.
TEST(MatcherTest, SearchForTriangulationPicksTheKeypointOnTheEpipolarLine) {
  test::TestPinhole cam(640, 480, 500, 320, 240);
  TrackerParams p;
  Matcher matcher(cam, p);
  const int n = 200;
  cv::RNG rng(5);
  Frame f1, f2;
  f1.descriptors.create(n, 32, CV_8U);
  f2.descriptors.create(2 * n, 32, CV_8U);
  rng.fill(f1.descriptors, cv::RNG::UNIFORM, 0, 256);
  const Eigen::Isometry3d T_21 = test::makePose({0, 2, 0}, {-0.3, 0.02, 0});
  std::vector<cv::KeyPoint> decoy_kps;
  std::vector<Eigen::Vector3d> decoy_bearings;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p1(rng.uniform(-1.5, 1.5), rng.uniform(-1.0, 1.0), rng.uniform(2.0, 6.0));
    const Eigen::Vector3d p2 = T_21 * p1;
    Eigen::Vector2d uv1, uv2;
    ASSERT_TRUE(cam.project(p1, &uv1));
    ASSERT_TRUE(cam.project(p2, &uv2));
    f1.keypoints.emplace_back(uv1.x(), uv1.y(), 31.f);
    f1.bearings.push_back(p1.normalized());
    f2.keypoints.emplace_back(uv2.x(), uv2.y(), 31.f);
    f2.bearings.push_back(p2.normalized());
    f1.descriptors.row(i).copyTo(f2.descriptors.row(i));
    f2.descriptors.at<uint8_t>(i, 0) ^= 0x3;  // 2 bits of noise on the true match
    // The decoy: the same descriptor exactly, 40 px off the epipolar line (moved along the line's normal).
    const Eigen::Vector3d b_off = (p2 + 40.0 / 500.0 * p2.z() * Eigen::Vector3d(0, 1, 0)).normalized();
    decoy_kps.emplace_back(uv2.x(), uv2.y() + 40.f, 31.f);
    decoy_bearings.push_back(b_off);
    f1.descriptors.row(i).copyTo(f2.descriptors.row(n + i));
  }
  f2.keypoints.insert(f2.keypoints.end(), decoy_kps.begin(), decoy_kps.end());
  f2.bearings.insert(f2.bearings.end(), decoy_bearings.begin(), decoy_bearings.end());
  f1.valid.assign(n, 1);
  f2.valid.assign(2 * n, 1);
  auto kf1 = Keyframe::fromFrame(f1, Eigen::Isometry3d::Identity());
  auto kf2 = Keyframe::fromFrame(f2, T_21);
  const std::vector<char> used1(n, 0);
  const std::vector<long> point_id2(2 * n, -1);
  const std::vector<int> match_of_2 = matcher.searchForTriangulation(*kf1, used1, *kf2, point_id2, T_21);
  int correct = 0, decoys = 0;
  for (int j = 0; j < 2 * n; ++j) {
    if (match_of_2[j] < 0) continue;
    if (j < n && match_of_2[j] == j) ++correct;
    if (j >= n) ++decoys;
  }
  EXPECT_EQ(decoys, 0);
  EXPECT_GE(correct, n * 95 / 100);
}

}  // namespace
}  // namespace iraf_vo
