// Simulator motion presets: the ground truth of each motion has the stated properties (speed and rotation per
// frame, lateral-only slider, zero motion during a static start), and each preset's camera / rate.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <stdexcept>
#include <vector>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/sim/motion_preset.h"
#include "iraf_vo/sim/scene_presets.h"
#include "iraf_vo/sim/sequence.h"
#include "iraf_vo/sim/trajectory.h"

namespace {

using iraf_vo::MotionKind;
using iraf_vo::MotionPreset;
using iraf_vo::TrajectoryParams;

double rotDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

std::vector<Eigen::Isometry3d> groundTruth(const MotionPreset& p, int frames = -1) {
  std::vector<Eigen::Isometry3d> poses;
  const int n = frames > 0 ? frames : p.frames;
  for (int i = 0; i < n; ++i) poses.push_back(iraf_vo::trajectoryPose(p.traj, i / p.rate_hz));
  return poses;
}

iraf_vo::CameraModelPtr presetCamera(const MotionPreset& p) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera(p.camera, 0, 0, &err);
  EXPECT_TRUE(cam) << err;
  return cam;
}

TEST(SimMotion, PresetCamerasAndRates) {
  const MotionPreset drive = iraf_vo::motionPreset(MotionKind::kDrive);
  auto cam = presetCamera(drive);
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->width(), 1241);
  EXPECT_EQ(cam->height(), 376);
  EXPECT_NEAR(cam->parameters()[0], 718.0, 5.0) << "KITTI-like focal length";
  EXPECT_DOUBLE_EQ(drive.rate_hz, 10.0);

  const MotionPreset slider = iraf_vo::motionPreset(MotionKind::kSlider);
  cam = presetCamera(slider);
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->width(), 240);
  EXPECT_EQ(cam->height(), 180);
  EXPECT_NEAR(cam->parameters()[0], 200.0, 20.0);
  const double k1 = cam->parameters()[4];
  EXPECT_LT(k1, 0.0) << "mild barrel distortion";
  EXPECT_GT(k1, -0.2);
  EXPECT_DOUBLE_EQ(slider.rate_hz, 25.0);

  const MotionPreset hand = iraf_vo::motionPreset(MotionKind::kHandheldFast);
  cam = presetCamera(hand);
  ASSERT_TRUE(cam);
  EXPECT_EQ(cam->width(), 752);
  EXPECT_EQ(cam->height(), 480);
  EXPECT_DOUBLE_EQ(hand.rate_hz, 20.0);
  EXPECT_GT(hand.motion_blur_samples, 1) << "hand-held fast motion is rendered with motion blur";
  std::string err;
  auto fisheye = iraf_vo::makeSimCamera("fisheye", 0, 0, &err);
  ASSERT_TRUE(fisheye) << err;
  EXPECT_EQ(fisheye->modelName(), "kannala-brandt");
}

TEST(SimMotion, DriveForwardAboutOneMetrePerFrameWithGentleTurns) {
  const MotionPreset p = iraf_vo::motionPreset(MotionKind::kDrive);
  const auto gt = groundTruth(p);
  double path = 0, max_rot = 0, min_yaw = 1e9, max_yaw = -1e9;
  for (size_t i = 0; i + 1 < gt.size(); ++i) {
    const Eigen::Vector3d d = gt[i + 1].translation() - gt[i].translation();
    EXPECT_GT(d.norm(), 0.85) << "frame " << i;
    EXPECT_LT(d.norm(), 1.15) << "frame " << i;
    path += d.norm();
    // Forward: the motion is along the optical axis (z) within 15 deg.
    const Eigen::Vector3d d_C = gt[i].linear().transpose() * d;
    EXPECT_GT(d_C.z() / d.norm(), std::cos(15.0 * M_PI / 180.0)) << "frame " << i;
    max_rot = std::max(max_rot, rotDeg(gt[i], gt[i + 1]));
    const Eigen::Vector3d fwd = gt[i].linear().col(2);
    const double yaw = std::atan2(fwd.y(), fwd.x()) * 180.0 / M_PI;
    min_yaw = std::min(min_yaw, yaw), max_yaw = std::max(max_yaw, yaw);
    EXPECT_NEAR(gt[i].translation().z(), 1.65, 0.05) << "camera height";
  }
  EXPECT_GT(path, 50.0);
  EXPECT_LT(path, 120.0);
  EXPECT_LT(max_rot, 2.0) << "gentle turns";
  EXPECT_GT(max_yaw - min_yaw, 8.0) << "the street turns";
  EXPECT_LT(max_yaw - min_yaw, 40.0);
}

TEST(SimMotion, SliderIsPureLateralTranslation) {
  const MotionPreset p = iraf_vo::motionPreset(MotionKind::kSlider);
  const auto gt = groundTruth(p);
  double travel = 0;
  for (size_t i = 0; i + 1 < gt.size(); ++i) {
    EXPECT_LT(rotDeg(gt[0], gt[i + 1]), 1e-9) << "attitude constant, frame " << i;
    const Eigen::Vector3d d_C = gt[i].linear().transpose() * (gt[i + 1].translation() - gt[i].translation());
    EXPECT_LT(std::abs(d_C.y()) + std::abs(d_C.z()), 1e-9) << "only along the camera x axis, frame " << i;
    EXPECT_NEAR(std::abs(d_C.x()), p.traj.slider_speed_mps / p.rate_hz, 1e-9) << "constant speed, frame " << i;
    travel += std::abs(d_C.x());
  }
  EXPECT_NEAR(travel, 1.0, 0.02) << "1 m of travel in the default sequence";
  // Beyond one pass the slider comes back (stays within the travel).
  const auto longer = groundTruth(p, 3 * p.frames);
  for (const auto& T : longer) EXPECT_LE(std::abs(T.translation().x()), p.traj.slider_travel_m / 2 + 1e-9);
}

TEST(SimMotion, HandheldFastRotatesUpToThreeDegreesPerFrame) {
  const MotionPreset p = iraf_vo::motionPreset(MotionKind::kHandheldFast);
  const auto gt = groundTruth(p, 400);
  double max_rot = 0, sum = 0;
  for (size_t i = 0; i + 1 < gt.size(); ++i) {
    const double r = rotDeg(gt[i], gt[i + 1]);
    max_rot = std::max(max_rot, r), sum += r;
  }
  EXPECT_LE(max_rot, 3.0);
  EXPECT_GT(max_rot, 2.4) << "fast: close to the 3 deg/frame bound";
  EXPECT_GT(sum / (gt.size() - 1), 1.0) << "fast on average, not only at one peak";
  const MotionPreset room = iraf_vo::motionPreset(MotionKind::kRoom);
  const auto slow = groundTruth(room, 400);
  double max_slow = 0;
  for (size_t i = 0; i + 1 < slow.size(); ++i) max_slow = std::max(max_slow, rotDeg(slow[i], slow[i + 1]));
  EXPECT_LT(max_slow, 0.6 * max_rot) << "handheld_fast rotates much faster than the room loop";
}

TEST(SimMotion, StaticStartHoldsStillThenAcceleratesSmoothly) {
  for (MotionKind m : {MotionKind::kRoom, MotionKind::kDrive, MotionKind::kSlider, MotionKind::kHandheldFast,
                       MotionKind::kHighway}) {
    MotionPreset p = iraf_vo::motionPreset(m);
    p.traj.static_start_s = 2.0;
    const int still = static_cast<int>(2.0 * p.rate_hz);  // frames 0..still are at the pose of t = 0
    const auto gt = groundTruth(p, still + static_cast<int>(3 * p.rate_hz));
    for (int i = 1; i <= still; ++i) {
      EXPECT_EQ((gt[i].matrix() - gt[0].matrix()).norm(), 0.0) << iraf_vo::toString(m) << " frame " << i;
    }
    // Moving afterwards; the first steps are small (acceleration), the speed is reached after the ramp.
    const double first = (gt[still + 1].translation() - gt[still].translation()).norm();
    const double later = (gt.back().translation() - gt[gt.size() - 2].translation()).norm();
    EXPECT_GT(first, 0.0) << iraf_vo::toString(m);
    EXPECT_LT(first, 0.2 * later) << iraf_vo::toString(m) << ": no velocity jump at the start";
    // The same motion as without the static start, shifted by static_start + ramp / 2.
    MotionPreset q = iraf_vo::motionPreset(m);
    const double t = gt.size() / p.rate_hz;
    const Eigen::Isometry3d a = iraf_vo::trajectoryPose(p.traj, t);
    const Eigen::Isometry3d b = iraf_vo::trajectoryPose(q.traj, t - 2.0 - 0.5 * p.traj.start_ramp_s);
    EXPECT_LT((a.matrix() - b.matrix()).norm(), 1e-9) << iraf_vo::toString(m);
  }
}

TEST(SimMotion, NamesAndBadParameters) {
  for (MotionKind m : {MotionKind::kRoom, MotionKind::kDrive, MotionKind::kSlider, MotionKind::kHandheldFast,
                       MotionKind::kHighway}) {
    MotionKind back;
    ASSERT_TRUE(iraf_vo::parseMotionKind(iraf_vo::toString(m), &back));
    EXPECT_EQ(back, m);
    EXPECT_NE(iraf_vo::motionKindNames().find(iraf_vo::toString(m)), std::string::npos);
  }
  MotionKind k;
  EXPECT_FALSE(iraf_vo::parseMotionKind("walk", &k));
  TrajectoryParams t;
  EXPECT_EQ(iraf_vo::validate(t), "");
  t.static_start_s = -1;
  EXPECT_NE(iraf_vo::validate(t).find("static_start_s"), std::string::npos);
  t = TrajectoryParams();
  t.slider_travel_m = 0;
  EXPECT_NE(iraf_vo::validate(t).find("slider_travel_m"), std::string::npos);
  t = TrajectoryParams();
  t.slider_travel_m = 5;
  iraf_vo::SceneParams sp;
  sp.texels_per_m = 32;
  try {
    iraf_vo::makeSliderScene(sp, t);
    ADD_FAILURE() << "a 5 m slider travel must be rejected";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("slider_travel_m"), std::string::npos) << e.what();
  }
}

TEST(SimMotion, DrivePathIsArcLengthParameterized) {
  const TrajectoryParams t = iraf_vo::motionPreset(MotionKind::kDrive).traj;
  double len = 0;
  Eigen::Vector2d prev = iraf_vo::drivePath(t, 0.0);
  EXPECT_LT(prev.norm(), 1e-12);
  for (int i = 1; i <= 200; ++i) {
    const Eigen::Vector2d p = iraf_vo::drivePath(t, 0.5 * i);
    len += (p - prev).norm();
    prev = p;
  }
  EXPECT_NEAR(len, 100.0, 0.05);
}

#include "common/tmp_dir.h"

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::vector<std::string> dataLines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(f, line);)
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}

TEST(SimMotion, ToolWritesTheMotionsCameraRateAndStaticStart) {
  const std::string bin = IRAF_VO_BIN_DIR;
  if (!std::filesystem::exists(bin + "/iraf_vo_simulate")) GTEST_SKIP() << "iraf_vo_simulate not built in " << bin;
  const std::string out = tmpRoot() + "sim_motion_slider";
  std::filesystem::remove_all(out);
  ASSERT_EQ(run(bin + "/iraf_vo_simulate --preset clean --motion slider --frames 6 --static-start 0.1 --no-photos --out " +
                out), 0);
  // The calibration iraf_vo_run --dataset reads: the slider's camera.
  std::string err;
  auto cam = iraf_vo::loadCamera(out + "/mav0/cam0/sensor.yaml", &err);
  ASSERT_TRUE(cam) << err;
  EXPECT_EQ(cam->width(), 240);
  EXPECT_EQ(cam->height(), 180);
  EXPECT_DOUBLE_EQ(cam->parameters()[4], -0.1);
  const auto rows = dataLines(out + "/mav0/cam0/data.csv");
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(std::stoll(rows[1]) - std::stoll(rows[0]), 40000000LL) << "25 Hz";
  // Static for 0.1 s: frames 0-2 (t = 0, 0.04, 0.08) at the same pose, frame 5 moved.
  iraf_vo::Trajectory gt;
  ASSERT_TRUE(iraf_vo::readTumTrajectory(out + "/groundtruth.txt", &gt, &err)) << err;
  ASSERT_EQ(gt.size(), 6u);
  EXPECT_EQ((gt.poses[1].matrix() - gt.poses[0].matrix()).norm(), 0.0);
  EXPECT_EQ((gt.poses[2].matrix() - gt.poses[0].matrix()).norm(), 0.0);
  EXPECT_GT((gt.poses[5].translation() - gt.poses[0].translation()).norm(), 1e-4);
  // Bad options: non-zero exit.
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset clean --motion walk --out " + out + "x"), 0);
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset clean --static-start -1 --out " + out + "x"), 0);
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset clean --rate 0 --out " + out + "x"), 0);
}

}  // namespace
