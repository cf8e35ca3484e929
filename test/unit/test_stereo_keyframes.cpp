// Stereo keyframes on a road: the near points (posts, signs) leave the view within 2-3 frames at 1 m per frame.
// Without a keyframe while they run out, the step between two keyframes is fixed by the farther points, whose
// stereo depth comes out short near the disparity floor, and the stereo path comes out short. The rule in
// isolation (keyframe_policy.h) and the metric path on the simulated highway (pinhole, seed 0, rendered in-process
// as iraf_vo_simulate --stereo renders it, synchronous mapping).
#include <gtest/gtest.h>
#include <iraf_vo/camera/stereo_rig.h>
#include <iraf_vo/pipeline/front_end.h>
#include <iraf_vo/pipeline/pipeline_params.h>
#include <iraf_vo/pipeline/tracking_session.h>
#include <iraf_vo/sim/renderer.h>
#include <iraf_vo/sim/sequence.h>
#include <iraf_vo/sim/sim_stereo_rig.h>
#include <iraf_vo/tracking/keyframe_policy.h>
#include <iraf_vo/tracking/tracker.h>

#include "motion_sim.h"

#include <algorithm>
#include <functional>
#include <map>
#include <string>
#include <vector>

using namespace iraf_vo;

namespace {

// A stereo frame one frame after a keyframe: mapping counts as busy, the inliers are 0.95 of the reference keyframe.
KeyframeCandidate stereoCandidate(int close_tracked, double close_untracked_share) {
  KeyframeCandidate c;
  c.frames_since_keyframe = 1;
  c.inliers = 190;
  c.reference_tracked = 200;
  c.stereo_close_tracked = close_tracked;
  c.stereo_close_untracked_share = close_untracked_share;
  return c;
}

struct RoadRun {
  double path_est = 0.0, path_true = 0.0;
  double min_step_ratio = 1e9;  // the shortest estimated step over the true one
  int tracked = 0, keyframes = 0;
  int weak_scale_frames = 0;  // tracked frames reported with a weakly observed metric scale
  int weak_scale_changes = 0;
};

// The highway rendered in-process as iraf_vo_simulate --stereo renders it, with the offline runner's stereo
// parameters (resolution rule of the camera, iraf front-end, synchronous mapping: deterministic).
struct Road {
  MotionSim m;
  PipelineParams pp;
  StereoRig rig;
  Eigen::Isometry3d T_l_r = Eigen::Isometry3d::Identity();  // the right camera in the left one
  std::string key;  // camera, seed, light and length: the rendered frames' cache key
  bool ok() const { return m.camera != nullptr; }
};

Road makeRoad(int frames, const std::string& camera, uint64_t seed, const std::string& light) {
  Road road;
  road.m = makeMotionSim(MotionKind::kHighway, camera, frames, 2, seed, light);
  if (!road.ok()) {
    ADD_FAILURE() << road.m.error;
    return road;
  }
  road.key = camera + "/" + std::to_string(seed) + "/" + light + "/" + std::to_string(frames);
  road.T_l_r = rightCameraInLeft(SimStereoRig(), road.m.sim.camera);
  applyResolutionRule(*road.m.camera, &road.pp);
  applyFrontEndMode(FrontEndMode::kIraf, &road.pp.enhance, &road.pp.features);
  road.pp.tracker.mapping_thread = false;
  road.rig.left = road.rig.right = road.m.camera;
  road.rig.T_r_l = road.T_l_r.inverse();
  return road;
}

// Renders both cameras frame by frame into on_frame (SimFrame::image / right_image). A road is rendered once per
// process and replayed to the next test that asks for it (the night road's motion blur renders at ~0.7 s a frame).
void renderRoad(const Road& road, const std::function<void(const SimFrame&)>& on_frame) {
  static std::map<std::string, std::vector<SimFrame>> rendered;
  const auto it = rendered.find(road.key);
  if (it != rendered.end()) {
    for (const SimFrame& f : it->second) on_frame(f);
    return;
  }
  const MotionSim& m = road.m;
  Renderer left(m.camera, m.scene, m.sim), right(m.camera, m.scene, m.sim);
  right.setPoseInRig(road.T_l_r);
  std::vector<SimFrame> frames;
  std::string err;
  EXPECT_TRUE(simulateSequence(left, &right, m.preset.traj, m.light, "",
                               [&](const SimFrame& f) {
                                 frames.push_back(f);  // own pixels: the renderer may reuse its buffers
                                 frames.back().image = f.image.clone();
                                 frames.back().right_image = f.right_image.clone();
                                 frames.back().depth = f.depth.clone();
                                 on_frame(f);
                               },
                               nullptr, &err))
      << err;
  if (err.empty()) rendered[road.key] = std::move(frames);
}

// Highway frames [0, frames) through the offline runner's stereo path: one FrontEnd per camera (the left one keeps
// its image for the sub-pixel disparities), the right features on demand.
RoadRun trackRoad(int frames, const std::string& camera = "pinhole", uint64_t seed = 0, int far_fill = -1,
                  const std::string& light = "clean") {
  Road road = makeRoad(frames, camera, seed, light);
  RoadRun run;
  if (!road.ok()) return run;
  const PipelineParams& pp = road.pp;
  if (far_fill >= 0) road.pp.tracker.stereo_far_fill_points = far_fill;
  FrontEnd left_front(pp.enhance, pp.features, true), right_front(pp.enhance, pp.features, true);
  Tracker tracker(road.rig, pp.tracker);
  Eigen::Vector3d last_est, last_true;
  bool have_last = false;
  renderRoad(road, [&](const SimFrame& f) {
    const double stamp = f.stamp_ns * 1e-9;
    const TrackResult r = tracker.track(left_front.process(f.image, stamp), true,
                                        [&] { return right_front.process(f.right_image, stamp); });
    if (r.state != TrackingState::kTracking) {
      have_last = false;
      return;
    }
    ++run.tracked;
    run.keyframes += r.is_keyframe;
    run.weak_scale_frames += r.metric_scale_weak;
    run.weak_scale_changes += r.metric_scale_changed;
    const Eigen::Vector3d est = r.T_w_c.translation(), truth = f.T_W_C.translation();
    if (have_last) {
      const double step_est = (est - last_est).norm(), step_true = (truth - last_true).norm();
      run.path_est += step_est;
      run.path_true += step_true;
      if (step_true > 0.1) run.min_step_ratio = std::min(run.min_step_ratio, step_est / step_true);
    }
    last_est = est;
    last_true = truth;
    have_last = true;
  });
  return run;
}

}  // namespace

TEST(StereoKeyframes, CloseRuleInIsolation) {
  const TrackerParams p;
  // Few close points tracked while the last keyframe left many untracked: a keyframe without the mapping wait.
  EXPECT_TRUE(needNewKeyframe(stereoCandidate(60, 0.12), p));
  // Enough close points tracked, or few close ones to gain: the ordinary rules decide (mapping busy: none).
  EXPECT_FALSE(needNewKeyframe(stereoCandidate(kStereoCloseTracked, 0.12), p));
  EXPECT_FALSE(needNewKeyframe(stereoCandidate(60, kStereoCloseUntrackedShare), p));
  // Monocular (no stereo counts): off.
  EXPECT_FALSE(needNewKeyframe(stereoCandidate(-1, 0.12), p));
  // min_frames_between_keyframes still holds.
  TrackerParams wait = p;
  wait.min_frames_between_keyframes = 2;
  EXPECT_FALSE(needNewKeyframe(stereoCandidate(60, 0.12), wait));
}

// Highway pinhole frames 0-30: without the rule the stereo path is 0.976 of the true one (keyframes every 3
// frames, the near points gone in between); with it 1.000.
TEST(StereoKeyframes, RoadPathIsMetric) {
  const RoadRun run = trackRoad(31);
  ASSERT_EQ(run.tracked, 31);
  ASSERT_GT(run.path_true, 25.0);
  const double ratio = run.path_est / run.path_true;
  EXPECT_NEAR(ratio, 1.0, 0.01) << "stereo path / true path over frames 0-30, " << run.keyframes << " keyframes";
}

// Highway fisheye (191 px, 0.10 m baseline, 1 m per frame) frames 0-11: the first steps after the one-frame start
// rest on the stereo points of frame 0, 123 of them closer than the 2-px disparity floor (9.5 m). With the far
// fill at ORB-SLAM's 100 no far point joins them and frames 1-7 are lost (two resets); with the default 200 the
// nearest far points fill the first map and every frame is tracked.
TEST(StereoKeyframes, FisheyeRoadStartKeepsTracking) {
  const RoadRun filled = trackRoad(12, "fisheye", 0);
  EXPECT_EQ(filled.tracked, 12);
  ASSERT_GT(filled.path_true, 9.0);
  EXPECT_NEAR(filled.path_est / filled.path_true, 1.0, 0.03);
  const RoadRun close_only = trackRoad(12, "fisheye", 0, 100);
  EXPECT_LT(close_only.tracked, 10) << "the start with ORB-SLAM's fill of 100";
}

// Highway fisheye seed 11 frames 0-30: ~760 keypoints per frame, and the keyframes left 62-68 close left-right
// matches without a map point. Under ORB-SLAM's count of 70 the close rule did not fire, the next keyframe came 3
// frames later, and the pose before it rested on far points: the shortest step 0.645 of the true one (25
// keyframes). As a share of the keypoints (7 %) the rule makes a keyframe while the near points run out: 0.934
// (31 keyframes); the path 0.991 -> 0.996 of the true one.
TEST(StereoKeyframes, FisheyeRoadStepsKeepTheirLength) {
  const RoadRun run = trackRoad(31, "fisheye", 11);
  ASSERT_EQ(run.tracked, 31);
  ASSERT_GT(run.path_true, 25.0);
  EXPECT_GT(run.min_step_ratio, 0.8) << run.keyframes << " keyframes over frames 0-30";
  EXPECT_NEAR(run.path_est / run.path_true, 1.0, 0.02);
}

// The first step after the one-frame start rests on a brute-force PnP against the first map, on the fisheye highway
// mostly its far points (seed 0: 21 inliers of 172 map points), whose motion comes out short (0.24 m of 1.06 m).
// Searched from that pose only, the step was 0.13 (seed 0) / 0.51 (seed 11) of the true one, and the metric map
// kept that scale for the whole run. The PnP's motion lengthened 2x and 4x competes: the first steps are metric.
TEST(StereoKeyframes, FisheyeRoadFirstStepsAreMetric) {
  for (const uint64_t seed : {0u, 11u}) {
    const RoadRun run = trackRoad(6, "fisheye", seed);
    ASSERT_EQ(run.tracked, 6) << "seed " << seed;
    ASSERT_GT(run.path_true, 4.0);
    EXPECT_NEAR(run.path_est / run.path_true, 1.0, 0.1) << "stereo path / true path over frames 0-5, seed " << seed;
  }
}

// The metric scale's observability (MetricScaleMonitor): the fisheye pair (0.10 m, 191 px) measures depth within
// 9.6 m. On the clean highway 16-72 pose inliers per frame lie that near; at night (gain ~5, the worn road's
// texture under the noise) 0-18, and the stereo path of the whole run came out 1.43x too short (iraf_vo_simulate
// --preset night --motion highway --camera fisheye --stereo). The night run is reported weakly observed from the
// first full window (frame 10) and keeps its pose (TRACKING); the clean one never.
namespace {
// The night road through a TrackingSession (what the tracker nodelet runs): its weak-scale messages and counters.
struct SessionRoad {
  int tracked = 0, warnings = 0, infos = 0;
  SessionCounters counters;
};
SessionRoad sessionRoad(int frames, const std::string& light) {
  SessionRoad out;
  const Road road = makeRoad(frames, "fisheye", 0, light);
  if (!road.ok()) return out;
  const PipelineParams& pp = road.pp;
  FrontEnd left_front(pp.enhance, pp.features, true), right_front(pp.enhance, pp.features, true);
  TrackingSession session(road.rig, pp.tracker, SessionOptions());
  renderRoad(road, [&](const SimFrame& f) {
    const FeatureFrame l = left_front.process(f.image, f.stamp_ns * 1e-9);
    const FeatureFrame r = right_front.process(f.right_image, f.stamp_ns * 1e-9);
    const SessionStep st = session.process(f.stamp_ns, &l, &r);
    out.tracked += st.has_pose;
    for (const SessionMessage& msg : st.messages) {
      out.warnings += msg.key == "scale_weak" && msg.level == SessionMessage::Level::kWarn;
      out.infos += msg.key == "scale_ok" && msg.level == SessionMessage::Level::kInfo;
    }
    out.counters = st.counters;
  });
  return out;
}
}  // namespace

TEST(StereoKeyframes, WeakMetricScaleIsReportedOnTheNightRoad) {
  const RoadRun night = trackRoad(16, "fisheye", 0, -1, "night");
  ASSERT_EQ(night.tracked, 16);
  EXPECT_GE(night.weak_scale_frames, 4) << "close inliers averaged over frames 0-9 .. 6-15";
  EXPECT_GE(night.weak_scale_changes, 1);
  const RoadRun clean = trackRoad(16, "fisheye", 0);
  ASSERT_EQ(clean.tracked, 16);
  EXPECT_EQ(clean.weak_scale_frames, 0);
  EXPECT_EQ(clean.weak_scale_changes, 0);
}

// The same through the session the tracker nodelet runs: one WARN when the scale becomes weak (ROS_WARN there), the
// counters /diagnostics reports from; none on the clean road.
TEST(StereoKeyframes, WeakMetricScaleReachesTheSession) {
  const SessionRoad night = sessionRoad(16, "night");
  ASSERT_EQ(night.tracked, 16);
  EXPECT_GE(night.warnings, 1);
  EXPECT_GE(night.counters.weak_scale_frames, 1);
  EXPECT_EQ(night.counters.metric_scale_weak, night.warnings > night.infos);
  EXPECT_GE(night.counters.close_inliers_mean, 0.0);
  const SessionRoad clean = sessionRoad(16, "clean");
  ASSERT_EQ(clean.tracked, 16);
  EXPECT_EQ(clean.warnings, 0);
  EXPECT_EQ(clean.counters.weak_scale_frames, 0);
  EXPECT_FALSE(clean.counters.metric_scale_weak);
  EXPECT_GT(clean.counters.close_inliers_mean, 15.0);
}
