// Map-point fusion (fusionTargets / Matcher::searchForFusion / applyFusion, as LocalMapper runs them): a
// hand-built map where the newest keyframe missed points the older keyframes observe, some of them triangulated
// again as duplicates. Fusion must link the missed keypoints, merge the duplicates into the older points, and
// leave keypoints whose descriptor or position does not fit alone.
#include "iraf_vo/tracking/local_mapper.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/map_fusion.h"
#include "iraf_vo/tracking/matcher.h"
#include "unit/tracking_test_utils.h"

#include <gtest/gtest.h>

namespace iraf_vo {
namespace {

constexpr int kN = 120;  // world points

struct FusionScene {
  test::TestPinhole cam{752, 480, 450.0, 376.0, 240.0};
  std::vector<Eigen::Vector3d> world;
  std::vector<std::array<uint8_t, 32>> desc;
  Map map;

  FusionScene() {
    test::SyntheticWorld w;  // random points 3.5-5 m ahead, random descriptors
    w.addBox(kN, Eigen::Vector3d(-1.5, -1.0, 3.5), Eigen::Vector3d(1.5, 1.0, 5.0));
    world = w.points;
    desc = w.desc;
  }
  static Eigen::Isometry3d pose(double x) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(-x, 0, 0);
    return T;
  }
  // Keypoint i = the exact projection of world point i (all points are in view), its descriptor.
  Frame frame(long index, double x) const {
    Frame f;
    f.index = index;
    f.T_c_w = pose(x);
    for (int i = 0; i < kN; ++i) {
      Eigen::Vector2d uv;
      EXPECT_TRUE(cam.project(f.T_c_w * world[i], &uv));
      f.keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f);
      f.bearings.push_back((f.T_c_w * world[i]).normalized());
    }
    f.descriptors.create(kN, 32, CV_8U);
    for (int i = 0; i < kN; ++i) std::memcpy(f.descriptors.ptr<uint8_t>(i), desc[i].data(), 32);
    f.valid.assign(kN, 1);
    f.point_id.assign(kN, -1);
    return f;
  }
  // The first two keyframes (x = 0 and 0.15) observing every point; returns the second one.
  KeyframePtr initialMap() {
    Frame f0 = frame(0, 0.0), f1 = frame(1, 0.15);
    auto kf0 = Keyframe::fromFrame(f0, f0.T_c_w), kf1 = Keyframe::fromFrame(f1, f1.T_c_w);
    std::vector<NewMapPoint> pts;
    for (int i = 0; i < kN; ++i) pts.push_back({world[i], 1, i, 0, i});
    int created = 0;
    EXPECT_TRUE(map.createInitialMap(kf0, kf1, pts, kN, &created));
    return kf1;
  }
};

// Keypoints: [0, 60) tracked in every keyframe; [60, 90) missed by kf2 and kf3 and triangulated again between
// them (duplicates); [90, 120) missed by kf2 and kf3, of which [100, 105) have a foreign descriptor in kf3 and
// [105, 110) sit 8 px away from their point's projection in kf3.
TEST(MapFusion, LinksMissedKeypointsAndMergesDuplicates) {
  FusionScene s;
  const std::vector<long> original = s.initialMap()->point_id;
  ASSERT_EQ(s.map.numPoints(), static_cast<size_t>(kN));

  Frame f2 = s.frame(2, 0.3), f3 = s.frame(3, 0.45);
  for (int i = 0; i < 60; ++i) f2.point_id[i] = f3.point_id[i] = original[i];
  for (int i = 100; i < 105; ++i)
    for (int b = 0; b < 32; ++b) f3.descriptors.at<uint8_t>(i, b) ^= 0xff;
  for (int i = 105; i < 110; ++i) f3.keypoints[i].pt.x += 8.f;
  const long kf2 = s.map.addKeyframe(f2), kf3 = s.map.addKeyframe(f3);
  std::vector<NewMapPoint> dup;
  for (int i = 60; i < 90; ++i) dup.push_back({s.world[i], kf3, i, kf2, i});
  s.map.addTriangulatedPoints(dup);
  ASSERT_EQ(s.map.numPoints(), static_cast<size_t>(kN + 30));
  ASSERT_EQ(s.map.trackedPoints(kf3, 1), 90);

  TrackerParams p;
  p.fuse_neighbors = 6;  // off by default (docs/decisions.md: measured, not adopted)
  Matcher matcher(s.cam, p);
  std::vector<FusionLink> links;
  const std::vector<FusionTarget> targets = fusionTargets(s.map, kf3, p.fuse_neighbors);
  ASSERT_FALSE(targets.empty());
  EXPECT_EQ(targets[0].keyframe->id, kf3) << "the new keyframe first";
  for (const FusionTarget& t : targets) {
    const auto l = matcher.searchForFusion(t, p.fuse_radius_px);
    links.insert(links.end(), l.begin(), l.end());
  }
  const std::pair<int, int> r = applyFusion(links, &s.map);
  EXPECT_EQ(r.second, 30) << "every duplicate merged";
  EXPECT_EQ(r.first, 20) << "keypoints 90-99 and 110-119 of kf3 got their point";
  EXPECT_EQ(s.map.numPoints(), static_cast<size_t>(kN));
  // kf3 now shows the original points, except the 10 keypoints that do not fit.
  EXPECT_EQ(s.map.trackedPoints(kf3, 1), kN - 10);
  // Merged points keep the older id and all four views; kf2 shows them too.
  EXPECT_EQ(s.map.trackedPoints(kf3, 4), 90);
  EXPECT_EQ(s.map.trackedPoints(kf2, 4), 90);
}

TEST(MapFusion, TheMapperFusesEachNewKeyframeUnlessTurnedOff) {
  for (const int neighbors : {0, 6}) {
    FusionScene s;
    const KeyframePtr kf1 = s.initialMap();
    Frame f2 = s.frame(2, 0.3);
    for (int i = 0; i < 60; ++i) f2.point_id[i] = kf1->point_id[i];
    const long kf2 = s.map.addKeyframe(f2);
    TrackerParams p;
    p.mapping_thread = false;
    p.fuse_neighbors = neighbors;
    p.ba_max_num_iterations = 0;
    LocalMapper mapper(s.cam, p, &s.map);
    mapper.createNewMapPoints(kf2);
    // Fusion links the 60 keypoints tracking missed; without it they stay unlinked (all their points exist).
    EXPECT_EQ(s.map.trackedPoints(kf2, 3), neighbors > 0 ? kN : 60) << "fuse_neighbors " << neighbors;
    EXPECT_EQ(s.map.numPoints(), static_cast<size_t>(kN));
  }
}

// The scale-prediction reference (tracker.predict_scale) is copied only when a camera is given: the oldest keyframe
// observing the point (kf0 at the origin), its keypoint's octave and its image scale there (pinhole: f / z at the
// axis, up to cos^-0.5 more off it).
TEST(MapFusion, LocalPointsCarryTheScaleReferenceOnlyWhenAsked) {
  FusionScene s;
  s.initialMap();
  for (const LocalPoint& lp : s.map.localPoints()) EXPECT_FALSE(lp.has_ref);
  const std::vector<LocalPoint> local = s.map.localPoints(&s.cam);
  ASSERT_EQ(local.size(), static_cast<size_t>(kN));
  for (const LocalPoint& lp : local) {
    ASSERT_TRUE(lp.has_ref);
    EXPECT_LT(lp.ref_center.norm(), 1e-9);
    EXPECT_EQ(lp.ref_octave, 0);
    const double axis = 450.0 / lp.p_w.z();
    EXPECT_GE(lp.ref_scale, axis * (1 - 1e-9));
    EXPECT_LE(lp.ref_scale, axis * 1.1);
  }
}

}  // namespace
}  // namespace iraf_vo
