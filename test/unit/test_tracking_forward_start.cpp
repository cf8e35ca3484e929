// Monocular start on forward driving: the simulated highway (structure mostly tens to hundreds of metres away)
// and street drive start within 5 frames of motion; a camera standing still on the highway does not start.
// Frames rendered in-process with the runner's resolution rule for the camera; mapping synchronous.
#include <gtest/gtest.h>
#include <iraf_vo/enhance/enhancer.h>
#include <iraf_vo/features/feature_extractor.h>
#include <iraf_vo/features/image_signal.h>
#include <iraf_vo/pipeline/pipeline_params.h>
#include <iraf_vo/sim/light_profile.h>
#include <iraf_vo/sim/motion_preset.h>
#include <iraf_vo/sim/photometric.h>
#include <iraf_vo/sim/renderer.h>
#include <iraf_vo/sim/scene_presets.h>
#include <iraf_vo/sim/sequence.h>
#include <iraf_vo/tracking/tracker.h>
#include <iraf_vo/tracking/two_view.h>

#include "unit/tracking_test_utils.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <string>
#include <vector>

using namespace iraf_vo;

namespace {

struct StartResult {
  int first_tracked = -1;             // first frame reported TRACKING (-1: none)
  std::vector<std::string> failures;  // per frame before it: why the initialization failed
  int initialized_at = -1;            // frame of the (first) initialization
  int not_tracked_after = 0;          // frames after the first TRACKING one not reported TRACKING
  double first_span_over_depth = -1;  // at the first TRACKING frame: keyframe span / median point depth
  Eigen::Vector3d first_centre = Eigen::Vector3d::Zero();  // the camera centre then, in the first keyframe's frame
  int first_keyframe = -1;            // the frame the first keyframe was made from
};

// The largest distance of a keyframe centre from the first keyframe's over the median depth of the map points in
// the camera T_c_w.
double keyframeSpanOverDepth(const Tracker& tracker, const Eigen::Isometry3d& T_c_w) {
  const std::vector<KeyframePose> kfs = tracker.keyframePoses();
  double span = 0.0;
  for (const KeyframePose& k : kfs) span = std::max(span, (k.T_w_c.translation() - kfs.front().T_w_c.translation()).norm());
  std::vector<double> z;
  for (const Eigen::Vector3d& p : tracker.mapPoints())
    if ((T_c_w * p).z() > 0) z.push_back((T_c_w * p).z());
  if (z.empty()) return 0.0;
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return span / z[z.size() / 2];
}

// Renders `frames` frames of the motion (motion blur off: the test's speed) and tracks them. `camera` replaces the
// motion's own camera when given; `as_simulator` renders the first frames of iraf_vo_simulate's sequence (the scene
// of the motion's whole length, its motion blur).
// min_map_baseline: tracker.init_min_map_baseline (the other tracker settings as the resolution rule gives them);
// snr > 0: every frame's image signal as measured (image_signal.h) but with this SNR (else not measured, as a bare
// extractor gives).
StartResult runStart(MotionKind motion, uint64_t seed, int frames, double static_start_s = 0.0,
                     const std::string& camera = "", bool as_simulator = false, double min_map_baseline = 0.0,
                     double snr = 0.0, int init_min_matches = 0) {
  const MotionPreset mp = motionPreset(motion);
  SimParams sim;
  sim.camera = camera.empty() ? mp.camera : camera;
  sim.rate_hz = mp.rate_hz;
  sim.frames = frames;
  sim.brightness = mp.brightness;
  sim.exposure_time_s = mp.exposure_time_s;
  sim.threads = 1;
  sim.seed = seed;
  if (as_simulator) sim.motion_blur_samples = mp.motion_blur_samples;
  TrajectoryParams traj = mp.traj;
  traj.static_start_s = static_start_s;
  std::string err;
  CameraModelPtr cam = makeSimCamera(sim.camera, 0, 0, &err);
  EXPECT_TRUE(cam) << err;
  StartResult res;
  if (!cam) return res;
  SceneParams sp;
  sp.texels_per_m = mp.texels_per_m;
  sp.seed = seed;
  if (!as_simulator) sp.photo_dir.clear();
  auto scene = std::make_shared<const Scene>(makeMotionScene(
      sp, traj, as_simulator ? (mp.frames - 1) / sim.rate_hz + sim.exposure_time_s : frames / sim.rate_hz));
  Renderer renderer(cam, scene, sim);
  PhotometricParams photometric;
  EXPECT_TRUE(photometricPreset("clean", sim.frames, false, sim.seed, &photometric));
  LightProfile light;  // as_simulator: the camera model's auto-exposure and sensor, as iraf_vo_simulate renders
  EXPECT_TRUE(lightProfile("clean", mp.frames, sim.rate_hz, sim.exposure_time_s, false, sim.seed, &light));

  PipelineParams pp;
  applyResolutionRule(*cam, &pp);
  pp.tracker.mapping_thread = false;
  pp.tracker.init_min_map_baseline = min_map_baseline;
  if (init_min_matches > 0) pp.tracker.init_min_matches = init_min_matches;
  Enhancer enhancer;
  FeatureExtractor extractor;
  Tracker tracker(cam, pp.tracker);
  int index = 0;
  SimulateReport rep;
  double first_stamp = -1.0;
  const auto on_frame = [&](const SimFrame& f) {
        if (first_stamp < 0.0) first_stamp = f.stamp_ns * 1e-9;
        const EnhanceResult er = enhancer.enhance(f.image, pp.enhance);
        FeatureFrame ff = extractor.extract(er.image, f.stamp_ns * 1e-9, pp.features);
        if (snr > 0.0) {  // the image's own estimate, with the SNR replaced
          ff.signal = measureImageSignal(f.image);
          ff.signal.snr = snr;
        }
        const TrackResult r = tracker.track(ff);
        if (r.initialized_now && res.initialized_at < 0) res.initialized_at = index;
        if (res.first_tracked >= 0 && r.state != TrackingState::kTracking) ++res.not_tracked_after;
        if (res.first_tracked < 0) {
          if (r.state == TrackingState::kTracking) {
            res.first_tracked = index;
            res.first_span_over_depth = keyframeSpanOverDepth(tracker, r.T_w_c.inverse());
            const std::vector<KeyframePose> kfs = tracker.keyframePoses();
            if (!kfs.empty()) {
              res.first_centre = kfs.front().T_w_c.inverse() * r.T_w_c.translation();
              res.first_keyframe = static_cast<int>(std::lround((kfs.front().stamp - first_stamp) * sim.rate_hz));
            }
          } else {
            res.failures.push_back(r.init_status);
          }
        }
        ++index;
  };
  const bool rendered = as_simulator ? simulateSequence(renderer, traj, light, "", on_frame, &rep, &err)
                                     : simulateSequence(renderer, traj, photometric, "", on_frame, &rep, &err);
  EXPECT_TRUE(rendered) << err;
  tracker.waitForMapping();
  return res;
}

// Two views of a highway by a KITTI-like camera (1241x376, f 719): 85 % of the points 30-300 m ahead (trees,
// buildings), 15 % on the road 6-20 m ahead; keypoint noise 0.5 px. T2_c_w: the second camera.
void highwayViews(const CameraModel& cam, const Eigen::Isometry3d& T2_c_w, unsigned seed,
                  std::vector<Eigen::Vector3d>* b1, std::vector<Eigen::Vector3d>* b2) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1), far(30, 300), near(6, 20);
  std::normal_distribution<double> nd(0.0, 0.5);
  while (b1->size() < 300) {
    Eigen::Vector3d X;
    if (u01(rng) < 0.85) {
      const double z = far(rng);
      X = Eigen::Vector3d((u01(rng) * 2 - 1) * 0.8 * z, 1.6 - u01(rng) * 0.1 * z, z);
    } else {
      X = Eigen::Vector3d(u01(rng) * 14 - 7, 1.65, near(rng));  // road (y down)
    }
    Eigen::Vector2d u1, u2;
    const Eigen::Vector3d X2 = T2_c_w * X;
    if (!cam.project(X, &u1) || !cam.project(X2, &u2) || X2.z() < 1.0) continue;
    if (u1.x() < 0 || u1.y() < 0 || u1.x() >= cam.width() || u1.y() >= cam.height()) continue;
    if (u2.x() < 0 || u2.y() < 0 || u2.x() >= cam.width() || u2.y() >= cam.height()) continue;
    Eigen::Vector3d a, b;
    if (!cam.unproject(u1 + Eigen::Vector2d(nd(rng), nd(rng)), &a) ||
        !cam.unproject(u2 + Eigen::Vector2d(nd(rng), nd(rng)), &b))
      continue;
    b1->push_back(a);
    b2->push_back(b);
  }
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += "\n  frame " + std::to_string(i) + ": " + v[i];
  return s;
}

}  // namespace

// Without the few-parallax-points rule (init_determined_parallax_points 0) the highway's seed 11 is refused with
// "parallax too low" on every try up to frame 10 (first pose at frame 11).
TEST(TrackingForwardStart, HighwayStartsWithinFiveFrames) {
  for (uint64_t seed : {0, 11}) {
    const StartResult r = runStart(MotionKind::kHighway, seed, 6);
    EXPECT_GE(r.first_tracked, 1) << "seed " << seed;
    EXPECT_LE(r.first_tracked, 5) << "seed " << seed << join(r.failures);
  }
}

// The fisheye (512x512, f 191) on the highway: a car's 1 m per frame carries the matches out of the view quickly
// (seed 0: 161 -> 116 -> 81 matches to frame 0); it starts at frame 1.
TEST(TrackingForwardStart, HighwayFisheyeStartsWithinFiveFrames) {
  const StartResult r = runStart(MotionKind::kHighway, 0, 7, 0.0, "fisheye", true);
  EXPECT_GE(r.first_tracked, 1) << join(r.failures);
  EXPECT_LE(r.first_tracked, 5) << join(r.failures);
}

// A reference replaced because its matches fell below init_min_matches stays a candidate while it keeps enough
// matches for an initial map. With init_min_matches 180 above the fisheye highway's 154-177 matches between
// consecutive frames, every frame replaces the reference: frame 4 starts from frame 2, the replaced one (without
// the candidate: no start within 8 frames).
TEST(TrackingForwardStart, ReplacedReferenceStaysACandidate) {
  const StartResult r = runStart(MotionKind::kHighway, 0, 8, 0.0, "fisheye", true, 0.0, 0.0, 180);
  ASSERT_GE(r.initialized_at, 1) << join(r.failures);
  EXPECT_LE(r.initialized_at, 5) << join(r.failures);
  EXPECT_LT(r.first_keyframe, r.initialized_at - 1) << join(r.failures);
}

TEST(TrackingForwardStart, DriveStartsWithinFiveFrames) {
  for (uint64_t seed : {0, 11}) {
    const StartResult r = runStart(MotionKind::kDrive, seed, 6);
    EXPECT_GE(r.first_tracked, 1) << "seed " << seed;
    EXPECT_LE(r.first_tracked, 5) << "seed " << seed << join(r.failures);
  }
}

// Standing still on the highway (only sensor noise between the frames): no start.
TEST(TrackingForwardStart, HighwayStandingStillDoesNotStart) {
  const StartResult r = runStart(MotionKind::kHighway, 0, 8, 10.0);
  EXPECT_EQ(r.first_tracked, -1) << join(r.failures);
  ASSERT_EQ(r.failures.size(), 8u);
  for (size_t i = 1; i < r.failures.size(); ++i) EXPECT_FALSE(r.failures[i].empty()) << "frame " << i;
}

// 1 m forward past far structure: only the road points have parallax (the 50th best point < 1 deg, median ~0.1
// deg). The translation is determined (profile chi2 far above init_determined_min_chi2): the few-points rule
// accepts the true motion; the strict rule alone refuses.
TEST(TrackingForwardStart, TwoViewForwardPastFarStructure) {
  test::TestPinhole cam(1241, 376, 719.0, 607.0, 185.0);
  const Eigen::Isometry3d T2 = test::makePose({0.0, 0.3, 0.0}, {0.0, 0.0, -1.0});
  int accepted = 0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::vector<Eigen::Vector3d> b1, b2;
    highwayViews(cam, T2, seed, &b1, &b2);
    const TwoViewResult r = initializeTwoView(b1, b2, cam.focal(), TwoViewParams());
    if (r.ok) {
      ++accepted;
      EXPECT_TRUE(r.few_parallax_points) << "seed " << seed;
      const double tdir = std::acos(std::clamp(r.t_21.dot(T2.translation().normalized()), -1.0, 1.0)) * 180 / M_PI;
      EXPECT_LT(tdir, 10.0) << "seed " << seed;
      EXPECT_LT(test::rotationErrorDeg(r.R_21, T2.rotation()), 0.2) << "seed " << seed;
    }
    TwoViewParams strict;
    strict.determined_parallax_points = 0;
    const TwoViewResult s = initializeTwoView(b1, b2, cam.focal(), strict);
    EXPECT_FALSE(s.ok) << "seed " << seed;
  }
  EXPECT_GE(accepted, 4);
}

// The same structure seen by a camera that only turns (a slow pan, a quick one) or stands still: refused. Without
// the pure-rotation test (max_rotation_inlier_ratio 1) 5 of the 15 pass as homographies: the road plane's
// decomposition gives a spurious 1.3-2.1 deg of parallax.
TEST(TrackingForwardStart, TwoViewRefusesRotationAndStillPastFarStructure) {
  test::TestPinhole cam(1241, 376, 719.0, 607.0, 185.0);
  for (const Eigen::Vector3d& rpy : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0.6, 0.0),
                                     Eigen::Vector3d(0.3, 3.0, 0.2)}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      std::vector<Eigen::Vector3d> b1, b2;
      highwayViews(cam, test::makePose(rpy, Eigen::Vector3d::Zero()), seed, &b1, &b2);
      const TwoViewResult r = initializeTwoView(b1, b2, cam.focal(), TwoViewParams());
      EXPECT_FALSE(r.ok) << "rotation " << rpy.transpose() << " seed " << seed << ": " << r.model;
    }
  }
}

// init_min_map_baseline: the drive's map starts at frame 1 from a baseline of ~8 % of the median depth; with 0.15 and
// images reported at SNR 4 (below init_min_map_baseline_snr 8) the young map is tracked and mapped but its frames are
// reported INITIALIZING until the keyframes span 15 % of the depth, then every frame is TRACKING (without the rule the
// first pose is the initialization's, at ~8 %).
TEST(TrackingForwardStart, YoungMapReportedOnceItsKeyframesSpanTheMinimumBaseline) {
  const StartResult r = runStart(MotionKind::kDrive, 0, 12, 0.0, "", false, 0.15, 4.0);
  ASSERT_GE(r.initialized_at, 0) << join(r.failures);
  ASSERT_GE(r.first_tracked, 0) << join(r.failures);
  EXPECT_GT(r.first_tracked, r.initialized_at);
  EXPECT_GE(r.first_span_over_depth, 0.15);
  EXPECT_EQ(r.not_tracked_after, 0);
}

// The same start on images at SNR 30 (clean, above init_min_map_baseline_snr): the rule does not apply, the first pose
// is the initialization's.
TEST(TrackingForwardStart, YoungMapOfACleanStartReportedAtOnce) {
  const StartResult r = runStart(MotionKind::kDrive, 0, 12, 0.0, "", false, 0.15, 30.0);
  ASSERT_GE(r.initialized_at, 0) << join(r.failures);
  EXPECT_EQ(r.first_tracked, r.initialized_at);
  EXPECT_LT(r.first_span_over_depth, 0.15);
}

// Starts on the simulated highway whose two-view geometry has a road homography scoring below the essential matrix
// (R_H < 0.45) while the essential matrix's motion has too little parallax for the strict test: the homography is
// tried and one decomposition of its pair carries the camera vertically or sideways with a spurious parallax of
// 1.7-6.9 deg (KITTI camera seed 2, EuRoC pinhole seed 2, fisheye seed 3 before that decomposition was refused: the
// first pose 45-83 deg off the road). The first pose now moves along the optical axis, as the car does.
TEST(TrackingForwardStart, HighwayStartMovesAlongTheRoad) {
  const std::vector<std::pair<std::string, uint64_t>> starts = {{"kitti", 2}, {"pinhole", 2}, {"fisheye", 3}};
  for (const auto& [camera, seed] : starts) {
    const StartResult r = runStart(MotionKind::kHighway, seed, 6, 0.0, camera, true);
    ASSERT_GE(r.first_tracked, 1) << camera << " seed " << seed << join(r.failures);
    EXPECT_LE(r.first_tracked, 5) << camera << " seed " << seed << join(r.failures);
    ASSERT_GT(r.first_centre.norm(), 0.0) << camera << " seed " << seed;
    const double off_axis = std::acos(std::clamp(r.first_centre.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI;
    EXPECT_LT(off_axis, 20.0) << camera << " seed " << seed << ": first camera centre " << r.first_centre.transpose();
  }
}
