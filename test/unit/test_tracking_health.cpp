// The tracking health monitor with injected faults of known truth: repeated and swapped frames, a frame from
// another place, a sudden texture change and a jump of the camera. Whatever the tracker reports as TRACKING
// must be right (checked against the truth after a Sim(3) alignment on the clean frames before the fault), the
// faulty frames must not be reported as TRACKING, tracking must come back, and a clean run gets no rejection.
#include <gtest/gtest.h>
#include <iraf_vo/tracking/health_monitor.h>
#include <iraf_vo/tracking/tracker.h>

#include "unit/tracking_test_utils.h"

#include <Eigen/Eigenvalues>
#include <functional>

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

// Sideways motion (~1.5 % of the scene depth per frame, as a hand-held camera at 20 Hz) with gentle rotation.
Eigen::Isometry3d truePose(double i) {
  return makePose({1.5 * std::sin(i * 0.07), 3.0 * std::sin(i * 0.05), 0.5 * std::sin(i * 0.03)},
                  {0.1 * i, 0.3 * std::sin(i * 0.04), 0.02 * i});
}

struct Fixture {
  CameraModelPtr cam = std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
  SyntheticWorld world, other;
  Fixture() {
    world.addBox(2500, {-4, -3, 5}, {16, 3, 12});
    other.rng.seed(99);
    other.addBox(2500, {-4, -3, 5}, {16, 3, 12});
  }
};

struct Outcome {
  std::vector<TrackResult> results;
  std::vector<Eigen::Isometry3d> truth;  // per result: the pose the frame was rendered from
  TrackerStats stats;
};

// Feeds frames 0..n-1; `inject(i)` may replace frame i by a list of (pose, frame) pairs.
using Injector = std::function<std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>>(int, Fixture&, const FeatureFrame&)>;

Outcome runWith(Fixture& fx, int n, const Injector& inject, bool monitor = true) {
  TrackerParams p;
  p.mapping_thread = false;
  p.health_monitor = monitor;
  Tracker tracker(fx.cam, p);
  Outcome out;
  for (int i = 0; i < n; ++i) {
    const FeatureFrame clean = fx.world.render(*fx.cam, truePose(i), 0.05 * i);
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> frames = inject ? inject(i, fx, clean)
                                                                            : decltype(frames){};
    if (frames.empty()) frames.push_back({truePose(i), clean});
    for (const auto& f : frames) {
      out.results.push_back(tracker.track(f.second));
      out.truth.push_back(f.first);
    }
  }
  out.stats = tracker.stats();
  return out;
}

// Sim(3) from the tracked frames among the first `n_align` results onto the truth.
Eigen::Matrix4d alignOnPrefix(const Outcome& o, size_t n_align) {
  std::vector<Eigen::Vector3d> est, gt;
  for (size_t k = 0; k < n_align; ++k)
    if (o.results[k].state == TrackingState::kTracking) {
      est.push_back(o.results[k].T_w_c.translation());
      gt.push_back(o.truth[k].translation());
    }
  Eigen::Matrix3Xd A(3, est.size()), B(3, gt.size());
  for (size_t k = 0; k < est.size(); ++k) {
    A.col(k) = est[k];
    B.col(k) = gt[k];
  }
  return Eigen::umeyama(A, B, true);
}

// Every TRACKING pose after the prefix is within `tol` of the truth (the prefix fixes the alignment).
void expectTrackedPosesRight(const Outcome& o, size_t n_align, double tol) {
  const Eigen::Matrix4d S = alignOnPrefix(o, n_align);
  for (size_t k = n_align; k < o.results.size(); ++k) {
    if (o.results[k].state != TrackingState::kTracking) continue;
    const Eigen::Vector3d e = (S * o.results[k].T_w_c.translation().homogeneous()).head<3>();
    EXPECT_LT((e - o.truth[k].translation()).norm(), tol) << "result " << k << " reported TRACKING with a wrong pose";
  }
}

int countTracked(const Outcome& o, size_t from) {
  int n = 0;
  for (size_t k = from; k < o.results.size(); ++k) n += o.results[k].state == TrackingState::kTracking;
  return n;
}

constexpr int kFault = 45;   // frame index of the injected fault (tracking is well settled)
constexpr int kFrames = 70;

}  // namespace

TEST(TrackingHealth, QuietOnACleanRun) {
  Fixture fx;
  const Outcome o = runWith(fx, kFrames, nullptr);
  EXPECT_EQ(o.stats.rejected, 0);
  EXPECT_EQ(o.stats.lost_events, 0);
  EXPECT_GE(o.stats.tracked, kFrames - 8);
  for (const auto& r : o.results)
    if (r.state == TrackingState::kTracking) {
      EXPECT_GT(r.inlier_ratio, 0.5);
      // Covariance: symmetric positive definite.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(r.covariance);
      EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
      EXPECT_LT((r.covariance - r.covariance.transpose()).norm(), 1e-12);
    }
  std::vector<Eigen::Vector3d> est, gt;
  for (size_t k = 0; k < o.results.size(); ++k)
    if (o.results[k].state == TrackingState::kTracking) {
      est.push_back(o.results[k].T_w_c.translation());
      gt.push_back(o.truth[k].translation());
    }
  EXPECT_LT(ateRmse(est, gt), 0.05);
}

Injector repeatFrame() {
  return [](int i, Fixture&, const FeatureFrame& f) {
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> v;
    if (i != kFault) return v;
    FeatureFrame again = f;
    again.stamp += 0.025;
    v.push_back({truePose(i), f});
    v.push_back({truePose(i + 0.5), again});  // the camera moved on, the driver sent the old image again
    return v;
  };
}

Injector swapFrames() {
  return [](int i, Fixture& f, const FeatureFrame&) {
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> v;
    if (i == kFault) v.push_back({truePose(i + 1), f.world.render(*f.cam, truePose(i + 1), 0.05 * i)});
    if (i == kFault + 1) v.push_back({truePose(i - 1), f.world.render(*f.cam, truePose(i - 1), 0.05 * i)});
    return v;
  };
}

TEST(TrackingHealth, WithoutTheMonitorTheseFaultsPassAsTracking) {
  // The same faults with health_monitor off: the tracker alone reports them as TRACKING (so the checks below
  // test the monitor, not the matcher).
  Fixture fx;
  EXPECT_EQ(runWith(fx, kFault + 3, repeatFrame(), false).results[kFault + 1].state, TrackingState::kTracking);
  Fixture fy;
  EXPECT_EQ(runWith(fy, kFault + 3, swapFrames(), false).results[kFault + 1].state, TrackingState::kTracking);
}

TEST(TrackingHealth, RepeatedFrameIsRejected) {
  Fixture fx;
  const Outcome o = runWith(fx, kFrames, repeatFrame());
  const TrackResult& dup = o.results[kFault + 1];
  EXPECT_NE(dup.state, TrackingState::kTracking);
  EXPECT_NE(dup.rejected.find("duplicate"), std::string::npos) << dup.rejected;
  EXPECT_GE(countTracked(o, kFault + 2), kFrames - kFault - 3) << "tracking continues";
  expectTrackedPosesRight(o, kFault, 0.05);
}

TEST(TrackingHealth, SwappedFramesAreRejected) {
  Fixture fx;
  const Outcome o = runWith(fx, kFrames, swapFrames());
  // The frame that goes backwards in time is not trusted.
  EXPECT_NE(o.results[kFault + 1].state, TrackingState::kTracking);
  EXPECT_NE(o.results[kFault + 1].rejected.find("jump"), std::string::npos) << o.results[kFault + 1].rejected;
  EXPECT_GE(countTracked(o, kFault + 2), kFrames - kFault - 4);
  expectTrackedPosesRight(o, kFault, 0.05);
}

TEST(TrackingHealth, FrameFromAnotherPlaceIsNotTracked) {
  Fixture fx;
  const Outcome o = runWith(fx, kFrames, [](int i, Fixture& f, const FeatureFrame&) {
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> v;
    if (i == kFault) v.push_back({truePose(i), f.other.render(*f.cam, truePose(i), 0.05 * i)});
    return v;
  });
  EXPECT_NE(o.results[kFault].state, TrackingState::kTracking);
  EXPECT_GE(countTracked(o, kFault + 1), kFrames - kFault - 6) << "tracking comes back";
  expectTrackedPosesRight(o, kFault, 0.05);
}

TEST(TrackingHealth, SuddenTextureChangeNeverGivesAWrongTrackedPose) {
  Fixture fx;
  // From the fault on, 60 % of the scene's texture changes (posters replaced, light pattern): those points'
  // descriptors are new; the rest of the scene still anchors the pose.
  const Outcome o = runWith(fx, kFrames, [](int i, Fixture& f, const FeatureFrame&) {
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> v;
    if (i == kFault) {
      std::mt19937 rng(5);
      std::uniform_int_distribution<int> byte(0, 255), pick(0, 9);
      for (auto& d : f.world.desc)
        if (pick(rng) < 6)
          for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    }
    return v;
  });
  expectTrackedPosesRight(o, kFault, 0.05);
  EXPECT_GE(countTracked(o, kFault), kFrames - kFault - 6);
}

TEST(TrackingHealth, CameraJumpIsRejectedThenRelocalized) {
  Fixture fx;
  const Eigen::Vector3d jump(1.5, 0.0, 0.0);  // 15 frames' worth of motion in one frame
  auto jumped = [jump](double i) {
    Eigen::Isometry3d T = truePose(i);
    T.translation() += jump;
    return T;
  };
  const Outcome o = runWith(fx, kFrames, [&](int i, Fixture& f, const FeatureFrame&) {
    std::vector<std::pair<Eigen::Isometry3d, FeatureFrame>> v;
    if (i >= kFault) v.push_back({jumped(i), f.world.render(*f.cam, jumped(i), 0.05 * i)});
    return v;
  });
  EXPECT_NE(o.results[kFault].state, TrackingState::kTracking) << "the jump itself is not trusted";
  EXPECT_GE(countTracked(o, kFault + 1), kFrames - kFault - 8) << "relocalized after the jump";
  expectTrackedPosesRight(o, kFault, 0.08);
}

TEST(TrackingHealth, MonitorChecksInIsolation) {
  TrackerParams p;
  TrackingHealthMonitor m(p);
  HealthInput in;
  in.inliers = 40;
  in.refine_matches = 100;
  EXPECT_NE(m.check(in).find("inlier ratio"), std::string::npos);
  in.inliers = 90;
  in.median_chi2 = 5.0;
  EXPECT_NE(m.check(in).find("chi2"), std::string::npos);
  in.median_chi2 = 1.0;
  in.ba_scale_change = 0.5;
  EXPECT_NE(m.check(in).find("scale"), std::string::npos);
  in.metric_scale = true;
  EXPECT_EQ(m.check(in), "") << "stereo map with its right image: the scale is observed, no map-scale check";
  in.ba_scale_change = 2.5;
  EXPECT_EQ(m.check(in), "");
  in.metric_scale = false;
  EXPECT_NE(m.check(in).find("scale"), std::string::npos) << "monocular map (or no right image): checked";
  in.ba_scale_change = 1.1;
  EXPECT_EQ(m.check(in), "");
  // Constant velocity 0.1 / frame at depth 5: a step as predicted passes, a reversal or a leap is a jump.
  auto at = [](double x) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation().x() = x;
    return T;
  };
  for (int k = 0; k < 5; ++k) m.accept(at(0.1 * k), at(0.1 * (k + 1)));
  in.median_depth = 5.0;
  in.have_motion_model = true;
  in.T_w_last = at(0.5);
  in.T_w_predicted = at(0.6);
  in.T_w_c = at(0.61);
  EXPECT_EQ(m.check(in), "");
  in.T_w_c = at(0.4);
  EXPECT_NE(m.check(in).find("reversed"), std::string::npos);
  in.T_w_c = at(1.2);
  EXPECT_NE(m.check(in).find("jump"), std::string::npos);
  in.have_motion_model = false;
  EXPECT_EQ(m.check(in), "") << "no motion model (after a loss): no motion checks";
  in.have_motion_model = true;
  p.health_monitor = false;
  EXPECT_EQ(m.check(in), "") << "off: never fires";
}
