// The pose tracker's relocalization path on a hand-built map: a projection search around a wrong prediction that
// finds a small self-consistent set of matches (a decoy) keeps the wrong pose under the normal tracking threshold;
// as a relocalization (min_search_inliers, after darkness) a decoy below that minimum is handed to the brute force
// + PnP, and one above it loses to the PnP pose, which ends with more inliers. And the map's most covisible keyframe,
// the keyframe rule's reference while the tracker recovers from darkness.
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/pose_tracker.h"
#include "unit/tracking_test_utils.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>

namespace iraf_vo {
namespace {

using Descriptor = std::array<uint8_t, 32>;
using View = test::PointView;

Frame toFrame(const CameraModel& cam, const View& v, long index) {
  Frame f;
  std::string err;
  EXPECT_TRUE(v.toFrame(cam, index, &f, &err)) << err;
  return f;
}

double centreDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

struct DecoyScene {
  test::TestPinhole cam{752, 480, 458.0, 376.0, 240.0};
  TrackerParams params;
  Map map;
  Eigen::Isometry3d T_pred, T_true;  // camera poses T_c_w
  Frame cur;

  // 300 points 3-6 m ahead, mapped from two keyframes 10 cm apart; the camera is now 0.8 m to the side of the
  // prediction (the last pose). The frame sees every point where it is, plus `n_decoys` decoy keypoints placed
  // where as many map points project from the prediction, with those points' descriptors (4 bits off).
  explicit DecoyScene(size_t n_decoys = 35) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-4.0, 4.0), uy(-2.5, 2.5), uz(3.0, 6.0);
    std::uniform_int_distribution<int> ub(0, 255);
    std::vector<Eigen::Vector3d> P;
    std::vector<Descriptor> D;
    std::vector<int> all;
    for (int i = 0; i < 300; ++i) {
      P.emplace_back(ux(rng), uy(rng), uz(rng));
      Descriptor d;
      for (auto& b : d) b = static_cast<uint8_t>(ub(rng));
      D.push_back(d);
      all.push_back(i);
    }
    const Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();
    T1.translation() = Eigen::Vector3d(-0.1, 0, 0);
    View v0, v1;
    v0.add(cam, T0, P, D, all, 0);
    v1.add(cam, T1, P, D, all, 0);
    const Frame f0 = toFrame(cam, v0, 0), f1 = toFrame(cam, v1, 1);
    auto kf0 = Keyframe::fromFrame(f0, T0), kf1 = Keyframe::fromFrame(f1, T1);
    std::vector<NewMapPoint> pts;
    for (int i = 0; i < 300; ++i)
      if (v0.keypoint_of_point[i] >= 0 && v1.keypoint_of_point[i] >= 0)
        pts.push_back({P[i], 0, v1.keypoint_of_point[i], 0, v0.keypoint_of_point[i]});
    int created = 0;
    EXPECT_TRUE(map.createInitialMap(kf0, kf1, pts, 100, &created));

    T_pred = T1;
    T_true = T1;
    T_true.translation() = Eigen::Vector3d(-0.9, 0, 0);
    View now;
    now.add(cam, T_true, P, D, all, 0);
    std::vector<int> decoys;
    for (int i = 0; i < 300 && decoys.size() < n_decoys; i += 3)
      if (v1.keypoint_of_point[i] >= 0) decoys.push_back(i);
    now.add(cam, T_pred, P, D, decoys, 4);
    cur = toFrame(cam, now, 2);
  }
};

// PoseTracker::trackLocalMap of the scene's frame from T_predicted.
PoseTrackingResult track(DecoyScene* s, const Eigen::Isometry3d& T_predicted, int min_search_inliers) {
  PoseTracker tracker(s->cam, s->params);
  return tracker.trackLocalMap(s->cur, T_predicted, &s->map, false, min_search_inliers);
}

TEST(PoseTrackerRelocalization, DecoyAroundTheLastPoseIsTrackedAtTheNormalThreshold) {
  DecoyScene s;
  const PoseTrackingResult r = track(&s, s.T_pred, 0);
  ASSERT_TRUE(r.tracked) << "the decoy alone passes min_tracking_inliers (" << s.params.min_tracking_inliers << ")";
  EXPECT_FALSE(r.used_pnp);
  EXPECT_LT(r.inliers, 50);
  EXPECT_LT(centreDistance(s.cur.T_c_w, s.T_pred), 0.05) << "the search around the prediction keeps the decoy's pose";
}

TEST(PoseTrackerRelocalization, StricterFirstRefinementHandsOnlyAWeakSearchPoseToPnP) {
  DecoyScene weak, strong;
  const PoseTrackingResult from_decoy = track(&weak, weak.T_pred, 50);
  ASSERT_TRUE(from_decoy.tracked);
  EXPECT_TRUE(from_decoy.used_pnp);
  EXPECT_GE(from_decoy.inliers, 150);
  EXPECT_LT(centreDistance(weak.cur.T_c_w, weak.T_true), 0.01) << "brute force + PnP finds the true pose";
  // Predicted at the true pose: the search finds every point and keeps its pose, no PnP.
  const PoseTrackingResult from_truth = track(&strong, strong.T_true, 50);
  ASSERT_TRUE(from_truth.tracked);
  EXPECT_FALSE(from_truth.used_pnp);
  EXPECT_LT(centreDistance(strong.cur.T_c_w, strong.T_true), 0.01);
}

TEST(PoseTrackerRelocalization, SearchPoseAboveTheMinimumLosesToAStrongerPnPPose) {
  DecoyScene s(70);
  const PoseTrackingResult normal = track(&s, s.T_pred, 0);
  ASSERT_TRUE(normal.tracked);
  EXPECT_FALSE(normal.used_pnp);
  EXPECT_GE(normal.inliers, 60) << "the decoy passes the relocalization minimum on its own";
  EXPECT_LT(centreDistance(s.cur.T_c_w, s.T_pred), 0.05);
  DecoyScene r(70);
  const PoseTrackingResult reloc = track(&r, r.T_pred, 50);
  ASSERT_TRUE(reloc.tracked);
  EXPECT_TRUE(reloc.used_pnp);
  EXPECT_GT(reloc.inliers, normal.inliers);
  EXPECT_LT(centreDistance(r.cur.T_c_w, r.T_true), 0.01) << "the PnP pose has more inliers and is kept";
}

// Ranking relocalization seeds (Tracker: the candidate whose tracking ends with the most map inliers first): what
// tracking from a seed would end with, computed without touching the frame or the map.
TEST(PoseTrackerRelocalization, InliersFromRanksTheTrueSeedAboveTheDecoyAndChangesNothing) {
  DecoyScene s(70);
  PoseTracker tracker(s.cam, s.params);
  const int from_decoy = tracker.inliersFrom(s.cur, s.T_pred, s.map, false, true);
  const int from_truth = tracker.inliersFrom(s.cur, s.T_true, s.map, false, true);
  EXPECT_GE(from_decoy, 60);
  EXPECT_GT(from_truth, from_decoy + 50);
  for (long id : s.cur.point_id) EXPECT_EQ(id, -1) << "the frame is untouched";
  // The same number as tracking itself (the map is taken const: its counts stay as they were); tracking afterwards
  // gives what it gives on an untouched scene.
  DecoyScene fresh(70);
  const PoseTrackingResult after = tracker.trackLocalMap(s.cur, s.T_true, &s.map, false, 0, true);
  const PoseTrackingResult untouched = PoseTracker(fresh.cam, fresh.params).trackLocalMap(fresh.cur, fresh.T_true,
                                                                                           &fresh.map, false, 0, true);
  ASSERT_TRUE(after.tracked);
  EXPECT_EQ(after.inliers, from_truth);
  EXPECT_EQ(after.inliers, untouched.inliers);
  EXPECT_LT(centreDistance(s.cur.T_c_w, fresh.cur.T_c_w), 1e-12);
}

// A metric map without a motion model tracks with brute force + PnP first (prediction_unknown): the ranking asks
// the same question, so the decoy seed ranks where tracking from it ends (at the true pose), not where a search
// around it would.
TEST(PoseTrackerRelocalization, InliersFromAsksWhatTrackingWithoutAMotionModelDoes) {
  DecoyScene s(70), m(70);
  PoseTracker tracker(s.cam, s.params);
  const int searched = tracker.inliersFrom(s.cur, s.T_pred, s.map, false, true);
  const int unknown = tracker.inliersFrom(s.cur, s.T_pred, s.map, true, true);
  const PoseTrackingResult tracked = PoseTracker(m.cam, m.params).trackLocalMap(m.cur, m.T_pred, &m.map, true, 0, true);
  ASSERT_TRUE(tracked.tracked);
  EXPECT_TRUE(tracked.used_pnp);
  EXPECT_EQ(unknown, tracked.inliers);
  EXPECT_GT(unknown, searched + 50);
  EXPECT_LT(centreDistance(m.cur.T_c_w, m.T_true), 0.01);
}

}  // namespace
}  // namespace iraf_vo

namespace iraf_vo {

// The keyframe rule's reference while recovering from darkness: the keyframe observing most of the frame's points
// (ORB-SLAM's reference keyframe), not the newest one when that one shares fewer.
TEST(MapCovisibility, MostCovisibleKeyframeObservesMostOfTheFramesPoints) {
  const int n = 40;
  Map map;
  Frame f0 = test::gridFrame(0, n, 0.0), f1 = test::gridFrame(1, n, 0.1);
  auto kf0 = Keyframe::fromFrame(f0, f0.T_c_w), kf1 = Keyframe::fromFrame(f1, f1.T_c_w);
  std::vector<NewMapPoint> pts;
  for (int i = 0; i < n; ++i) pts.push_back({Eigen::Vector3d(0.01 * i, 0, 2), 0, i, 0, i});
  int created = 0;
  ASSERT_TRUE(map.createInitialMap(kf0, kf1, pts, n, &created));
  const std::vector<long> all = kf1->point_id;
  Frame weak = test::gridFrame(2, n, 0.2);  // a newer keyframe that observes only the first 5 points
  for (int i = 0; i < 5; ++i) weak.point_id[i] = all[i];
  const long weak_id = map.addKeyframe(weak);
  EXPECT_EQ(map.mostCovisibleKeyframe(all, weak_id), kf1->id) << "40 shared points against 5: the newer of the two 40s";
  std::vector<long> first_five(all.begin(), all.begin() + 5);
  first_five.resize(n, -1);
  EXPECT_EQ(map.mostCovisibleKeyframe(first_five, kf0->id), weak_id) << "a tie of 5: the newest keyframe";
  EXPECT_EQ(map.mostCovisibleKeyframe(std::vector<long>(n, -1), kf0->id), kf0->id) << "no point: the fallback";
}

}  // namespace iraf_vo
