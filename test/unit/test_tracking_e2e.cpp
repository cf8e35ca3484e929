// End to end: images -> Enhancer -> FeatureExtractor -> Tracker (the runner's core loop, mapping synchronous so
// the result is deterministic), on a short simulated sequence and on the first real EuRoC MH_01 frames.
#include <gtest/gtest.h>
#include <iraf_vo/enhance/enhancer.h>
#include <iraf_vo/eval/trajectory_eval.h>
#include <iraf_vo/features/feature_extractor.h>
#include <iraf_vo/io/image_folder.h>
#include <iraf_vo/io/trajectory.h>
#include <iraf_vo/sim/photometric.h>
#include <iraf_vo/sim/renderer.h>
#include <iraf_vo/sim/scene.h>
#include <iraf_vo/sim/sequence.h>
#include <iraf_vo/sim/trajectory.h>
#include <iraf_vo/tracking/tracker.h>

#include <sys/stat.h>

using namespace iraf_vo;

namespace {

struct LoopResult {
  int frames = 0, tracked = 0, first_tracked = -1;
  Trajectory est;
  TrackerStats stats;
};

class Loop {
 public:
  Loop(CameraModelPtr cam, bool iraf) : tracker_(cam, trackerParams()) {
    ep_.method = iraf ? EnhanceMethod::kIraf : EnhanceMethod::kNone;
    fp_.adaptive_threshold = iraf;
    fp_.culling = iraf;
  }
  static TrackerParams trackerParams() {
    TrackerParams p;
    p.mapping_thread = false;  // deterministic
    p.ba_max_num_iterations = 5;  // keeps the test fast
    return p;
  }
  void add(const cv::Mat& gray, double stamp) {
    const EnhanceResult er = enhancer_.enhance(gray, ep_);
    const FeatureFrame f = extractor_.extract(er.image, stamp, fp_);
    const TrackResult r = tracker_.track(f);
    if (r.state == TrackingState::kTracking) {
      if (res_.first_tracked < 0) res_.first_tracked = res_.frames;
      ++res_.tracked;
      res_.est.push_back(stamp, r.T_w_c);
    }
    ++res_.frames;
  }
  LoopResult finish() {
    tracker_.waitForMapping();
    res_.stats = tracker_.stats();
    return res_;
  }

 private:
  EnhanceParams ep_;
  FeatureParams fp_;
  Enhancer enhancer_;
  FeatureExtractor extractor_;
  Tracker tracker_;
  LoopResult res_;
};

double ateSim3(const Trajectory& gt, const Trajectory& est, double* scale = nullptr) {
  EvalParams ev;
  ev.align = AlignMode::kSim3;
  EvalResult r;
  std::string err;
  if (!evaluateTrajectory(gt, est, ev, &r, &err)) {
    ADD_FAILURE() << err;
    return 1e9;
  }
  if (scale) *scale = r.scale;
  return r.ate.rmse;
}

}  // namespace

TEST(TrackingE2E, SimulatedCleanSequence) {
  std::string err;
  SimParams sim;
  sim.frames = 60;
  sim.threads = 1;
  CameraModelPtr cam = makeSimCamera(sim.camera, 0, 0, &err);
  ASSERT_TRUE(cam) << err;
  SceneParams sp;
  sp.photo_dir.clear();  // procedural textures only: no dependency on data files
  auto scene = std::make_shared<const Scene>(Scene::makeDefaultRoom(sp));
  Renderer renderer(cam, scene, sim);
  PhotometricParams photometric;
  ASSERT_TRUE(photometricPreset("clean", sim.frames, false, sim.seed, &photometric));
  TrajectoryParams traj;
  Loop loop(cam, true);
  Trajectory gt;
  SimulateReport rep;
  ASSERT_TRUE(simulateSequence(
      renderer, traj, photometric, "",
      [&](const SimFrame& f) {
        loop.add(f.image, f.stamp_ns * 1e-9);
        gt.push_back(f.stamp_ns * 1e-9, f.T_W_C);
      },
      &rep, &err))
      << err;
  const LoopResult r = loop.finish();
  EXPECT_EQ(r.frames, 60);
  EXPECT_GE(r.first_tracked, 1);
  EXPECT_LE(r.first_tracked, 20);
  EXPECT_GE(r.tracked, 0.85 * r.frames);
  EXPECT_EQ(r.stats.lost_events, 0);
  EXPECT_LT(ateSim3(gt, r.est), 0.03);
}

TEST(TrackingE2E, EurocFirstFrames) {
  const std::string dir = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600";
  struct stat st;
  if (stat(dir.c_str(), &st) != 0) GTEST_SKIP() << "no real data at " << dir;
  AslImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(dir, &err)) << err;
  CameraModelPtr cam = reader.loadCamera(&err);
  ASSERT_TRUE(cam) << err;
  Trajectory gt;
  ASSERT_TRUE(readTumTrajectory(dir + "/groundtruth/groundtruth_tum_cam0.txt", &gt, &err)) << err;
  Loop loop(cam, false);
  const size_t n = std::min<size_t>(70, reader.size());
  for (size_t i = 0; i < n; ++i) {
    cv::Mat gray;
    ASSERT_TRUE(reader.loadImage(i, &gray, &err)) << err;
    loop.add(gray, reader.entries()[i].stamp());
  }
  const LoopResult r = loop.finish();
  EXPECT_GE(r.first_tracked, 1);  // initialization needs two frames
  EXPECT_LE(r.first_tracked, 30);
  EXPECT_GE(r.tracked, 0.85 * r.frames);
  EXPECT_EQ(r.stats.lost_events, 0);
  double scale = 0;
  EXPECT_LT(ateSim3(gt, r.est, &scale), 0.02);  // handheld, ~1.2 m of path in the first 70 frames
  EXPECT_GT(scale, 0.0);
}
