// The Tracker end to end on synthetic feature frames (random textured points, known trajectory): initialization,
// frame-to-map tracking, keyframes + triangulation + sliding-window BA (synchronous and threaded), loss and recovery.
#include <gtest/gtest.h>
#include <iraf_vo/tracking/tracker.h>

#include "unit/tracking_test_utils.h"

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

// Sideways motion with yaw/pitch oscillation in front of a box of points (camera z forward, world = first camera).
Eigen::Isometry3d truePose(int i) {
  const double t = i;
  return makePose({1.5 * std::sin(t * 0.07), 3.0 * std::sin(t * 0.05), 0.5 * std::sin(t * 0.03)},
                  {0.03 * t, 0.2 * std::sin(t * 0.04), 0.01 * t});
}

struct RunStats {
  int tracked = 0;
  int frames = 0;
  double ate = 1e9;
  TrackerStats stats;
  size_t map_points = 0, keyframes = 0;
};

RunStats run(const CameraModelPtr& cam, TrackerParams params, int n_frames, int blackout_begin = -1,
             int blackout_end = -1) {
  SyntheticWorld world;
  world.addBox(1300, {-4, -3, 4}, {6, 3, 10});
  // Blackout: every frame shows unrelated points and descriptors, which the tracker can neither match nor
  // initialize from (one fixed unrelated world is a rigid scene: it initializes within a few frames).
  if (getenv("TRACKING_TEST_CERES")) params.pose_use_ceres = true;
  Tracker tracker(cam, params);
  std::vector<Eigen::Vector3d> est, gt;
  RunStats rs;
  for (int i = 0; i < n_frames; ++i) {
    const bool black = i >= blackout_begin && i < blackout_end;
    SyntheticWorld other;
    if (black) {
      other.rng.seed(99 + i);
      other.addBox(1300, {-4, -3, 4}, {6, 3, 10});
    }
    const FeatureFrame f = (black ? other : world).render(*cam, truePose(i), 0.05 * i);
    const TrackResult r = tracker.track(f);
    if (getenv("TRACKING_TEST_VERBOSE"))
      printf("%d %s kps=%zu inl=%d m=%d kf=%d prep=%.1f init=%.1f match=%.1f pose=%.1f kf=%.1f tot=%.1f\n", i,
             toString(r.state), f.keypoints.size(), r.inliers, r.matches, r.is_keyframe, r.timing.ms_prepare,
             r.timing.ms_init, r.timing.ms_match, r.timing.ms_pose, r.timing.ms_keyframe, r.timing.ms_total);
    if (getenv("TRACKING_TEST_VERBOSE") && !r.init_status.empty()) printf("  init: %s\n", r.init_status.c_str());
    ++rs.frames;
    if (r.state == TrackingState::kTracking) {
      ++rs.tracked;
      est.push_back(r.T_w_c.translation());
      gt.push_back(truePose(i).translation());
    }
    if (black) {
      EXPECT_NE(r.state, TrackingState::kTracking) << "frame " << i;
    }
  }
  tracker.waitForMapping();
  rs.stats = tracker.stats();
  rs.ate = ateRmse(est, gt);
  rs.map_points = tracker.mapPoints().size();
  rs.keyframes = tracker.keyframePoses().size();
  return rs;
}

}  // namespace

TEST(TrackingPipeline, SyntheticSequenceSynchronousMapping) {
  auto cam = std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
  TrackerParams p;
  p.mapping_thread = false;
  const RunStats rs = run(cam, p, 120);
  EXPECT_GE(rs.tracked, 0.9 * rs.frames);
  EXPECT_LT(rs.ate, 0.02);  // path ~3.7 m
  EXPECT_EQ(rs.stats.lost_events, 0);
  EXPECT_GE(rs.stats.keyframes, 4);
  EXPECT_GT(rs.stats.ba_runs, 0);
  EXPECT_LE(static_cast<int>(rs.keyframes), p.max_map_keyframes);
  EXPECT_GT(rs.map_points, 100u);
}

TEST(TrackingPipeline, SyntheticSequenceFisheyeThreadedMapping) {
  auto cam = std::make_shared<TestFisheye>(640, 512, 230.0, 320.0, 256.0);
  TrackerParams p;
  p.mapping_thread = true;
  const RunStats rs = run(cam, p, 120);
  EXPECT_GE(rs.tracked, 0.9 * rs.frames);
  EXPECT_LT(rs.ate, 0.03);
  EXPECT_EQ(rs.stats.lost_events, 0);
}

// Threaded mapping: each keyframe's BA runs on the mapping thread and is written back at the next keyframe (the
// tracker waits for it there), so a threaded run is reproducible: two runs give the same trajectory.
TEST(TrackingPipeline, ThreadedMappingIsReproducible) {
  auto cam = std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
  TrackerParams p;
  p.mapping_thread = true;
  // The BA's CPU-time budget (0.1 s) is a deliberate dependence on the machine's speed: on a starved virtual
  // machine (the hypervisor taking ~70 % of the time) one run hit it and the other did not. Thread timing is
  // what this test is about, so the budget is lifted here.
  p.ba_max_solver_time_in_seconds = 10.0;
  const RunStats a = run(cam, p, 100), b = run(cam, p, 100);
  EXPECT_GE(a.tracked, 0.9 * a.frames);
  EXPECT_LT(a.ate, 0.02);
  EXPECT_EQ(a.stats.lost_events, 0);
  EXPECT_GT(a.stats.ba_runs, 0);
  EXPECT_EQ(a.ate, b.ate) << "threaded runs must not depend on thread timing";
  EXPECT_EQ(a.tracked, b.tracked);
}

TEST(TrackingPipeline, LossIsDetectedAndRecovered) {
  auto cam = std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
  TrackerParams p;
  p.mapping_thread = false;
  const RunStats rs = run(cam, p, 130, 50, 56);
  EXPECT_GE(rs.stats.lost_events, 1);
  EXPECT_GE(rs.stats.resets, 1);
  EXPECT_GE(rs.stats.initializations, 2);
  EXPECT_GE(rs.stats.lost_frames, 6);
  // Tracking resumes after the blackout: most of the remaining frames are tracked again.
  EXPECT_GE(rs.tracked, 50 - 5 + (130 - 56) - 25);
}

TEST(TrackingPipeline, RejectsBadInput) {
  auto cam = std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
  TrackerParams bad;
  bad.ba_window_size = 1;
  EXPECT_THROW(Tracker(cam, bad), std::invalid_argument);
  EXPECT_THROW(Tracker(nullptr, TrackerParams()), std::invalid_argument);
  TrackerParams p;
  p.mapping_thread = false;
  Tracker t(cam, p);
  FeatureFrame f;
  f.keypoints.resize(10);
  f.descriptors = cv::Mat::zeros(5, 32, CV_8U);  // mismatch
  const TrackResult r = t.track(f);
  EXPECT_NE(r.state, TrackingState::kTracking);
  EXPECT_EQ(t.stats().frames, 1);
}
