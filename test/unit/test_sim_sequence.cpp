// Sequence output: ASL folder + TUM ground truth written by simulateSequence / iraf_vo_simulate, and
// iraf_vo_degrade keeping ground truth, calibration and the image count (missing images skipped).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/sim/asl_degrade.h"
#include "iraf_vo/sim/light_profile.h"
#include "iraf_vo/sim/motion_preset.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/sequence.h"

namespace fs = std::filesystem;

namespace {

/// Per-process temp prefix so parallel runs (ctest -j, plain + sanitizer builds) never share files;
/// removed at exit (same convention as the other test binaries).
#include "common/tmp_dir.h"

std::string freshDir(const std::string& name) {
  const std::string d = tmpRoot() + "sim_" + name;
  fs::remove_all(d);
  return d;
}

std::vector<std::string> dataLines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(f, line))
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// The default room with procedural textures at 64 texels/m.
std::shared_ptr<const iraf_vo::Scene> smallRoom() {
  iraf_vo::SceneParams sp;
  sp.texels_per_m = 64;
  sp.photo_dir.clear();  // procedural only
  return std::make_shared<const iraf_vo::Scene>(iraf_vo::Scene::makeDefaultRoom(sp));
}

TEST(SimSequence, WritesAslFolderAndTumGroundTruth) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera("fisheye", 128, 128, &err);
  ASSERT_TRUE(cam) << err;
  auto scene = smallRoom();
  iraf_vo::SimParams params;
  params.frames = 6;
  params.write_depth = true;
  iraf_vo::Renderer r(cam, scene, params);
  iraf_vo::PhotometricParams ph;
  ASSERT_TRUE(iraf_vo::photometricPreset("mixed", params.frames, false, 1, &ph));
  const std::string out = freshDir("seq");
  int calls = 0;
  iraf_vo::SimulateReport rep;
  ASSERT_TRUE(iraf_vo::simulateSequence(r, iraf_vo::TrajectoryParams(), ph, out,
                                        [&](const iraf_vo::SimFrame& f) { calls += f.image.type() == CV_8UC1; }, &rep,
                                        &err))
      << err;
  EXPECT_EQ(calls, 6);
  // Depth maps (mm) agree with castPixel.
  ASSERT_EQ(dataLines(out + "/mav0/depth0/data.csv").size(), 6u);
  const cv::Mat dmm = cv::imread(out + "/mav0/depth0/data/1000000000050000000.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(dmm.type(), CV_16UC1);
  Eigen::Vector3d p_W;
  double depth_m = 0;
  ASSERT_TRUE(r.castPixel(iraf_vo::trajectoryPose(iraf_vo::TrajectoryParams(), 0.05), Eigen::Vector2d(64, 40), &p_W,
                          &depth_m));
  EXPECT_NEAR(dmm.at<uint16_t>(40, 64), depth_m * 1000.0, 1.0);
  const auto rows = dataLines(out + "/mav0/cam0/data.csv");
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[1], "1000000000050000000,1000000000050000000.png");  // 20 Hz, ns
  for (const auto& row : rows) {
    const cv::Mat img = cv::imread(out + "/mav0/cam0/data/" + row.substr(row.find(',') + 1), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty()) << row;
    EXPECT_EQ(img.type(), CV_8UC1);
    EXPECT_EQ(img.cols, 128);
  }
  // sensor.yaml reads back as the same camera (Kalibr layout, equidistant).
  auto back = iraf_vo::loadCamera(out + "/mav0/cam0/sensor.yaml", &err);
  ASSERT_TRUE(back) << err;
  EXPECT_EQ(back->modelName(), "kannala-brandt");
  const auto p0 = cam->parameters(), p1 = back->parameters();
  ASSERT_EQ(p0.size(), p1.size());
  for (size_t i = 0; i < p0.size(); ++i) EXPECT_NEAR(p0[i], p1[i], 1e-12);
  const std::string yaml = slurp(out + "/mav0/cam0/sensor.yaml");
  EXPECT_NE(yaml.find("rate_hz: 20"), std::string::npos);
  EXPECT_NE(yaml.find("distortion_model: equidistant"), std::string::npos);
  // TUM ground truth: seconds with 9 decimals, unit quaternion matching the trajectory.
  const auto gt = dataLines(out + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), 6u);
  std::istringstream ls(gt[2]);
  std::string t;
  double x, y, z, qx, qy, qz, qw;
  ls >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
  EXPECT_EQ(t, "1000000000.100000000");
  const Eigen::Isometry3d T = iraf_vo::trajectoryPose(iraf_vo::TrajectoryParams(), 0.1);
  EXPECT_NEAR((Eigen::Vector3d(x, y, z) - T.translation()).norm(), 0.0, 1e-8);
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  EXPECT_NEAR(q.norm(), 1.0, 1e-8);
  EXPECT_LT(Eigen::AngleAxisd(q.toRotationMatrix().transpose() * T.linear()).angle(), 1e-7);
  EXPECT_EQ(dataLines(out + "/events.csv").size(), ph.events.size());

  // The project's own readers (io/) accept the output: ASL folder with its camera, TUM ground truth.
  iraf_vo::AslImageReader reader;
  ASSERT_TRUE(reader.open(out, &err)) << err;
  EXPECT_EQ(reader.size(), 6u);
  EXPECT_TRUE(reader.warnings().empty());
  ASSERT_TRUE(reader.loadCamera(&err)) << err;
  iraf_vo::Trajectory traj;
  ASSERT_TRUE(iraf_vo::readTumTrajectory(out + "/groundtruth.txt", &traj, &err)) << err;
  ASSERT_EQ(traj.size(), 6u);
  EXPECT_NEAR(traj.stamps[2] - traj.stamps[0], 0.1, 1e-6);
  EXPECT_LT((traj.poses[2].translation() - T.translation()).norm(), 1e-8);
}

/// A tiny ASL sequence: n images (one row without its file), ground truth folders, sensor.yaml.
std::string makeTinyAsl(const std::string& name, int n) {
  const std::string dir = freshDir(name);
  fs::create_directories(dir + "/mav0/cam0/data");
  fs::create_directories(dir + "/mav0/state_groundtruth_estimate0");
  fs::create_directories(dir + "/groundtruth");
  std::ofstream(dir + "/groundtruth/groundtruth_tum_cam0.txt") << "# t x y z qx qy qz qw\n1.0 0 0 0 0 0 0 1\n";
  std::ofstream(dir + "/mav0/state_groundtruth_estimate0/data.csv") << "#timestamp,p_x\n1000,0.5\n";
  std::ofstream(dir + "/mav0/cam0/sensor.yaml") << "camera_model: pinhole\n";
  std::ofstream csv(dir + "/mav0/cam0/data.csv");
  csv << "#timestamp [ns],filename\n";
  cv::RNG rng(1);
  for (int i = 0; i < n; ++i) {
    const std::string file = std::to_string(1000 + i * 50) + ".png";
    csv << 1000 + i * 50 << "," << file << "\r\n";  // CRLF as in some EuRoC copies
    if (i == 2) continue;                              // missing image
    cv::Mat img(48, 64, CV_8UC1);
    rng.fill(img, cv::RNG::UNIFORM, 40, 200);
    cv::imwrite(dir + "/mav0/cam0/data/" + file, img);
  }
  csv << "1450,not_an_image.png\n";  // unreadable
  std::ofstream(dir + "/mav0/cam0/data/not_an_image.png") << "garbage";
  return dir;
}

TEST(SimDegrade, KeepsGroundTruthAndImageCount) {
  const std::string in = makeTinyAsl("degrade_in", 8);
  const std::string out = freshDir("degrade_out");
  iraf_vo::PhotometricParams ph;
  ASSERT_TRUE(iraf_vo::photometricPreset("dark", 9, true, 1, &ph));
  iraf_vo::DegradeReport rep;
  std::string err;
  ASSERT_TRUE(iraf_vo::degradeAslSequence(in, out, ph, &rep, &err)) << err;
  EXPECT_EQ(rep.images, 9);
  EXPECT_EQ(rep.written, 7);
  EXPECT_EQ(rep.skipped, 2);
  EXPECT_EQ(dataLines(out + "/mav0/cam0/data.csv").size(), 7u);
  EXPECT_EQ(slurp(out + "/groundtruth/groundtruth_tum_cam0.txt"), slurp(in + "/groundtruth/groundtruth_tum_cam0.txt"));
  EXPECT_EQ(slurp(out + "/mav0/state_groundtruth_estimate0/data.csv"),
            slurp(in + "/mav0/state_groundtruth_estimate0/data.csv"));
  EXPECT_EQ(slurp(out + "/mav0/cam0/sensor.yaml"), slurp(in + "/mav0/cam0/sensor.yaml"));
  EXPECT_TRUE(fs::exists(out + "/events.csv"));
  // The middle frame (ramp bottom) is much darker than its input; the first frame is unchanged but for noise.
  const cv::Mat a = cv::imread(in + "/mav0/cam0/data/1200.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat b = cv::imread(out + "/mav0/cam0/data/1200.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(b.empty());
  EXPECT_LT(cv::mean(b)[0], 0.2 * cv::mean(a)[0]);
  const cv::Mat a0 = cv::imread(in + "/mav0/cam0/data/1000.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat b0 = cv::imread(out + "/mav0/cam0/data/1000.png", cv::IMREAD_GRAYSCALE);
  EXPECT_NEAR(cv::mean(b0)[0], cv::mean(a0)[0], 1.0);

  // Missing dataset: error naming the path.
  EXPECT_FALSE(iraf_vo::degradeAslSequence(in + "_nope", out + "2", ph, &rep, &err));
  EXPECT_NE(err.find("_nope"), std::string::npos) << err;
}

TEST(SimSequence, LightProfileWritesExposurePerFrameAndIsDeterministic) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera("pinhole", 94, 60, &err);
  ASSERT_TRUE(cam) << err;
  auto scene = smallRoom();
  iraf_vo::SimParams params;
  params.frames = 20;
  iraf_vo::Renderer r(cam, scene, params);
  iraf_vo::LightProfile light;
  ASSERT_TRUE(iraf_vo::lightProfile("blackout", params.frames, params.rate_hz, params.exposure_time_s, false, 4, &light));
  std::vector<cv::Mat> first, second;
  const std::string out = freshDir("light_seq");
  ASSERT_TRUE(iraf_vo::simulateSequence(r, iraf_vo::TrajectoryParams(), light, out,
                                        [&](const iraf_vo::SimFrame& f) { first.push_back(f.image.clone()); }, nullptr,
                                        &err))
      << err;
  ASSERT_TRUE(iraf_vo::simulateSequence(r, iraf_vo::TrajectoryParams(), light, "",
                                        [&](const iraf_vo::SimFrame& f) { second.push_back(f.image.clone()); }, nullptr,
                                        &err))
      << err;
  ASSERT_EQ(first.size(), 20u);
  ASSERT_EQ(second.size(), 20u);
  for (size_t i = 0; i < first.size(); ++i) EXPECT_EQ(cv::countNonZero(first[i] != second[i]), 0) << i;
  // exposure.csv: one row per frame; the blackout (frames 8-13 of 20: 30 % cap) is dark, the exposure maxed.
  const auto rows = dataLines(out + "/exposure.csv");
  ASSERT_EQ(rows.size(), 20u);
  EXPECT_EQ(rows[0].substr(0, 2), "0,");
  EXPECT_LT(cv::mean(first[10])[0], 5.0);
  EXPECT_GT(cv::mean(first[5])[0], 50.0);
  double t5 = 0, t13 = 0;
  ASSERT_EQ(std::sscanf(rows[5].c_str(), "%*d,%lf", &t5), 1);
  ASSERT_EQ(std::sscanf(rows[13].c_str(), "%*d,%lf", &t13), 1);
  EXPECT_GT(t13, 2.0 * t5) << rows[13];
}

TEST(SimSequence, ShutterBlurGrowsWithTheExposure) {
  // The renderer's shutter follows the camera's exposure: 4x the time under fast hand rotation blurs more.
  std::string err;
  auto cam = iraf_vo::makeSimCamera("pinhole", 188, 120, &err);
  ASSERT_TRUE(cam) << err;
  const iraf_vo::MotionPreset mp = iraf_vo::motionPreset(iraf_vo::MotionKind::kHandheldFast);
  iraf_vo::SimParams params;
  params.motion_blur_samples = 1;
  params.exposure_time_s = 0.01;
  iraf_vo::Renderer r(cam, smallRoom(), params);
  auto sharpness = [&](double exposure_s) {
    double sum = 0.0;
    for (int frame : {40, 80, 120}) {
      cv::Mat rad, lap;
      r.renderFrame(mp.traj, frame, exposure_s, &rad);
      cv::Laplacian(rad, lap, CV_32F);
      sum += cv::mean(lap.mul(lap))[0];
    }
    return sum;
  };
  const double at_reference = sharpness(0.01), at_4x = sharpness(0.04);
  EXPECT_LT(at_4x, 0.8 * at_reference) << at_4x << " vs " << at_reference;
  // At the reference exposure the one-sample render is the plain render of the frame's pose.
  cv::Mat a, b;
  r.renderFrame(mp.traj, 40, 0.01, &a);
  r.render(iraf_vo::trajectoryPose(mp.traj, r.frameTime(40)), &b);
  EXPECT_EQ(cv::countNonZero(a != b), 0);
}

TEST(SimDegrade, LightProfileOnRealImages) {
  const std::string in = makeTinyAsl("degrade_light_in", 30);
  const std::string out = freshDir("degrade_light_out");
  iraf_vo::LightProfile light;
  ASSERT_TRUE(iraf_vo::lightProfile("night", 31, 20.0, 0.01, true, 1, &light));
  iraf_vo::DegradeReport rep;
  std::string err;
  ASSERT_TRUE(iraf_vo::degradeAslSequence(in, out, light, &rep, &err)) << err;
  EXPECT_EQ(rep.written, 29);
  EXPECT_EQ(dataLines(out + "/exposure.csv").size(), 29u);
  // Night: 0.23 % of the light; the longest exposure (4x) and the highest gain (48) bring the mean back to 44 % of
  // the input's, with the noise of that gain.
  const cv::Mat a = cv::imread(in + "/mav0/cam0/data/1500.png", cv::IMREAD_GRAYSCALE);
  const cv::Mat b = cv::imread(out + "/mav0/cam0/data/1500.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(b.empty());
  EXPECT_GT(cv::mean(b)[0], 0.35 * cv::mean(a)[0]);
  EXPECT_LT(cv::mean(b)[0], 0.55 * cv::mean(a)[0]);
  cv::Mat d;
  cv::absdiff(a, b, d);
  EXPECT_GT(cv::mean(d)[0], 5.0) << "high-gain noise on top of the image";
}

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

TEST(SimTools, CommandLines) {
  const std::string bin = IRAF_VO_BIN_DIR;
  if (!fs::exists(bin + "/iraf_vo_simulate") || !fs::exists(bin + "/iraf_vo_degrade"))
    GTEST_SKIP() << "tools not built in " << bin << " (build the package first)";
  const std::string out = freshDir("tool_sim");
  ASSERT_EQ(run(bin + "/iraf_vo_simulate --preset flicker --out " + out + " --frames 4 --width 94 --height 60 --no-photos"), 0);
  EXPECT_EQ(dataLines(out + "/mav0/cam0/data.csv").size(), 4u);
  EXPECT_EQ(dataLines(out + "/groundtruth.txt").size(), 4u);
  const std::string deg = freshDir("tool_deg");
  EXPECT_EQ(run(bin + "/iraf_vo_degrade " + out + " " + deg + " --profile mixed --seed 3"), 0);
  EXPECT_EQ(dataLines(deg + "/mav0/cam0/data.csv").size(), 4u);
  EXPECT_EQ(slurp(deg + "/groundtruth.txt"), slurp(out + "/groundtruth.txt"));
  // Bad input: non-zero exit.
  EXPECT_NE(run(bin + "/iraf_vo_degrade /nonexistent/seq " + deg + "x --profile dark"), 0);
  EXPECT_NE(run(bin + "/iraf_vo_degrade " + out + " " + deg + "y --profile sunny"), 0);
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset nope --out " + out), 0);
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset clean --out " + out + " --frames -3"), 0);
  EXPECT_NE(run(bin + "/iraf_vo_simulate --preset clean --out " + out + " --camera /nonexistent.yaml"), 0);
}

}  // namespace
