// Trajectory evaluation: association, Umeyama alignment, ATE / RPE against hand-computed values.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sys/stat.h>

#include "iraf_vo/eval/trajectory_eval.h"

using namespace iraf_vo;

#include "common/tmp_dir.h"

namespace {

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = p;
  return T;
}

/// Smooth synthetic trajectory: a 3D Lissajous with rotating orientation, 20 Hz.
Trajectory makeGt(size_t n) {
  Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double s = 0.05 * i;
    const Eigen::Vector3d p(2.0 * std::sin(0.5 * s), 1.5 * std::cos(0.3 * s), 0.5 * std::sin(0.7 * s));
    const Eigen::Quaterniond q = Eigen::AngleAxisd(0.2 * s, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(0.1 * std::sin(s), Eigen::Vector3d::UnitX());
    t.push_back(100.0 + s, pose(p, q));
  }
  return t;
}

}  // namespace

TEST(Association, NearestOneToOneWithinMaxDt) {
  const std::vector<double> gt{0.0, 0.1, 0.2, 0.3, 0.4};
  const std::vector<double> est{0.005, 0.012, 0.19, 0.35, 0.5};
  const auto pairs = associate(gt, est, 0.02);
  // 0.005 -> 0.0 (closest); 0.012 cannot reuse gt 0.0 (one-to-one) and has nothing else within 20 ms;
  // 0.19 -> 0.2; 0.35 is 50 ms from 0.3 / 0.4; 0.5 has no GT.
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0], std::make_pair(size_t(0), size_t(0)));
  EXPECT_EQ(pairs[1], std::make_pair(size_t(2), size_t(2)));
  // With 60 ms, 0.35 also matches (0.3 or 0.4, both 50 ms away); 0.012 is still blocked by 0.005 and
  // 0.5 is 100 ms from 0.4.
  const auto wide = associate(gt, est, 0.06);
  ASSERT_EQ(wide.size(), 3u);
  EXPECT_EQ(wide[2].second, 3u);
  EXPECT_TRUE(wide[2].first == 3u || wide[2].first == 4u);
  EXPECT_TRUE(associate(gt, {}, 0.02).empty());
  EXPECT_TRUE(associate({}, est, 0.02).empty());
}

TEST(Umeyama, RecoversKnownSim3WithNoise) {
  const Trajectory gt = makeGt(600);
  // est = S_true^-1 (gt) + noise, i.e. the estimate lives in a frame scaled by 1/2.5, rotated and shifted.
  Sim3 S_true;
  S_true.s = 2.5;
  S_true.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  S_true.t = Eigen::Vector3d(10.0, -4.0, 2.0);
  const Sim3 S_inv = S_true.inverse();
  std::mt19937 rng(42);
  std::normal_distribution<double> N(0.0, 0.004);  // noise in the estimate frame
  Trajectory est;
  double noise_sq_gt = 0.0;  // noise expressed in GT units (x s)
  for (size_t i = 0; i < gt.size(); ++i) {
    const Eigen::Vector3d n(N(rng), N(rng), N(rng));
    Eigen::Isometry3d T = S_inv.apply(gt.poses[i]);
    T.translation() += n;
    noise_sq_gt += (S_true.s * n).squaredNorm();
    est.push_back(gt.stamps[i] + 0.003, T);  // 3 ms offset: still associated
  }
  const double noise_rms = std::sqrt(noise_sq_gt / gt.size());

  EvalParams p;  // sim3, 20 ms, 1 s RPE
  EvalResult r;
  std::string err;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_EQ(r.n_matched, 600u);
  EXPECT_DOUBLE_EQ(r.coverage, 1.0);
  // The alignment is the inverse of the transform applied to the estimate, i.e. S_true.
  EXPECT_NEAR(r.scale, 2.5, 2e-3);
  EXPECT_LT((r.alignment.R - S_true.R).norm(), 2e-3);
  EXPECT_LT((r.alignment.t - S_true.t).norm(), 1e-2);
  // 600 points, 7 dof: the residual RMS is the noise RMS up to ~sqrt(1 - 7/1800) and sampling of the fit.
  EXPECT_NEAR(r.ate.rmse, noise_rms, 0.03 * noise_rms);
  EXPECT_GT(r.ate.rmse, 0.005);

  // SE(3) alignment cannot undo the scale: much larger error.
  p.align = AlignMode::kSE3;
  EvalResult r2;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r2, &err)) << err;
  EXPECT_DOUBLE_EQ(r2.scale, 1.0);
  EXPECT_GT(r2.ate.rmse, 10.0 * r.ate.rmse);
}

TEST(Umeyama, IdenticalTrajectoriesZeroError) {
  const Trajectory gt = makeGt(200);
  for (AlignMode m : {AlignMode::kNone, AlignMode::kSE3, AlignMode::kSim3}) {
    EvalParams p;
    p.align = m;
    EvalResult r;
    std::string err;
    ASSERT_TRUE(evaluateTrajectory(gt, gt, p, &r, &err)) << err;
    EXPECT_EQ(r.n_matched, 200u);
    EXPECT_DOUBLE_EQ(r.coverage, 1.0);
    EXPECT_NEAR(r.ate.rmse, 0.0, 1e-9) << alignModeName(m);
    EXPECT_NEAR(r.ate.max, 0.0, 1e-9);
    EXPECT_NEAR(r.scale, 1.0, 1e-9);
    EXPECT_GT(r.rpe_trans.n, 100u);
    EXPECT_NEAR(r.rpe_trans.rmse, 0.0, 1e-9);
    EXPECT_NEAR(r.rpe_rot.rmse, 0.0, 1e-6);
  }
}

// Hand-checked example (evo convention: align EST onto GT, ATE = RMSE of translation differences).
// GT: unit square corners in z = 0, identity orientation, t = 0, 1, 2, 3 s.
// EST = 2 * (GT + d) + (2, 3, 4) with d = (0, 0, +0.1), (0, 0, -0.1), (0, 0, +0.1), (0, 0, -0.1).
// Centred GT corners c_i = (+-0.5, +-0.5, 0) are orthogonal to d_i and sum_i d_i c_i^T = 0 (saddle pattern), so the
// optimal rotation is the identity. By hand:
//  * none: e_i = est_i - gt_i = gt_i + 2 d_i + (2, 3, 4): squared norms (corner by corner)
//      (2,3,4.2): 30.64, (3,3,3.8): 32.44, (3,4,4.2): 42.64, (2,4,3.8): 34.44 -> mean 35.04, ATE = sqrt(35.04).
//  * se3: only the mean offset is removed: e_i = c_i + 2 d_i -> |e|^2 = 0.5 + 0.04 -> ATE = sqrt(0.54) = 0.734847.
//  * sim3: var(est) = 4 * (0.5 + 0.01) = 2.04, trace(D S) = 2 * 0.5 = 1 -> s = 1 / 2.04;
//      e_i = (2 s - 1) c_i + 2 s d_i -> |e|^2 = (2/2.04 - 1)^2 * 0.5 + (2/2.04)^2 * 0.01 = 0.01 / 1.02
//      -> ATE = 0.1 / sqrt(1.02) = 0.0990148.
TEST(Ate, HandCheckedEvoConvention) {
  Trajectory gt, est;
  const Eigen::Vector3d c[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const double dz[4] = {0.1, -0.1, 0.1, -0.1};
  for (int i = 0; i < 4; ++i) {
    gt.push_back(i, pose(c[i]));
    est.push_back(i, pose(2.0 * (c[i] + Eigen::Vector3d(0, 0, dz[i])) + Eigen::Vector3d(2, 3, 4)));
  }
  EvalParams p;
  EvalResult r;
  std::string err;
  p.align = AlignMode::kNone;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_NEAR(r.ate.rmse, std::sqrt(35.04), 1e-9);
  p.align = AlignMode::kSE3;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_NEAR(r.ate.rmse, std::sqrt(0.54), 1e-9);
  EXPECT_LT((r.alignment.R - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  p.align = AlignMode::kSim3;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_NEAR(r.scale, 1.0 / 2.04, 1e-9);
  EXPECT_NEAR(r.ate.rmse, 0.1 / std::sqrt(1.02), 1e-9);
  EXPECT_NEAR(r.ate.mean, 0.1 / std::sqrt(1.02), 1e-9);  // all four errors are equal
  EXPECT_NEAR(r.ate.std, 0.0, 1e-7);
  EXPECT_LT((r.alignment.R - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  // Aligned estimate of corner 0: s * 2 * (c0 - mean(c) + d0) + mean(gt) = (2/2.04) (-0.5, -0.5, 0.1) + (0.5, 0.5, 0).
  ASSERT_EQ(r.per_pose.size(), 4u);
  EXPECT_NEAR(r.per_pose[0].est_aligned.x(), 0.5 - 1.0 / 2.04, 1e-9);
  EXPECT_NEAR(r.per_pose[0].est_aligned.z(), 0.2 / 2.04, 1e-9);
}

// RPE by hand: GT moves 1 m along x per second with identity rotation; the estimate equals the GT except
// pose 2, which is displaced by 0.3 m along y and yawed by 10 deg. With delta = 1 frame and no alignment,
// pairs (1,2) and (2,3) are affected:
//  (1,2): E = G12^-1 A12, A12 = [R10, (1, 0.3, 0)] -> t(E) = (0, 0.3, 0): 0.3 m, 10 deg.
//  (2,3): A23 = A2^-1 A3 = [R10^T, R10^T ((3,0,0) - (2,0.3,0))] = [R10^T, R10^T (1, -0.3, 0)];
//         E = G23^-1 A23 = [R10^T, R10^T (1, -0.3, 0) - (1, 0, 0)]: |t| = |(1,-0.3,0) - R10 (1,0,0)|.
TEST(Rpe, HandChecked) {
  Trajectory gt, est;
  const double yaw = 10.0 * M_PI / 180.0;
  for (int i = 0; i < 5; ++i) {
    gt.push_back(i, pose(Eigen::Vector3d(i, 0, 0)));
    if (i == 2)
      est.push_back(i, pose(Eigen::Vector3d(i, 0.3, 0), Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()))));
    else
      est.push_back(i, pose(Eigen::Vector3d(i, 0, 0)));
  }
  EvalParams p;
  p.align = AlignMode::kNone;
  p.rpe_delta = 1;
  p.rpe_delta_frames = true;
  EvalResult r;
  std::string err;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  ASSERT_EQ(r.rpe_trans.n, 4u);
  const double e23 = (Eigen::Vector3d(1, -0.3, 0) - Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(1, 0, 0)).norm();
  EXPECT_NEAR(r.rpe_trans.max, std::max(0.3, e23), 1e-9);
  EXPECT_NEAR(r.rpe_trans.rmse, std::sqrt((0.09 + e23 * e23) / 4.0), 1e-9);
  EXPECT_NEAR(r.rpe_rot.max, 10.0, 1e-9);
  EXPECT_NEAR(r.rpe_rot.rmse, std::sqrt(200.0 / 4.0), 1e-9);
  // delta in seconds (1 s = 1 frame here) gives the same.
  p.rpe_delta_frames = false;
  EvalResult r2;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r2, &err)) << err;
  EXPECT_EQ(r2.rpe_trans.n, 4u);
  EXPECT_NEAR(r2.rpe_trans.rmse, r.rpe_trans.rmse, 1e-12);
}

TEST(Eval, CoverageStatsAndErrors) {
  const Trajectory gt = makeGt(100);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); i += 2) est.push_back(gt.stamps[i], gt.poses[i]);
  EvalParams p;
  EvalResult r;
  std::string err;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_EQ(r.n_matched, 50u);
  EXPECT_DOUBLE_EQ(r.coverage, 0.5);

  const ErrorStats s = computeStats({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.max, 4.0);

  // Too few matches / degenerate estimate -> error, no crash.
  Trajectory far;
  far.push_back(0.0, gt.poses[0]);
  EXPECT_FALSE(evaluateTrajectory(gt, far, p, &r, &err));
  EXPECT_NE(err.find("need at least 3"), std::string::npos) << err;
  Trajectory still;
  for (size_t i = 0; i < gt.size(); ++i) still.push_back(gt.stamps[i], Eigen::Isometry3d::Identity());
  EXPECT_FALSE(evaluateTrajectory(gt, still, p, &r, &err));
  EXPECT_NE(err.find("degenerate"), std::string::npos) << err;

  // CSV + JSON.
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err));
  const std::string csv = tmpRoot() + "iraf_vo_errors.csv";
  ASSERT_TRUE(writeErrorsCsv(csv, r, &err)) << err;
  std::ifstream f(csv);
  std::string line;
  int lines = 0;
  while (std::getline(f, line)) ++lines;
  EXPECT_EQ(lines, 51);
  EXPECT_NE(toJson(r, p).find("\"n_matched\": 50"), std::string::npos);
  EXPECT_NE(formatSummary(r, p).find("coverage 50.0 %"), std::string::npos) << formatSummary(r, p);
  EXPECT_FALSE(writeErrorsCsv("/nonexistent/dir/e.csv", r, &err));
  AlignMode m;
  EXPECT_TRUE(parseAlignMode("Sim3", &m));
  EXPECT_EQ(m, AlignMode::kSim3);
  EXPECT_FALSE(parseAlignMode("affine", &m));
}

TEST(Eval, MetricAlignmentReportsTheScaleErrorThatSim3Hides) {
  // A rigidly moved copy of the ground truth that is 3 % too large: Sim(3) absorbs the scale (ATE ~ 0),
  // SE(3) cannot (ATE of the order of 3 % of the trajectory's extent), and both report the Sim(3) scale.
  const Trajectory gt = makeGt(100);
  Sim3 S;
  S.s = 1.03;
  S.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  S.t = Eigen::Vector3d(0.5, -1, 2);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); ++i) est.push_back(gt.stamps[i], S.apply(gt.poses[i]));
  std::string err;
  EvalParams p;
  EvalResult sim3, se3;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &sim3, &err)) << err;
  p.align = AlignMode::kSE3;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &se3, &err)) << err;
  EXPECT_LT(sim3.ate.rmse, 1e-9);
  EXPECT_NEAR(sim3.scale, 1.0 / 1.03, 1e-9);
  EXPECT_DOUBLE_EQ(se3.scale, 1.0);
  // Scale error 3 % on positions spread over ~1.5 m around their centroid: SE(3) ATE 2-6 cm.
  EXPECT_GT(se3.ate.rmse, 0.02);
  EXPECT_LT(se3.ate.rmse, 0.06);
  for (const EvalResult* r : {&sim3, &se3}) {
    ASSERT_TRUE(r->metric_valid);
    EXPECT_NEAR(r->se3_ate_rmse, se3.ate.rmse, 1e-12);
    EXPECT_NEAR(r->sim3_scale, 1.0 / 1.03, 1e-9);
    EXPECT_LT(r->sim3_ate_rmse, 1e-9);
  }
  // A metric copy (scale 1): SE(3) ATE ~ 0 too.
  S.s = 1.0;
  Trajectory metric;
  for (size_t i = 0; i < gt.size(); ++i) metric.push_back(gt.stamps[i], S.apply(gt.poses[i]));
  EvalResult m;
  ASSERT_TRUE(evaluateTrajectory(gt, metric, p, &m, &err)) << err;
  EXPECT_LT(m.ate.rmse, 1e-9);
  EXPECT_NEAR(m.sim3_scale, 1.0, 1e-9);
  // Printed and in the JSON.
  EXPECT_NE(formatSummary(se3, p).find("metric: SE(3) ATE rmse"), std::string::npos) << formatSummary(se3, p);
  EXPECT_NE(toJson(se3, p).find("\"sim3_scale\": 0.97087"), std::string::npos) << toJson(se3, p);
  EXPECT_NE(toJson(se3, p).find("\"se3_ate_percent_of_path\""), std::string::npos);
  EXPECT_NE(toJson(se3, p).find("\"align\": \"se3\""), std::string::npos);
}

TEST(Eval, EachMapAfterAResetIsAlignedOnItsOwn) {
  // A run that reset its map at pose 60: the poses before are the ground truth in one frame at scale 0.5, the poses
  // after it in another frame at scale 2 (a new map). One Sim(3) over both cannot fit; each map on its own fits.
  const Trajectory gt = makeGt(100);
  Sim3 A, B;
  A.s = 0.5;
  B.s = 2.0;
  B.R = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  B.t = Eigen::Vector3d(3, 0, -1);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); ++i) est.push_back(gt.stamps[i], (i < 60 ? A : B).apply(gt.poses[i]));
  EvalParams p;
  EvalResult all;
  std::string err;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &all, &err)) << err;
  EXPECT_GT(all.ate.rmse, 0.1);
  const std::vector<EvalResult> maps = evaluatePerMap(gt, est, {gt.stamps[0], gt.stamps[60]}, p);
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].n_matched, 60u);
  EXPECT_EQ(maps[1].n_matched, 40u);
  EXPECT_LT(maps[0].ate.rmse, 1e-9);
  EXPECT_LT(maps[1].ate.rmse, 1e-9);
  EXPECT_NEAR(maps[0].scale, 2.0, 1e-9);
  EXPECT_NEAR(maps[1].scale, 0.5, 1e-9);
  // A map with fewer than 3 poses: n_matched 0; no start given: one map, the whole run.
  EXPECT_EQ(evaluatePerMap(gt, est, {gt.stamps[0], gt.stamps[98]}, p)[1].n_matched, 0u);
  const std::vector<EvalResult> one = evaluatePerMap(gt, est, {}, p);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].ate.rmse, all.ate.rmse, 1e-12);
}

TEST(Eval, SharedEurocGroundTruthAgainstPerturbedCopy) {
  const std::string path = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/groundtruth/groundtruth_tum_cam0.txt";
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) GTEST_SKIP() << "shared EuRoC ground truth absent: " << path;
  Trajectory gt;
  std::string err;
  ASSERT_TRUE(readTrajectory(path, &gt, &err)) << err;
  ASSERT_EQ(gt.size(), 600u);
  // A monocular-like estimate: scaled by 0.3, rotated and shifted -> sim3 ATE ~ 0, scale 1/0.3.
  Sim3 S;
  S.s = 0.3;
  S.R = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  S.t = Eigen::Vector3d(1, 2, 3);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); ++i) est.push_back(gt.stamps[i], S.apply(gt.poses[i]));
  EvalParams p;
  EvalResult r;
  ASSERT_TRUE(evaluateTrajectory(gt, est, p, &r, &err)) << err;
  EXPECT_EQ(r.n_matched, 600u);
  EXPECT_NEAR(r.scale, 1.0 / 0.3, 1e-6);
  EXPECT_LT(r.ate.rmse, 1e-6);
  EXPECT_LT(r.rpe_rot.rmse, 1e-6);
  EXPECT_GT(r.gt_length, 5.0);  // PROVENANCE: 5.4 m path in the first 15 s
}

TEST(EvalTool, CommandLine) {
  const std::string tool = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_eval";
  struct stat st;
  if (::stat(tool.c_str(), &st) != 0) GTEST_SKIP() << "tool not built: " << tool;
  const std::string dir = tmpRoot();
  const Trajectory gt = makeGt(100);
  Sim3 S;
  S.s = 0.5;
  S.t = Eigen::Vector3d(1, 0, 0);
  Trajectory est;
  for (size_t i = 0; i < gt.size(); ++i) est.push_back(gt.stamps[i] + 0.001, S.apply(gt.poses[i]));
  std::string err;
  ASSERT_TRUE(writeTumTrajectory(dir + "iraf_vo_cli_gt.txt", gt, &err)) << err;
  ASSERT_TRUE(writeTumTrajectory(dir + "iraf_vo_cli_est.txt", est, &err)) << err;
  const std::string base = tool + " " + dir + "iraf_vo_cli_gt.txt " + dir + "iraf_vo_cli_est.txt";
  ASSERT_EQ(std::system((base + " --json " + dir + "iraf_vo_cli.json --csv " + dir + "iraf_vo_cli.csv > /dev/null").c_str()), 0);
  std::ifstream j(dir + "iraf_vo_cli.json");
  const std::string json((std::istreambuf_iterator<char>(j)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"n_matched\": 100"), std::string::npos) << json;
  EXPECT_NE(json.find("\"scale\": 2"), std::string::npos) << json;  // 1 / 0.5
  // --align se3: the scale stays 1, the Sim(3) scale is reported beside the metric ATE.
  ASSERT_EQ(std::system((base + " --align se3 --json " + dir + "iraf_vo_cli_se3.json > /dev/null").c_str()), 0);
  std::ifstream j3(dir + "iraf_vo_cli_se3.json");
  const std::string json3((std::istreambuf_iterator<char>(j3)), std::istreambuf_iterator<char>());
  EXPECT_NE(json3.find("\"scale\": 1,"), std::string::npos) << json3;
  EXPECT_NE(json3.find("\"sim3_scale\": 2"), std::string::npos) << json3;
  // Bad input -> non-zero exit with a message.
  EXPECT_NE(std::system((base + " --align affine 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((base + " --max-dt abc 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " " + dir + "iraf_vo_cli_gt.txt /nonexistent.txt 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((tool + " 2>/dev/null").c_str()), 0);
}
