// Unit tests of the tracker's matching: the match set's links, the descriptor distance and the epipolar search
// for triangulation (including repeated texture along the epipolar line).
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

// Forward motion past a far facade with a repeated pattern: keyframe 2 is 3 m ahead, the points are 200-400 m away
// near the horizon (their epipolar lines run along the image rows). In keyframe 2 the true keypoint is hidden and
// two copies of the pattern lie on the line (at the projections of 20 m and 10 m along keyframe 1's ray), each with
// 2-3 bits of descriptor noise. Matching either copy makes a point 15-30x too close; the distinctness test
// (triangulation_match_ratio) refuses both, while the same corner detected at two octaves 1 px apart still matches.
struct FacadeViews {
  Frame f1, f2;
  Eigen::Isometry3d T_21;
  int n = 0;
};

FacadeViews facadeViews(const CameraModel& cam, bool true_keypoint_visible) {
  FacadeViews v;
  v.T_21 = test::makePose({0, 0, 0}, {0, 0, -3.0});
  v.n = 100;
  cv::RNG rng(7);
  v.f1.descriptors.create(v.n, 32, CV_8U);
  rng.fill(v.f1.descriptors, cv::RNG::UNIFORM, 0, 256);
  std::vector<cv::Mat> rows2;
  auto noisy = [&](int i, int bits) {
    cv::Mat d = v.f1.descriptors.row(i).clone();
    for (int b = 0; b < bits; ++b) d.at<uint8_t>(0, b) ^= 0x1;
    return d;
  };
  auto add2 = [&](const Eigen::Vector3d& p2, float dx, int octave, const cv::Mat& d) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(p2, &uv));
    v.f2.keypoints.emplace_back(static_cast<float>(uv.x()) + dx, static_cast<float>(uv.y()), 31.f, 0.f, 0.f, octave);
    Eigen::Vector3d b;
    ASSERT_TRUE(cam.unproject(Eigen::Vector2d(uv.x() + dx, uv.y()), &b));
    v.f2.bearings.push_back(b);
    rows2.push_back(d);
  };
  for (int i = 0; i < v.n; ++i) {
    const double side = i % 2 ? 1.0 : -1.0;
    const Eigen::Vector3d ray(side * rng.uniform(0.3, 0.6), rng.uniform(-0.05, 0.05), 1.0);
    const Eigen::Vector3d p1 = rng.uniform(200.0, 400.0) * ray;
    Eigen::Vector2d uv1;
    EXPECT_TRUE(cam.project(p1, &uv1));
    v.f1.keypoints.emplace_back(uv1.x(), uv1.y(), 31.f);
    v.f1.bearings.push_back(p1.normalized());
    if (true_keypoint_visible) {
      add2(v.T_21 * p1, 0.f, 0, noisy(i, 2));
      add2(v.T_21 * p1, 1.f, 1, noisy(i, 3));  // the same corner at the next octave
    } else {
      add2(v.T_21 * (20.0 * ray), 0.f, 0, noisy(i, 2));
      add2(v.T_21 * (10.0 * ray), 0.f, 0, noisy(i, 3));
    }
  }
  cv::vconcat(rows2, v.f2.descriptors);
  v.f1.valid.assign(v.f1.keypoints.size(), 1);
  v.f2.valid.assign(v.f2.keypoints.size(), 1);
  return v;
}

// Matches of keyframe 1's keypoints: (keypoint of keyframe 2, keypoint of keyframe 1).
std::vector<std::pair<int, int>> triangulationMatches(const CameraModel& cam, const FacadeViews& v, double ratio) {
  TrackerParams p;
  p.triangulation_match_ratio = ratio;
  Matcher matcher(cam, p);
  auto kf1 = Keyframe::fromFrame(v.f1, Eigen::Isometry3d::Identity());
  auto kf2 = Keyframe::fromFrame(v.f2, v.T_21);
  const std::vector<int> m = matcher.searchForTriangulation(*kf1, std::vector<char>(v.f1.keypoints.size(), 0), *kf2,
                                                            std::vector<long>(v.f2.keypoints.size(), -1), v.T_21);
  std::vector<std::pair<int, int>> out;
  for (size_t j = 0; j < m.size(); ++j)
    if (m[j] >= 0) out.emplace_back(static_cast<int>(j), m[j]);
  return out;
}

TEST(MatcherTest, SearchForTriangulationRefusesRepeatedTextureOnTheLine) {
  test::TestPinhole cam(640, 480, 500, 320, 240);
  const FacadeViews hidden = facadeViews(cam, false);
  EXPECT_EQ(triangulationMatches(cam, hidden, TrackerParams().triangulation_match_ratio).size(), 0u);
  // Without the test (ratio 1) a copy is matched for every point.
  EXPECT_GE(triangulationMatches(cam, hidden, 1.0).size(), 95u);

  const FacadeViews visible = facadeViews(cam, true);
  int correct = 0;
  for (const auto& [j, i] : triangulationMatches(cam, visible, TrackerParams().triangulation_match_ratio))
    correct += j / 2 == i;
  EXPECT_GE(correct, 95);
}

}  // namespace
}  // namespace iraf_vo
