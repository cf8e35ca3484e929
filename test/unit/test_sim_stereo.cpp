// The simulator's stereo rig: a scene point seen by both cameras lands where the rig geometry says (the
// T_BS written to cam1/sensor.yaml; median < 0.25 px, 90 % < 0.5 px, all < 1 px of template matching),
// pinhole and fisheye, parallel and slightly turned rigs; cam1 takes
// cam0's exposure and gain on every frame with its own sensor noise; iraf_vo_degrade degrades cam1 with
// cam0's exposure and independent noise.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/sim/asl_degrade.h"
#include "iraf_vo/sim/image_formation.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/sensor_model.h"
#include "iraf_vo/sim/sequence.h"
#include "iraf_vo/sim/sim_stereo_rig.h"

namespace fs = std::filesystem;

namespace {

#include "common/tmp_dir.h"

std::string freshDir(const std::string& name) {
  const std::string d = tmpRoot() + "stereo_" + name;
  fs::remove_all(d);
  return d;
}

std::shared_ptr<const iraf_vo::Scene> room() {
  iraf_vo::SceneParams sp;
  sp.texels_per_m = 128;
  sp.photo_dir.clear();
  return std::make_shared<const iraf_vo::Scene>(iraf_vo::Scene::makeDefaultRoom(sp));
}

/// Sub-pixel position of `patch` in `image` within `search` (normalised cross-correlation, parabola fit).
/// Returns false when the best match is weak or on the border of the search window.
bool findPatch(const cv::Mat& image, const cv::Mat& patch, const cv::Rect& search, cv::Point2d* centre) {
  const cv::Rect roi = search & cv::Rect(0, 0, image.cols, image.rows);
  if (roi.width <= patch.cols + 2 || roi.height <= patch.rows + 2) return false;
  cv::Mat score;
  cv::matchTemplate(image(roi), patch, score, cv::TM_CCOEFF_NORMED);
  double best;
  cv::Point at;
  cv::minMaxLoc(score, nullptr, &best, nullptr, &at);
  if (best < 0.9 || at.x < 1 || at.y < 1 || at.x >= score.cols - 1 || at.y >= score.rows - 1) return false;
  auto peak = [](float a, float b, float c) { return 0.5 * (a - c) / (a - 2.0 * b + c); };
  const double dx = peak(score.at<float>(at.y, at.x - 1), score.at<float>(at), score.at<float>(at.y, at.x + 1));
  const double dy = peak(score.at<float>(at.y - 1, at.x), score.at<float>(at), score.at<float>(at.y + 1, at.x));
  *centre = cv::Point2d(roi.x + at.x + dx + 0.5 * (patch.cols - 1), roi.y + at.y + dy + 0.5 * (patch.rows - 1));
  return true;
}

/// Simulates 2 stereo frames of the room with `camera` and `rig`, then checks textured left pixels:
/// the ray's hit point, moved into cam1 with the T_BS read back from cam1/sensor.yaml, projects where the
/// patch is found in the right image (noise-free radiance of the same renderers).
void expectRigGeometry(const std::string& camera, const iraf_vo::SimStereoRig& rig, double expect_baseline) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera(camera, 0, 0, &err);
  ASSERT_TRUE(cam) << err;
  auto scene = room();
  iraf_vo::SimParams params;
  params.frames = 2;
  iraf_vo::Renderer left(cam, scene, params), right(cam, scene, params);
  right.setPoseInRig(iraf_vo::rightCameraInLeft(rig, camera));
  iraf_vo::LightProfile light;
  ASSERT_TRUE(iraf_vo::lightProfile("clean", params.frames, params.rate_hz, params.exposure_time_s, false, 1, &light));
  const std::string out = freshDir(camera);
  const iraf_vo::TrajectoryParams traj;
  ASSERT_TRUE(iraf_vo::simulateSequence(left, &right, traj, light, out, nullptr, nullptr, &err)) << err;
  iraf_vo::CameraModelPtr cam0 = iraf_vo::loadCamera(out + "/mav0/cam0/sensor.yaml", &err);
  iraf_vo::CameraModelPtr cam1 = iraf_vo::loadCamera(out + "/mav0/cam1/sensor.yaml", &err);
  ASSERT_TRUE(cam0 && cam1) << err;
  Eigen::Isometry3d T_C0_C1;
  T_C0_C1.matrix() = cam0->T_BS.inverse() * cam1->T_BS;
  EXPECT_NEAR(T_C0_C1.translation().norm(), expect_baseline, 1e-9);
  EXPECT_EQ(fs::directory_iterator(out + "/mav0/cam1/data") == fs::directory_iterator(), false);

  const Eigen::Isometry3d T_W_C0 = iraf_vo::trajectoryPose(traj, left.frameTime(1));
  cv::Mat L, R, Z;
  left.render(T_W_C0, &L, &Z);
  cv::Mat Z2;  // second differences of the depth: 0 on a plane (nearly, over a patch), large at edges
  cv::Laplacian(Z, Z2, CV_32F, 1);
  right.renderFrame(traj, 1, &R);  // the simulator's own right view (no motion blur by default)
  const int half = 10;
  int checked = 0;
  double worst = 0.0;
  std::vector<double> errors;
  for (int v = 3 * L.rows / 10; v <= 7 * L.rows / 10; v += L.rows / 10) {
    for (int u = 2 * L.cols / 10; u <= 7 * L.cols / 10; u += L.cols / 20) {
      const cv::Mat patch = L(cv::Rect(u - half, v - half, 2 * half + 1, 2 * half + 1));
      cv::Scalar mean, sd;
      cv::meanStdDev(patch, mean, sd);
      if (sd[0] < 8.0) continue;  // too little texture to locate
      // Structure in both directions (structure tensor's eigenvalues within 1:4), else the match slides.
      cv::Mat gx, gy;
      cv::Sobel(patch, gx, CV_64F, 1, 0);
      cv::Sobel(patch, gy, CV_64F, 0, 1);
      const double xx = gx.dot(gx), yy = gy.dot(gy), xy = gx.dot(gy);
      const double tr = 0.5 * (xx + yy), det = std::sqrt(0.25 * (xx - yy) * (xx - yy) + xy * xy);
      if (tr - det < 0.25 * (tr + det)) continue;
      double z_lo, kink;
      const cv::Rect box(u - half, v - half, 2 * half + 1, 2 * half + 1);
      cv::minMaxLoc(Z(box), &z_lo);
      cv::minMaxLoc(cv::abs(Z2(box)), nullptr, &kink);
      if (z_lo <= 0.0 || kink > 1e-3 * z_lo) continue;  // a depth edge or a corner: the patch moves in parts
      Eigen::Vector3d p_W;
      double depth;
      if (!left.castPixel(T_W_C0, Eigen::Vector2d(u, v), &p_W, &depth) || depth < 0.5) continue;
      Eigen::Vector2d uv1;
      if (!cam1->project((T_W_C0 * T_C0_C1).inverse() * p_W, &uv1)) continue;
      cv::Point2d found;
      const cv::Rect search(static_cast<int>(uv1.x()) - 3 * half, static_cast<int>(uv1.y()) - 3 * half, 6 * half,
                            6 * half);
      if (!findPatch(R, patch, search, &found)) continue;
      const double e = std::hypot(found.x - uv1.x(), found.y - uv1.y());
      worst = std::max(worst, e);
      errors.push_back(e);
      EXPECT_LT(e, 1.0) << camera << " left (" << u << ", " << v << ") depth " << depth << " m: expected ("
                        << uv1.transpose() << "), found (" << found.x << ", " << found.y << ")";
      ++checked;
    }
  }
  ASSERT_GE(checked, 8) << camera << ": too few textured points to check";
  // Template matching between two views of a slanted surface is itself off by a few tenths of a pixel
  // (the patch is warped); a wrong rig (half a pixel, a wrong sign, mm of baseline) shifts every point.
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], p90 = errors[errors.size() * 9 / 10];
  EXPECT_LT(median, 0.25) << camera;
  EXPECT_LT(p90, 0.5) << camera;
  std::cout << camera << ": " << checked << " points, median " << median << " px, 90 % " << p90 << " px, worst "
            << worst << " px\n";
}

}  // namespace

TEST(SimStereo, PointsLandWhereTheRigSays) {
  expectRigGeometry("pinhole", iraf_vo::SimStereoRig(), 0.110);
  iraf_vo::SimStereoRig turned;  // a rig that is not quite parallel, TUM-VI baseline
  turned.yaw_deg = 1.0, turned.roll_deg = -0.5;
  expectRigGeometry("fisheye", turned, 0.101);
  iraf_vo::SimStereoRig wide;
  wide.baseline_m = 0.25, wide.pitch_deg = 0.5;
  expectRigGeometry("pinhole", wide, 0.25);
  EXPECT_DOUBLE_EQ(iraf_vo::defaultStereoBaseline("fisheye"), 0.101);
  EXPECT_DOUBLE_EQ(iraf_vo::defaultStereoBaseline("kitti"), 0.54);
  EXPECT_FALSE(iraf_vo::validate(turned) != "");
  turned.yaw_deg = 30.0;
  EXPECT_NE(iraf_vo::validate(turned), "");
}

TEST(SimStereo, RightCameraTakesTheLeftExposureWithItsOwnNoise) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera("pinhole", 188, 120, &err);
  ASSERT_TRUE(cam) << err;
  auto scene = room();
  iraf_vo::SimParams params;
  params.frames = 14;
  iraf_vo::Renderer left(cam, scene, params), right(cam, scene, params);
  right.setPoseInRig(iraf_vo::rightCameraInLeft(iraf_vo::SimStereoRig(), "pinhole"));
  iraf_vo::LightProfile light;
  ASSERT_TRUE(iraf_vo::lightProfile("ae_hunting", params.frames, params.rate_hz, params.exposure_time_s, false, 1,
                                    &light));
  double lo = 1e9, hi = 0.0;
  int frames = 0;
  auto check = [&](const iraf_vo::SimFrame& f) {
    ASSERT_FALSE(f.right_image.empty());
    EXPECT_EQ(f.right_light.exposure.time_s, f.light.exposure.time_s) << "frame " << f.index;
    EXPECT_EQ(f.right_light.exposure.gain, f.light.exposure.gain) << "frame " << f.index;
    const double rel = f.light.exposure.relative(light.sensor);
    lo = std::min(lo, rel), hi = std::max(hi, rel);
    // Same exposure, 11 cm apart in a room: the mean grey follows the left's frame by frame.
    EXPECT_NEAR(cv::mean(f.right_image)[0] / cv::mean(f.image)[0], 1.0, 0.1) << "frame " << f.index;
    ++frames;
  };
  ASSERT_TRUE(iraf_vo::simulateSequence(left, &right, iraf_vo::TrajectoryParams(), light, "", check, nullptr, &err))
      << err;
  EXPECT_EQ(frames, params.frames);
  EXPECT_GT(hi / lo, 1.5) << "the hunting auto-exposure must move the exposure for the test to mean anything";

  // Independent noise: the two cameras' images of one flat irradiance differ by 2x the noise variance.
  iraf_vo::ImageFormation f0(light, cam), f1(light, cam, 1);
  const cv::Mat flat(120, 188, CV_32FC1, cv::Scalar(50.0f));
  const iraf_vo::Exposure e{0.01, 2.0};
  cv::Mat a, b, d;
  f0.captureWithExposure(3, e, flat, nullptr, &a);
  f1.captureWithExposure(3, e, flat, nullptr, &b);
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  cv::Scalar m, sd;
  cv::meanStdDev(fa - fb, m, sd);
  const double var1 = iraf_vo::SensorModel(light.sensor).noiseVarianceDn(cv::mean(a)[0], e.gain);
  EXPECT_NEAR(sd[0] * sd[0] / (2.0 * var1), 1.0, 0.15) << "var(a - b) " << sd[0] * sd[0] << ", var " << var1;
}

TEST(SimStereo, DegradeTakesCam1AlongWithTheLeftExposure) {
  // A stereo ASL folder: cam1 images equal to cam0's, cam1 shorter (as EuRoC's right camera stops early).
  const std::string in = freshDir("deg_in"), out = freshDir("deg_out");
  for (const std::string cam : {"cam0", "cam1"}) {
    fs::create_directories(in + "/mav0/" + cam + "/data");
    std::ofstream(in + "/mav0/" + cam + "/sensor.yaml") << "camera_model: pinhole\n";
  }
  std::ofstream c0(in + "/mav0/cam0/data.csv"), c1(in + "/mav0/cam1/data.csv");
  cv::RNG rng(5);
  const int n = 16, n_right = 12;
  for (int i = 0; i < n; ++i) {
    const std::string file = std::to_string(1000000 + i * 50000000LL) + ".png";
    cv::Mat img(60, 80, CV_8UC1);
    rng.fill(img, cv::RNG::UNIFORM, 30, 150);
    cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
    cv::imwrite(in + "/mav0/cam0/data/" + file, img);
    c0 << 1000000 + i * 50000000LL << "," << file << "\n";
    if (i >= n_right) continue;
    cv::imwrite(in + "/mav0/cam1/data/" + file, img);
    c1 << 1000000 + i * 50000000LL + 1000 << "," << file << "\n";  // 1 us later: paired by the nearest time
  }
  c0.close(), c1.close();
  iraf_vo::LightProfile light;
  ASSERT_TRUE(iraf_vo::lightProfile("ae_hunting", n, 20.0, 0.01, true, 1, &light));
  iraf_vo::DegradeReport rep;
  std::string err;
  ASSERT_TRUE(iraf_vo::degradeAslSequence(in, out, light, &rep, &err)) << err;
  EXPECT_EQ(rep.written, n);
  EXPECT_EQ(rep.right_images, n_right);
  EXPECT_EQ(rep.right_written, n_right);
  EXPECT_TRUE(fs::exists(out + "/mav0/cam1/sensor.yaml"));
  double lo = 1e9, hi = 0.0;
  for (int i = 0; i < n_right; ++i) {
    const std::string file = std::to_string(1000000 + i * 50000000LL) + ".png";
    const cv::Mat src = cv::imread(in + "/mav0/cam1/data/" + file, cv::IMREAD_GRAYSCALE);
    const cv::Mat a = cv::imread(out + "/mav0/cam0/data/" + file, cv::IMREAD_GRAYSCALE);
    const cv::Mat b = cv::imread(out + "/mav0/cam1/data/" + file, cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(a.empty() || b.empty()) << file;
    lo = std::min(lo, cv::mean(a)[0]), hi = std::max(hi, cv::mean(a)[0]);
    // Same input, same exposure: the same brightness; not the input any more; not cam0's noise.
    EXPECT_NEAR(cv::mean(b)[0], cv::mean(a)[0], 1.0) << "frame " << i;
    EXPECT_GT(cv::norm(b, src, cv::NORM_L1) / b.total(), 1.0) << "frame " << i;
    EXPECT_GT(cv::countNonZero(a != b), static_cast<int>(a.total() / 4)) << "frame " << i;
  }
  EXPECT_GT(hi - lo, 10.0) << "the hunting auto-exposure must move the grey for the test to mean anything";
}

TEST(SimStereo, SimulateCommandLine) {
  const std::string bin = IRAF_VO_BIN_DIR;
  if (!fs::exists(bin + "/iraf_vo_simulate")) GTEST_SKIP() << "iraf_vo_simulate not built";
  const std::string out = freshDir("cli");
  auto run = [](const std::string& cmd) {
    const int rc = std::system((cmd + " > /dev/null 2>&1").c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  };
  const std::string sim = bin + "/iraf_vo_simulate --preset clean --frames 3 --width 94 --height 60 --no-photos";
  ASSERT_EQ(run(sim + " --camera fisheye --stereo --out " + out), 0);
  std::string err;
  iraf_vo::CameraModelPtr cam1 = iraf_vo::loadCamera(out + "/mav0/cam1/sensor.yaml", &err);
  ASSERT_TRUE(cam1) << err;
  EXPECT_NEAR(cam1->T_BS(0, 3), 0.101, 1e-12);  // the TUM-VI rig's baseline by default
  std::ifstream csv0(out + "/mav0/cam0/data.csv"), csv1(out + "/mav0/cam1/data.csv");
  const std::string rows0((std::istreambuf_iterator<char>(csv0)), std::istreambuf_iterator<char>());
  const std::string rows1((std::istreambuf_iterator<char>(csv1)), std::istreambuf_iterator<char>());
  EXPECT_EQ(rows0, rows1);  // same timestamps and names
  EXPECT_NE(run(sim + " --baseline 0.2 --out " + out + "_b"), 0) << "--baseline needs --stereo";
  EXPECT_NE(run(sim + " --stereo --rig-yaw 45 --out " + out + "_c"), 0) << "rig angle out of range";
}
