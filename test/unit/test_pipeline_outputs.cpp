// ROS-free helpers of the live nodelets: OdometryOutput (base frame composition, covariance in the base frame,
// twist from consecutive poses), run_monitor.h (missed frames from stamp gaps, rates, throttling, health) and
// InputWatchdog (a stopped publisher).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "iraf_vo/pipeline/anchored_trajectory.h"
#include "iraf_vo/pipeline/input_watchdog.h"
#include "iraf_vo/pipeline/odometry_output.h"
#include "iraf_vo/pipeline/run_monitor.h"

using namespace iraf_vo;

namespace {

Eigen::Isometry3d makeT(const Eigen::Vector3d& t, const Eigen::Vector3d& rotvec) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (rotvec.norm() > 0) T.linear() = Eigen::AngleAxisd(rotvec.norm(), rotvec.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// REP-103: optical frame (z forward, x right, y down) in a z-up base looking along base x.
Eigen::Isometry3d opticalInBase() {
  Eigen::Isometry3d B = Eigen::Isometry3d::Identity();
  B.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  B.translation() = Eigen::Vector3d(0.2, 0.0, 0.5);
  return B;
}

Matrix6d randomSpd(int seed) {
  std::srand(seed);
  const Matrix6d A = Matrix6d::Random();
  return A * A.transpose() * 1e-4 + Matrix6d::Identity() * 1e-6;
}

double minEigen(const Matrix6d& c) { return Eigen::SelfAdjointEigenSolver<Matrix6d>(c).eigenvalues().minCoeff(); }

}  // namespace

TEST(OdometryOutput, IdentityBaseIsTheCameraPose) {
  OdometryOutput out;
  const Eigen::Isometry3d T = makeT({1, 2, 3}, {0.1, -0.2, 0.3});
  const Matrix6d C = randomSpd(1);
  const OdometrySample s = out.update(10.0, T, C);
  EXPECT_TRUE(s.T_odom_base.isApprox(T, 1e-12));
  EXPECT_TRUE(s.pose_covariance.isApprox(C, 1e-9));
  EXPECT_FALSE(s.has_twist);  // first pose
}

TEST(OdometryOutput, ForwardCameraMotionIsBaseXInAZUpOdom) {
  Eigen::Isometry3d B = opticalInBase();
  B.translation().setZero();  // no lever arm here (CovarianceMatchesNumericalPropagation has one)
  OdometryOutput out(B);
  // The camera moves 1 unit along its optical axis (z) in 0.5 s and yaws (turns right in the image = about -y_optical,
  // which is +z... of the base: a left turn of the base is a rotation about base +z = optical -y).
  const Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d T1 = makeT({0, 0, 1}, {0, -0.1, 0});
  out.update(0.0, T0, randomSpd(2));
  const OdometrySample s = out.update(0.5, T1, randomSpd(3));
  EXPECT_NEAR(s.T_odom_base.translation().x(), 1.0, 1e-9);  // forward = base x
  EXPECT_NEAR(s.T_odom_base.translation().y(), 0.0, 1e-9);
  EXPECT_NEAR(s.T_odom_base.translation().z(), 0.0, 1e-9);  // up stays up
  const Eigen::AngleAxisd aa(s.T_odom_base.rotation());
  EXPECT_NEAR(aa.angle(), 0.1, 1e-9);
  EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-9);  // a yaw about the z-up axis
  ASSERT_TRUE(s.has_twist);
  EXPECT_NEAR(s.twist(5), 0.2, 1e-9);   // wz = 0.1 rad / 0.5 s, left turn positive
  EXPECT_NEAR(s.twist.head<3>().norm(), 2.0, 1e-9);  // 1 unit / 0.5 s
  EXPECT_GT(minEigen(s.twist_covariance), 0.0);
}

TEST(OdometryOutput, CovarianceMatchesNumericalPropagation) {
  // Perturb the camera pose with the core's convention (dc in the world, R' = Exp(dtheta) R) and check the base pose
  // perturbation (position in odom, odom-frame rotation) against the analytic Jacobian through the covariance.
  const Eigen::Isometry3d B = opticalInBase();
  const Eigen::Isometry3d T = makeT({0.3, -0.2, 1.5}, {0.2, 0.4, -0.1});
  Matrix6d J;
  const Eigen::Isometry3d base0 = B * T * B.inverse();
  for (int k = 0; k < 6; ++k) {
    const double h = 1e-6;
    Eigen::Isometry3d Tp = T;
    if (k < 3) Tp.translation()[k] += h;
    else Tp.linear() = Eigen::AngleAxisd(h, Eigen::Vector3d::Unit(k - 3)).toRotationMatrix() * T.rotation();
    const Eigen::Isometry3d base1 = B * Tp * B.inverse();
    J.block<3, 1>(0, k) = (base1.translation() - base0.translation()) / h;
    const Eigen::AngleAxisd d(base1.rotation() * base0.rotation().transpose());
    J.block<3, 1>(3, k) = d.axis() * d.angle() / h;
  }
  const Matrix6d C = randomSpd(4);
  const Matrix6d expected = J * C * J.transpose();
  const Matrix6d got = baseCovariance(C, T, B);
  EXPECT_LT((got - expected).norm(), 1e-5 * expected.norm());
  EXPECT_GT(minEigen(got), 0.0);
}

TEST(OdometryOutput, PositiveDefiniteRepairsBadMatrices) {
  Matrix6d c = Matrix6d::Zero();
  c(0, 0) = -1.0;
  c(0, 1) = 0.5;
  EXPECT_GT(minEigen(positiveDefinite(c)), 0.0);
  c(2, 2) = std::nan("");
  EXPECT_GT(minEigen(positiveDefinite(c)), 0.0);
  EXPECT_TRUE(positiveDefinite(c).allFinite());
}

TEST(OdometryOutput, ResetForgetsTheTwist) {
  OdometryOutput out;
  out.update(0.0, Eigen::Isometry3d::Identity(), randomSpd(5));
  EXPECT_TRUE(out.update(0.05, makeT({0, 0, 0.1}, {0, 0, 0}), randomSpd(5)).has_twist);
  out.reset();
  EXPECT_FALSE(out.update(0.10, makeT({0, 0, 0.2}, {0, 0, 0}), randomSpd(5)).has_twist);
  EXPECT_FALSE(out.update(5.0, makeT({0, 0, 0.3}, {0, 0, 0}), randomSpd(5)).has_twist) << "dt above max_dt";
}

TEST(StampGapCounter, CountsMissingFramesFromStampSteps) {
  StampGapCounter g;
  const int64_t ms = 1000000;
  EXPECT_EQ(g.update(0), 0);
  EXPECT_EQ(g.update(50 * ms), 0);
  EXPECT_EQ(g.update(100 * ms), 0);
  EXPECT_EQ(g.update(250 * ms), 2);  // 150 ms = 3 periods: 2 missing
  EXPECT_EQ(g.update(300 * ms), 0);
  EXPECT_EQ(g.update(360 * ms), 0);  // jitter (1.2 periods) is not a drop
  EXPECT_EQ(g.update(5000 * ms), 0);  // a pause (bag paused) is not counted
  EXPECT_EQ(g.update(4000 * ms), 0);  // a step back (time jump) neither
  EXPECT_EQ(g.missed(), 2);
  EXPECT_NEAR(g.period(), 0.05, 1e-12);
}

TEST(StampGapCounter, OverloadedBurstKeepsTheTruePeriod) {
  // A 200 Hz burst of which only every 10th frame arrives after the first few: the smallest step stays 5 ms.
  StampGapCounter g;
  const int64_t ms = 1000000;
  long received = 0;
  for (int i = 0; i < 200; ++i)
    if (i < 3 || i % 10 == 0) g.update(i * 5 * ms), ++received;
  EXPECT_EQ(g.missed() + received, 200 - 9);  // frames after the last received one are unknown
}

TEST(StampGapCounter, JitteredHealthyStreamHasNoMissedFrames) {
  // 20 Hz with +-8 ms of stamp jitter (uniform): steps of 34..66 ms are not gaps. The smallest recent step as the
  // period (35 ms) made 45 of 200 frames "missed".
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> jitter(-8000, 8000);  // us
  const auto stamp = [&](int i) { return static_cast<int64_t>(i) * 50000000LL + jitter(rng) * 1000LL; };
  StampGapCounter healthy;
  for (int i = 0; i < 200; ++i) healthy.update(stamp(i));
  EXPECT_EQ(healthy.missed(), 0);
  EXPECT_NEAR(healthy.period(), 0.05, 0.004);
  // The same jittered stream with real drops: 1 frame at 60, 3 frames at 120-122, counted exactly.
  StampGapCounter dropping;
  for (int i = 0; i < 200; ++i)
    if (i != 60 && (i < 120 || i > 122)) dropping.update(stamp(i));
  EXPECT_EQ(dropping.missed(), 4);
}

TEST(StampGapCounter, FramesRejectedByTheGraphAreNotMissed) {
  StampGapCounter g;
  const int64_t ms = 1000000;
  for (int i = 0; i < 10; ++i) g.update(i * 50 * ms);
  EXPECT_EQ(g.update(600 * ms, 2), 0);  // frames 10 and 11 arrived and were rejected upstream (size guard)
  EXPECT_EQ(g.update(750 * ms, 1), 1);  // 2 missing, 1 of them rejected
  EXPECT_EQ(g.missed(), 1);
}

TEST(StampGapCounter, TimeJumpBackRestartsTheCount) {
  // A looped bag: after the jump back, gaps are counted again at once (they were ignored until the stamps passed
  // the first loop's last one).
  StampGapCounter g;
  const int64_t ms = 1000000;
  for (int i = 0; i < 100; ++i) g.update(i * 50 * ms);
  for (int i = 0; i < 100; ++i)
    if (i != 30 && i != 31) g.update(i * 50 * ms);
  EXPECT_EQ(g.missed(), 2);
  // A late frame (small step back) changes nothing.
  EXPECT_EQ(g.update(4900 * ms), 0);
  EXPECT_EQ(g.update(5000 * ms), 0);
  EXPECT_EQ(g.missed(), 2);
}

TEST(StampGapCounter, ACameraRateChangeIsNotAnEndlessOverload) {
  StampGapCounter g(20);
  const int64_t ms = 1000000;
  int64_t t = 0;
  for (int i = 0; i < 30; ++i) g.update(t += 50 * ms);  // 20 Hz
  for (int i = 0; i < 100; ++i) g.update(t += 100 * ms);  // then 10 Hz
  EXPECT_EQ(g.missed(), 19);  // one per long step until `window` of them in a row re-estimate the period
  EXPECT_NEAR(g.period(), 0.1, 1e-9);
}

TEST(InputWatchdog, AStoppedPublisherIsLateWithinThreePeriodsAndDeadAfterTheTimeout) {
  InputWatchdog w("image", 3.0);
  EXPECT_TRUE(w.check(0.0).empty()) << "idle until armed (lazy subscription)";
  w.arm("/cam0/image_raw", 100.0);
  std::string why;
  EXPECT_EQ(w.level(102.0, &why), HealthReport::kOk) << "a camera that has not started yet, before the timeout";
  double last = 0.0;
  for (int i = 0; i < 40; ++i) EXPECT_TRUE(w.onFrame(last = 102.0 + 0.05 * i + 0.004 * (i % 3 - 1)).empty());
  EXPECT_NEAR(w.period(), 0.05, 0.009);
  // The publisher stops: nothing within 2 periods, a warning naming the topic before 3 periods, once.
  EXPECT_TRUE(w.check(last + 0.10).empty());
  const std::vector<SessionMessage> late = w.check(last + 0.145);
  ASSERT_EQ(late.size(), 1u);
  EXPECT_EQ(late[0].level, SessionMessage::Level::kWarn);
  EXPECT_NE(late[0].text.find("no image on /cam0/image_raw"), std::string::npos) << late[0].text;
  EXPECT_TRUE(w.check(last + 0.5).empty());
  EXPECT_EQ(w.level(last + 0.5, &why), HealthReport::kWarn);
  // ... an error after the timeout, once; /diagnostics ERROR naming the topic.
  const std::vector<SessionMessage> dead = w.check(last + 3.1);
  ASSERT_EQ(dead.size(), 1u);
  EXPECT_EQ(dead[0].level, SessionMessage::Level::kError);
  EXPECT_TRUE(w.check(last + 5.0).empty());
  EXPECT_EQ(w.level(last + 5.0, &why), HealthReport::kError);
  EXPECT_NE(why.find("/cam0/image_raw"), std::string::npos) << why;
  // Frames return: one info line, OK again.
  const std::vector<SessionMessage> back = w.onFrame(last + 6.0);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].level, SessionMessage::Level::kInfo);
  EXPECT_EQ(w.level(last + 6.01, &why), HealthReport::kOk);
  EXPECT_NEAR(w.period(), 0.05, 0.009) << "the outage is not a period";
  // Unsubscribed (no listener): no alarm however long.
  w.disarm();
  EXPECT_TRUE(w.check(last + 100.0).empty());
  EXPECT_EQ(w.level(last + 100.0, &why), HealthReport::kOk);
}

TEST(InputWatchdog, AHealthyJitteredStreamRaisesNothing) {
  InputWatchdog w("image", 3.0);
  w.arm("/cam0/image_raw", 0.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.008, 0.008);
  std::string why;
  for (int i = 0; i < 400; ++i) {
    const double t = 0.05 * i + jitter(rng);
    for (double c = t - 0.04; c < t; c += 0.01) EXPECT_TRUE(w.check(c).empty()) << c;
    EXPECT_TRUE(w.onFrame(t).empty());
    EXPECT_EQ(w.level(t + 0.001, &why), HealthReport::kOk) << why;
  }
}

TEST(RunMonitor, ShutdownSummary) {
  SessionCounters c;
  c.frames = 866, c.tracked = 850, c.lost_events = 1, c.resets = 2, c.time_resets = 1, c.dropped = 3;
  EXPECT_EQ(sessionSummary(c, 4), "summary: 866 frames, 850 tracked (98.2 %), 1 lost events, 2 resets, 1 time resets, "
                                  "3 dropped, 4 missed");
}

TEST(RunMonitor, RatesThrottleAndHealth) {
  RateMeter r(5.0);
  for (int i = 0; i <= 20; ++i) r.tick(100.0 + 0.1 * i);
  EXPECT_NEAR(r.rate(102.0), 10.0, 1e-6);
  EXPECT_NEAR(r.rate(200.0), 0.0, 1e-12);

  MessageThrottle t;
  const SessionMessage lost{SessionMessage::Level::kWarn, "LOST", "lost"};
  const SessionMessage drop{SessionMessage::Level::kWarn, "dropping", "drop"};
  EXPECT_TRUE(t.allow(lost, 0.0));
  EXPECT_TRUE(t.allow(drop, 0.1)) << "kinds are throttled separately";
  EXPECT_FALSE(t.allow(lost, 0.5));
  EXPECT_TRUE(t.allow(lost, 1.2));
  EXPECT_FALSE(t.allow(drop, 3.0));
  EXPECT_TRUE(t.allow(SessionMessage{SessionMessage::Level::kInfo, "x", "init"}, 3.0));

  TrackerMonitor m;
  const std::string reason = calibrationReason("", "", "/cam0/camera_info", "");
  EXPECT_NE(reason.find("waiting for camera_info on /cam0/camera_info"), std::string::npos) << reason;
  HealthReport h = m.health(reason, "", SessionCounters(), 0.0);
  EXPECT_EQ(h.level, HealthReport::kError);
  EXPECT_EQ(h.summary, reason);
  const int64_t ms = 1000000;
  EXPECT_TRUE(m.onInput(0.0, 0).empty());
  EXPECT_TRUE(m.onInput(0.05, 50 * ms).empty());
  const std::vector<SessionMessage> w = m.onInput(0.1, 200 * ms);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].key, "drop");
  EXPECT_NE(w[0].text.find("2 frame(s) missed"), std::string::npos) << w[0].text;
  SessionStep step;
  step.tracked_frame = true;
  step.result.state = TrackingState::kTracking;
  m.onStep(step);
  h = m.health("", "pinhole", SessionCounters(), 0.2);
  EXPECT_EQ(h.level, HealthReport::kWarn) << h.summary;  // frames missed since the last report
  h = m.health("", "pinhole", SessionCounters(), 0.3);
  EXPECT_EQ(h.level, HealthReport::kOk) << h.summary;
  EXPECT_NE(m.statusLine(step, 0.3).find("missed 2"), std::string::npos) << m.statusLine(step, 0.3);
}

// The trajectory after mapping: a frame follows its reference keyframe's later (BA-refined) pose; frames without a
// known keyframe keep their online pose; lost frames are not in it.
TEST(KeyframeAnchoredTrajectory, FramesFollowTheirKeyframesRefinedPose) {
  iraf_vo::KeyframeAnchoredTrajectory traj;
  iraf_vo::TrackResult r;
  r.state = iraf_vo::TrackingState::kTracking;
  r.reference_keyframe_id = 7;
  r.T_kf_c = Eigen::Isometry3d(Eigen::Translation3d(0.1, 0, 0));
  r.T_w_c = Eigen::Isometry3d(Eigen::Translation3d(1.1, 0, 0));  // keyframe 7 at x = 1 when tracked
  traj.addFrame(1.0, r);
  iraf_vo::TrackResult lost = r;
  lost.state = iraf_vo::TrackingState::kLost;
  traj.addFrame(2.0, lost);
  iraf_vo::TrackResult orphan = r;
  orphan.reference_keyframe_id = 99;
  orphan.T_w_c = Eigen::Isometry3d(Eigen::Translation3d(5, 0, 0));
  traj.addFrame(3.0, orphan);
  iraf_vo::KeyframePose k;
  k.id = 7;
  k.T_w_c = Eigen::Isometry3d(Eigen::Translation3d(1, 0, 0));
  traj.updateKeyframes({k});
  k.T_w_c = Eigen::Isometry3d(Eigen::Translation3d(2, 1, 0));  // BA moved it; later the keyframe left the map
  traj.updateKeyframes({k});
  traj.updateKeyframes({});
  const iraf_vo::Trajectory t = traj.build();
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t.stamps[0], 1.0);
  EXPECT_LT((t.poses[0].translation() - Eigen::Vector3d(2.1, 1, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(t.stamps[1], 3.0);
  EXPECT_LT((t.poses[1].translation() - Eigen::Vector3d(5, 0, 0)).norm(), 1e-12);
}
