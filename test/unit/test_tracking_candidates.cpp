// Candidate map points (tracker.candidate_parallax_ratio): a new point whose parallax is below the gate is kept as a
// candidate, matched and bundle-adjusted but left out of the pose and of the keyframe rule's counts, until the rays
// of its observing keyframes span the gate (Map::promoteCandidates). Hand-built maps, cameras looking down +z.
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/pose_tracker.h"
#include "unit/tracking_test_utils.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace iraf_vo {
namespace {

// A frame with n keypoints, camera centre at (x, 0, 0) looking down +z.
Frame frameAt(long index, int n, double x) {
  Frame f;
  f.index = index;
  for (int i = 0; i < n; ++i) f.keypoints.emplace_back(10.f + 20.f * i, 10.f, 31.f);
  f.descriptors = cv::Mat::zeros(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) f.descriptors.at<uint8_t>(i, 0) = static_cast<uint8_t>(i);
  f.bearings.assign(n, Eigen::Vector3d::UnitZ());
  f.valid.assign(n, 1);
  f.point_id.assign(n, -1);
  f.T_c_w.translation() = Eigen::Vector3d(-x, 0, 0);
  return f;
}

double cosDeg(double deg) { return std::cos(deg * M_PI / 180.0); }

// Keyframes at x = 0 and 0.1 m: keypoints 0-3 are ordinary points at 2 m (parallax 2.9 deg), keypoints 4-7
// candidates at 20 m (0.29 deg).
struct CandidateMap {
  Map map;
  KeyframePtr kf0, kf1;
  std::vector<long> ordinary, candidates;
  CandidateMap() {
    Frame f0 = frameAt(0, 8, 0.0), f1 = frameAt(1, 8, 0.1);
    kf0 = Keyframe::fromFrame(f0, f0.T_c_w);
    kf1 = Keyframe::fromFrame(f1, f1.T_c_w);
    std::vector<NewMapPoint> init;
    for (int i = 0; i < 4; ++i) init.push_back({Eigen::Vector3d(0.05, 0, 2.0), 0, i, 0, i});
    int created = 0;
    EXPECT_TRUE(map.createInitialMap(kf0, kf1, init, 4, &created));
    std::vector<NewMapPoint> far;
    for (int i = 4; i < 8; ++i) far.push_back({Eigen::Vector3d(0.05, 0, 20.0), kf1->id, i, kf0->id, i, true});
    map.addTriangulatedPoints(far);
    ordinary.assign(kf1->point_id.begin(), kf1->point_id.begin() + 4);
    candidates.assign(kf1->point_id.begin() + 4, kf1->point_id.end());
  }
  int candidateCount() const {
    int n = 0;
    for (const LocalPoint& lp : map.localPoints()) n += lp.candidate ? 1 : 0;
    return n;
  }
};

TEST(CandidatePoints, KeptMarkedAndLeftOutOfTheKeyframeCounts) {
  CandidateMap m;
  for (long id : m.candidates) ASSERT_GE(id, 0) << "every far keypoint got a point";
  EXPECT_EQ(m.map.numPoints(), 8u);
  EXPECT_EQ(m.candidateCount(), 4);
  int nearer = -1;
  EXPECT_EQ(m.map.trackedPoints(m.kf1->id, 2, 100.0, &nearer), 4) << "the reference's tracked points: not candidates";
  EXPECT_EQ(nearer, 4);
  EXPECT_EQ(m.map.pointsNearerThan(m.kf1->point_id, m.kf1->T_c_w, 100.0), 4);
}

TEST(CandidatePoints, PromotedOnceTheirRaysSpanTheGate) {
  CandidateMap m;
  std::vector<long> all = m.ordinary;
  all.insert(all.end(), m.candidates.begin(), m.candidates.end());
  EXPECT_EQ(m.map.promoteCandidates(all, cosDeg(1.0)), 0) << "0.29 deg between the two keyframes";
  EXPECT_EQ(m.map.promoteCandidates(all, cosDeg(0.2)), 4) << "a gate below their parallax";
  EXPECT_EQ(m.candidateCount(), 0);

  CandidateMap wide;
  Frame f2 = frameAt(2, 8, 1.0);  // 1 m from the first keyframe: 2.9 deg to the far points
  f2.point_id = wide.kf1->point_id;
  f2.point_id[4] = -1;  // this candidate is not seen from there
  wide.map.addKeyframe(f2);
  EXPECT_EQ(wide.map.promoteCandidates({wide.candidates[0]}, cosDeg(1.0)), 0) << "only its two near keyframes see it";
  EXPECT_EQ(wide.map.promoteCandidates({wide.candidates[1]}, cosDeg(1.0)), 1);
  EXPECT_EQ(wide.map.promoteCandidates(wide.candidates, cosDeg(1.0)), 2) << "the two others; one stays a candidate";
  EXPECT_EQ(wide.candidateCount(), 1);
}

// 300 points 3-6 m ahead, mapped from keyframes at x = 0 and 0.1 m: 200 ordinary ones where they are, then 50
// candidates where they are and 50 candidates placed 30 % nearer the first keyframe than they are (too near, as
// a far point that just passed the gate). The frame is 0.3 m forward of the second keyframe.
TEST(CandidatePoints, LeftOutOfThePoseAndKeptWhereTheyReproject) {
  test::TestPinhole cam(752, 480, 458.0, 376.0, 240.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-3.0, 3.0), uy(-2.0, 2.0), uz(3.0, 6.0);
  std::uniform_int_distribution<int> ub(0, 255);
  std::vector<Eigen::Vector3d> P;
  std::vector<std::array<uint8_t, 32>> D(300);
  std::vector<int> all;
  for (int i = 0; i < 300; ++i) {
    P.emplace_back(ux(rng), uy(rng), uz(rng));
    for (auto& b : D[i]) b = static_cast<uint8_t>(ub(rng));
    all.push_back(i);
  }
  Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity(), T1 = T0, T2 = T0;
  T1.translation() = Eigen::Vector3d(-0.1, 0, 0);
  T2.translation() = Eigen::Vector3d(-0.1, 0, -0.3);
  test::PointView v0, v1, v2;
  v0.add(cam, T0, P, D, all, 0);
  v1.add(cam, T1, P, D, all, 0);
  v2.add(cam, T2, P, D, all, 0);
  Frame f0, f1, cur;
  std::string err;
  ASSERT_TRUE(v0.toFrame(cam, 0, &f0, &err)) << err;
  ASSERT_TRUE(v1.toFrame(cam, 1, &f1, &err)) << err;
  ASSERT_TRUE(v2.toFrame(cam, 2, &cur, &err)) << err;
  auto kf0 = Keyframe::fromFrame(f0, T0), kf1 = Keyframe::fromFrame(f1, T1);
  std::vector<NewMapPoint> ordinary, candidates;
  std::vector<int> kind(300, -1);  // 0 ordinary, 1 candidate where it is, 2 candidate too near
  for (int i = 0; i < 300; ++i) {
    const int a = v1.keypoint_of_point[i], b = v0.keypoint_of_point[i];
    if (a < 0 || b < 0) continue;
    if (ordinary.size() < 200) {
      ordinary.push_back({P[i], 0, a, 0, b});
      kind[i] = 0;
    } else {
      kind[i] = candidates.size() < 50 ? 1 : 2;
      candidates.push_back({kind[i] == 1 ? P[i] : 0.7 * P[i], 0, a, 0, b, true});
    }
  }
  ASSERT_EQ(ordinary.size(), 200u);
  ASSERT_GE(candidates.size(), 80u);
  Map map;
  int created = 0;
  ASSERT_TRUE(map.createInitialMap(kf0, kf1, ordinary, 100, &created));
  for (auto& c : candidates) c.kf_a = kf1->id, c.kf_b = kf0->id;
  map.addTriangulatedPoints(candidates);

  TrackerParams params;
  const PoseTrackingResult r = PoseTracker(cam, params).trackLocalMap(cur, T1, &map, false, 0);
  ASSERT_TRUE(r.tracked);
  EXPECT_LT((cur.T_c_w.inverse().translation() - T2.inverse().translation()).norm(), 0.005);
  EXPECT_LE(r.inliers, 200) << "only ordinary points carry the pose";
  EXPECT_GE(r.inliers, 190);
  EXPECT_LE(r.refine_matches, 200) << "the health monitor's inlier ratio counts ordinary points";
  int kept[3] = {0, 0, 0};
  for (int i = 0; i < 300; ++i) {
    const int k = v2.keypoint_of_point[i];
    if (kind[i] >= 0 && k >= 0 && cur.point_id[static_cast<size_t>(k)] >= 0) ++kept[kind[i]];
  }
  EXPECT_GE(kept[1], 45) << "candidates where they are stay matched (the next keyframe observes them)";
  EXPECT_LE(kept[2], 5) << "candidates that do not reproject are dropped";
}

}  // namespace
}  // namespace iraf_vo
