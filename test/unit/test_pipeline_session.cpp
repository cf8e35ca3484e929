// TrackingSession (pipeline/tracking_session.h): the run rules of the tracker nodelet on synthetic feature frames.
#include <gtest/gtest.h>
#include <iraf_vo/pipeline/tracking_session.h>

#include <fstream>

#include "common/tmp_dir.h"
#include "unit/tracking_test_utils.h"

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

constexpr int64_t kSecond = 1000000000;

struct SessionFixture : testing::Test {
  CameraModelPtr cam = std::make_shared<TestPinhole>(640, 480, 500, 320, 240);
  SyntheticWorld world;
  SessionFixture() { world.addBox(1300, {-4, -3, 4}, {6, 3, 10}); }

  static Eigen::Isometry3d pose(int i) { return makePose({0, 1.0 * std::sin(0.05 * i), 0}, {0.03 * i, 0, 0.01 * i}); }
  FeatureFrame frame(int i) { return world.render(*cam, pose(i), 0.05 * i); }
  static int64_t stampOf(int i) { return 100 * kSecond + i * (kSecond / 20); }

  /// Feeds frames [from, to); returns the index of the first tracked one (-1 if none).
  int feed(TrackingSession* s, int from, int to, SessionStep* last = nullptr) {
    int first_tracked = -1;
    for (int i = from; i < to; ++i) {
      const FeatureFrame f = frame(i);
      const SessionStep st = s->process(stampOf(i), &f);
      EXPECT_TRUE(st.tracked_frame) << i;
      if (st.has_pose && first_tracked < 0) first_tracked = i;
      if (last) *last = st;
    }
    return first_tracked;
  }
};

bool mentions(const SessionStep& s, const std::string& text) {
  for (const SessionMessage& m : s.messages)
    if (m.text.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_F(SessionFixture, DuplicatedAndLateStampsAreDroppedAJumpBackRestartsTheMap) {
  TrackerParams p;
  p.mapping_thread = false;
  TrackingSession s(cam, p, SessionOptions());
  ASSERT_GE(feed(&s, 0, 30), 0) << "the synthetic sequence never tracked";
  const size_t poses = s.trajectory().size();
  EXPECT_GT(poses, 0u);

  const FeatureFrame f = frame(30);
  SessionStep st = s.process(stampOf(29), &f);  // same stamp as the last frame
  EXPECT_FALSE(st.tracked_frame);
  EXPECT_TRUE(mentions(st, "duplicated stamp"));
  EXPECT_EQ(st.counters.dropped, 1);
  st = s.process(stampOf(29) - kSecond / 2, &f);  // 0.5 s late: within max_out_of_order
  EXPECT_FALSE(st.tracked_frame);
  EXPECT_TRUE(mentions(st, "out-of-order"));
  EXPECT_EQ(st.counters.dropped, 2);
  EXPECT_EQ(s.trajectory().size(), poses);  // nothing recorded for dropped frames

  st = s.process(stampOf(29) - 5 * kSecond, &f);  // the bag looped
  EXPECT_TRUE(st.tracked_frame);
  EXPECT_TRUE(st.time_jump);
  EXPECT_EQ(st.counters.time_resets, 1);
  EXPECT_FALSE(st.has_pose);             // a new map starts with initialization
  EXPECT_EQ(s.trajectory().size(), 0u);  // the recorded trajectory restarts
  EXPECT_EQ(st.counters.frames, 31);     // counters run over every tracker of the session
}

TEST_F(SessionFixture, UnusableFramesAreDroppedWithTheReason) {
  TrackingSession s(cam, TrackerParams(), SessionOptions());
  SessionStep st = s.process(kSecond, nullptr, "descriptors has 3 bytes");
  EXPECT_FALSE(st.tracked_frame);
  EXPECT_TRUE(mentions(st, "descriptors has 3 bytes"));
  FeatureFrame small = frame(0);
  small.width = 320;
  st = s.process(2 * kSecond, &small);
  EXPECT_FALSE(st.tracked_frame);
  EXPECT_TRUE(mentions(st, "320x480"));
  EXPECT_EQ(st.counters.dropped, 2);
  EXPECT_EQ(st.counters.frames, 0);
  EXPECT_THROW(TrackingSession(nullptr, TrackerParams(), SessionOptions()), std::invalid_argument);
}

TEST_F(SessionFixture, ParametersWaitWhileTrackingAndApplyAtTheRestartWhichKeepsThePathContinuous) {
  TrackerParams p;
  p.mapping_thread = false;
  TrackingSession s(cam, p, SessionOptions());
  TrackerParams q = p;
  q.ba_window_size = 7;
  s.setParams(q);  // nothing tracked yet: applied with the first frame
  SessionStep st;
  ASSERT_GE(feed(&s, 0, 30, &st), 0);
  EXPECT_EQ(s.params().ba_window_size, 7);
  ASSERT_TRUE(st.has_pose);
  const long resets = st.counters.resets;

  q.ba_window_size = 9;
  s.setParams(q);
  feed(&s, 30, 33, &st);
  ASSERT_TRUE(st.has_pose) << "tracking was lost: the test cannot tell a pending change";
  EXPECT_EQ(s.params().ba_window_size, 7) << "applied while tracking";
  EXPECT_EQ(st.counters.resets, resets);

  const Eigen::Isometry3d before = st.T_world_camera;
  s.requestRestart();
  const FeatureFrame f = frame(33);
  st = s.process(stampOf(33), &f);
  EXPECT_TRUE(mentions(st, "restarting the tracker with the new parameters"));
  EXPECT_EQ(s.params().ba_window_size, 9);
  EXPECT_EQ(st.counters.resets, resets + 1);
  const int again = feed(&s, 34, 60, &st);
  ASSERT_GE(again, 0) << "no tracking after the restart";
  // The new map is anchored at the last published pose: the path continues near it (new map scale: depth 1).
  const Eigen::Isometry3d T_first = s.trajectory().poses[s.trajectory().size() - (60 - again)];
  EXPECT_LT((T_first.translation() - before.translation()).norm(), 0.5);
}

TEST_F(SessionFixture, TrajectoryIsRecordedAndSavedAtKeyframes) {
  TrackerParams p;
  p.mapping_thread = false;
  SessionOptions o;
  o.trajectory_file = tmpRoot() + "session_traj.txt";
  TrackingSession s(cam, p, o);
  SessionStep st;
  long tracked = 0;
  long poses_at_keyframe = -1;
  for (int i = 0; i < 40; ++i) {
    const FeatureFrame f = frame(i);
    st = s.process(stampOf(i), &f);
    tracked += st.has_pose;
    if (st.result.is_keyframe) poses_at_keyframe = static_cast<long>(s.trajectory().size());
    if (st.map_changed) {
      EXPECT_FALSE(st.map_points.empty()) << i;
    }
  }
  EXPECT_EQ(static_cast<long>(s.trajectory().size()), tracked);
  EXPECT_EQ(st.counters.tracked, tracked);
  ASSERT_GT(poses_at_keyframe, 0) << "no keyframe in 40 frames";
  std::ifstream in(o.trajectory_file);
  long lines = 0;
  for (std::string l; std::getline(in, l);) lines += !l.empty() && l[0] != '#';
  EXPECT_EQ(lines, poses_at_keyframe);
  std::string err;
  EXPECT_TRUE(s.saveTrajectory(&err)) << err;
  TrackingSession no_file(cam, p, SessionOptions());
  EXPECT_FALSE(no_file.saveTrajectory(&err));
}

// The events a user sees on the console (kWarn messages with a key for per-kind throttling), the counters
// behind /diagnostics, and the covariance of the anchored pose.
TEST_F(SessionFixture, EventsAreReportedWithKeysAndTheAnchoredCovarianceIsRotated) {
  TrackerParams p;
  p.mapping_thread = false;
  TrackingSession s(cam, p, SessionOptions());
  auto keyed = [](const SessionStep& st, const std::string& key, SessionMessage::Level level) {
    for (const SessionMessage& m : st.messages)
      if (m.key == key && m.level == level) return true;
    return false;
  };
  bool init_seen = false;
  SessionStep st;
  for (int i = 0; i < 30; ++i) {
    const FeatureFrame f = frame(i);
    st = s.process(stampOf(i), &f);
    if (st.result.initialized_now) {
      EXPECT_TRUE(keyed(st, "init", SessionMessage::Level::kInfo)) << "the first initialization is not a warning";
      init_seen = true;
    }
  }
  ASSERT_TRUE(init_seen);
  ASSERT_TRUE(st.has_pose);
  EXPECT_EQ(st.counters.initializations, 1);
  EXPECT_EQ(st.counters.rejected, 0);

  s.requestRestart();
  const FeatureFrame f = frame(30);
  st = s.process(stampOf(30), &f);
  EXPECT_TRUE(keyed(st, "restart", SessionMessage::Level::kWarn));
  bool reinit = false;
  for (int i = 31; i < 60 && !reinit; ++i) {
    const FeatureFrame g = frame(i);
    st = s.process(stampOf(i), &g);
    reinit = keyed(st, "reinit", SessionMessage::Level::kWarn);
  }
  EXPECT_TRUE(reinit) << "the re-initialization after the restart is a warning";
  for (int i = 60; i < 70 && !st.has_pose; ++i) {
    const FeatureFrame g = frame(i);
    st = s.process(stampOf(i), &g);
  }
  ASSERT_TRUE(st.has_pose);
  // Anchored at the last pose before the restart (a rotation): same eigenvalues as the core's covariance, rotated.
  const Eigen::Matrix3d R = (st.T_world_camera * st.result.T_w_c.inverse()).rotation();
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topLeftCorner<3, 3>() = A.bottomRightCorner<3, 3>() = R;
  EXPECT_LT((st.covariance - A * st.result.covariance * A.transpose()).norm(), 1e-9 * st.covariance.norm());
  EXPECT_GT((R - Eigen::Matrix3d::Identity()).norm(), 1e-3) << "the anchor should not be the identity here";

  // A jump back in time is a warning with its own key.
  const FeatureFrame g = frame(0);
  st = s.process(stampOf(0), &g);
  EXPECT_TRUE(keyed(st, "time_jump", SessionMessage::Level::kWarn));
}

TEST_F(SessionFixture, EveryNewMapIsANewEpochWithItsCause) {
  TrackerParams p;
  p.mapping_thread = false;
  TrackingSession s(cam, p, SessionOptions());
  std::vector<std::pair<long, std::string>> epochs;  // (epoch, cause) at each new epoch
  const auto feedEpochs = [&](int from, int to, int64_t offset = 0) {
    for (int i = from; i < to; ++i) {
      const FeatureFrame f = frame(i);
      const SessionStep st = s.process(stampOf(i) + offset, &f);
      if (st.new_epoch) epochs.emplace_back(st.counters.epoch, st.epoch_cause);
      if (!st.new_epoch && !epochs.empty()) {
        EXPECT_EQ(st.counters.epoch, epochs.back().first) << i;
      }
    }
  };
  feedEpochs(0, 30);
  ASSERT_EQ(epochs.size(), 1u) << "the first map";
  EXPECT_EQ(epochs[0], std::make_pair(1L, std::string("initial")));
  s.requestRestart();  // ~reset: a new map anchored at the last pose, its own scale
  feedEpochs(30, 60);
  ASSERT_EQ(epochs.size(), 2u);
  EXPECT_EQ(epochs[1], std::make_pair(2L, std::string("restart")));
  feedEpochs(0, 30, -10 * kSecond);  // the bag looped
  ASSERT_EQ(epochs.size(), 3u);
  EXPECT_EQ(epochs[2], std::make_pair(3L, std::string("time_reset")));
}
