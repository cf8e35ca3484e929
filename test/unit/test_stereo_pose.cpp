// Pose-only refinement with the right image of a stereo pair (optimizePose with RightObservations): the right
// residuals make the pose more accurate than the left ones alone, a wrong right observation is left out, and
// without right observations the result is the monocular one.
#include <gtest/gtest.h>

#include <random>

#include "iraf_vo/tracking/pose_optimization.h"
#include "unit/tracking_test_utils.h"

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

struct StereoPoseProblem {
  Eigen::Isometry3d T_c_w, T_start;
  std::vector<Eigen::Vector3d> P;
  std::vector<Eigen::Vector2d> uv;
  std::vector<double> sigma;
  RightObservations right;
};

// 60 points 4-12 m ahead, both pixels with 1 px noise; EuRoC-like pair (f 458 px, 0.11 m baseline).
StereoPoseProblem makeProblem(const CameraModel& cam, std::mt19937* rng) {
  std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(4, 12);
  std::normal_distribution<double> noise(0.0, 1.0);
  StereoPoseProblem pr;
  pr.T_c_w = makePose({2, -3, 1}, {0.3, -0.2, 0.5}).inverse();
  pr.T_start = makePose({0.5, 0.5, -0.5}, {0.05, 0.03, -0.05}) * pr.T_c_w;
  pr.right.camera = &cam;
  pr.right.T_r_l = makePose({0.0, 0.0, 0.0}, {-0.11, 0.0, 0.0});
  const Eigen::Isometry3d T_w_c = pr.T_c_w.inverse();
  while (pr.P.size() < 60) {
    const Eigen::Vector3d p_w = T_w_c * Eigen::Vector3d(ux(*rng), uy(*rng), uz(*rng));
    Eigen::Vector2d l, r;
    if (!cam.project(pr.T_c_w * p_w, &l) || !cam.project(pr.right.T_r_l * (pr.T_c_w * p_w), &r)) continue;
    pr.P.push_back(p_w);
    pr.uv.push_back(l + Eigen::Vector2d(noise(*rng), noise(*rng)));
    pr.sigma.push_back(1.0);
    pr.right.uv.push_back(r + Eigen::Vector2d(noise(*rng), noise(*rng)));
    pr.right.sigma.push_back(1.0);
  }
  return pr;
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

}  // namespace

TEST(StereoPose, RightResidualsMakeThePoseMoreAccurate) {
  TestPinhole cam(752, 480, 458.0, 376.0, 240.0);
  std::mt19937 rng(11);
  double err_mono = 0.0, err_stereo = 0.0;
  const int trials = 60;
  for (int t = 0; t < trials; ++t) {
    const StereoPoseProblem pr = makeProblem(cam, &rng);
    Eigen::Isometry3d T_mono = pr.T_start, T_stereo = pr.T_start;
    std::vector<char> in_mono(pr.P.size(), 1), in_stereo(pr.P.size(), 1);
    const int n_mono = optimizePose(cam, pr.P, pr.uv, pr.sigma, PoseOptimizationOptions(), &T_mono, &in_mono);
    int right_inliers = 0;
    const int n_stereo = optimizePose(cam, pr.P, pr.uv, pr.sigma, PoseOptimizationOptions(), &T_stereo, &in_stereo,
                                      &pr.right, &right_inliers);
    EXPECT_GE(n_mono, 50);
    EXPECT_GE(n_stereo, 50);
    EXPECT_GE(right_inliers, 45);  // ~90 % of 60 pass both chi2 tests
    err_mono += translationError(T_mono, pr.T_c_w);
    err_stereo += translationError(T_stereo, pr.T_c_w);
  }
  err_mono /= trials;
  err_stereo /= trials;
  // Twice the observations and a second viewpoint: ~0.7 of the monocular error.
  EXPECT_LT(err_stereo, 0.85 * err_mono) << "mean position error: stereo " << err_stereo << " m, left only "
                                         << err_mono << " m";
}

TEST(StereoPose, WrongRightObservationIsLeftOut) {
  TestPinhole cam(752, 480, 458.0, 376.0, 240.0);
  std::mt19937 rng(3);
  StereoPoseProblem pr = makeProblem(cam, &rng);
  // Noise-free pixels, ten right ones on the wrong keypoint (a disparity 25 px off, along the epipolar line).
  for (size_t i = 0; i < pr.P.size(); ++i) {
    cam.project(pr.T_c_w * pr.P[i], &pr.uv[i]);
    cam.project(pr.right.T_r_l * (pr.T_c_w * pr.P[i]), &pr.right.uv[i]);
  }
  for (size_t i = 0; i < 10; ++i) pr.right.uv[i].x() += 25.0;
  Eigen::Isometry3d T = pr.T_start;
  std::vector<char> inlier(pr.P.size(), 1);
  int right_inliers = 0;
  optimizePose(cam, pr.P, pr.uv, pr.sigma, PoseOptimizationOptions(), &T, &inlier, &pr.right, &right_inliers);
  EXPECT_EQ(right_inliers, 50);
  EXPECT_LT(translationError(T, pr.T_c_w), 1e-6);
}

TEST(StereoPose, NoRightObservationsIsTheMonocularResult) {
  TestPinhole cam(752, 480, 458.0, 376.0, 240.0);
  std::mt19937 rng(5);
  StereoPoseProblem pr = makeProblem(cam, &rng);
  std::fill(pr.right.sigma.begin(), pr.right.sigma.end(), 0.0);  // none has a right match
  Eigen::Isometry3d T_mono = pr.T_start, T_none = pr.T_start;
  std::vector<char> in_mono(pr.P.size(), 1), in_none(pr.P.size(), 1);
  optimizePose(cam, pr.P, pr.uv, pr.sigma, PoseOptimizationOptions(), &T_mono, &in_mono);
  int right_inliers = -1;
  optimizePose(cam, pr.P, pr.uv, pr.sigma, PoseOptimizationOptions(), &T_none, &in_none, &pr.right, &right_inliers);
  EXPECT_EQ(right_inliers, 0);
  EXPECT_TRUE(T_mono.matrix() == T_none.matrix());
  EXPECT_EQ(in_mono, in_none);
}
