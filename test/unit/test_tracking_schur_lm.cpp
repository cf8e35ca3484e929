// The local BA's Schur-complement Levenberg-Marquardt (src/tracking/schur_lm.h, BAOptions::use_ceres = false)
// against ceres::Solve (use_ceres = true) on the same problems with Ceres' rule for invalid steps: the same steps,
// hence the same cost, iterations and parameters; its stop rules (abort flag, iteration budget); and its own rule
// for points that a step moves behind a camera.
#include "iraf_vo/tracking/bundle_adjustment.h"
#include "tracking_test_utils.h"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <random>

using namespace iraf_vo;

namespace {

struct Problem {
  std::vector<BAKeyframe> kfs;
  std::vector<BAPoint> pts;
  std::vector<BAObservation> obs;
};

// num_kf keyframes along a curve, the first num_fixed fixed; noisy observations with gross outliers (Huber
// active), perturbed free poses and points; one point seen only by fixed keyframes.
Problem makeProblem(const CameraModel& cam, int num_kf, int num_fixed, int num_points, unsigned seed) {
  Problem p;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(3, 8);
  std::normal_distribution<double> nd(0.0, 1.0);
  p.kfs.resize(num_kf);
  for (int k = 0; k < num_kf; ++k) {
    p.kfs[k].T_c_w = test::makePose({1.0 * k, -1.5 * k, 0.5 * k}, {0.15 * k, 0.03 * k, 0.02 * k}).inverse();
    p.kfs[k].fixed = k < num_fixed;
  }
  for (int i = 0; i < num_points; ++i) {
    BAPoint q;
    q.p_w = Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
    for (int k = 0; k < num_kf; ++k) {
      if (i == 0 && !p.kfs[k].fixed) continue;  // point 0: fixed observers only
      Eigen::Vector2d uv;
      if (!cam.project(p.kfs[k].T_c_w * q.p_w, &uv)) continue;
      p.obs.push_back({k, i, uv + 0.5 * Eigen::Vector2d(nd(rng), nd(rng)), 1.0 + 0.2 * (i % 4)});
    }
    p.pts.push_back(q);
  }
  for (int k = num_fixed; k < num_kf; ++k)
    p.kfs[k].T_c_w = test::makePose(0.5 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng)),
                                    0.05 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng))) *
                     p.kfs[k].T_c_w;
  for (auto& q : p.pts) q.p_w += 0.05 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
  for (size_t j = 0; j < p.obs.size(); j += 37) p.obs[j].uv += Eigen::Vector2d(25, -20);
  return p;
}

std::unique_ptr<CameraModel> makeCam(bool fisheye) {
  if (fisheye) return std::make_unique<test::TestFisheye>(640, 480, 300.0, 320.0, 240.0);
  return std::make_unique<PinholeRadtan>(640, 480, 450.0, 452.0, 320.0, 240.0, -0.2, 0.05, 1e-3, -1e-3);
}

struct BARun {
  Problem p;
  BASummary sum;
  bool ok = false;
};

BARun solve(const CameraModel& cam, const Problem& start, BAOptions opt, bool use_ceres) {
  BARun r;
  r.p = start;
  opt.use_ceres = use_ceres;
  r.ok = bundleAdjust(cam, &r.p.kfs, &r.p.pts, r.p.obs, opt, &r.sum);
  return r;
}

void expectSameSolution(const BARun& a, const BARun& b, double tol) {
  ASSERT_EQ(a.ok, b.ok);
  EXPECT_NEAR(a.sum.initial_cost, b.sum.initial_cost, 1e-9 * a.sum.initial_cost);
  EXPECT_NEAR(a.sum.final_cost, b.sum.final_cost, 1e-7 * a.sum.initial_cost);
  EXPECT_EQ(a.sum.iterations, b.sum.iterations);
  EXPECT_EQ(a.sum.outlier, b.sum.outlier);
  for (size_t k = 0; k < a.p.kfs.size(); ++k) {
    EXPECT_LT((a.p.kfs[k].T_c_w.matrix() - b.p.kfs[k].T_c_w.matrix()).cwiseAbs().maxCoeff(), tol) << "pose " << k;
  }
  // A point seen once is free along its ray (no curvature there): only the damping holds it, and rounding
  // differences are not damped out; those are not compared.
  std::vector<int> seen(a.p.pts.size(), 0);
  for (const BAObservation& o : a.p.obs) ++seen[o.point];
  for (size_t i = 0; i < a.p.pts.size(); ++i) {
    if (seen[i] < 2) continue;  // relative: points pushed towards infinity by outliers (1e7 m) agree to 1e-8
    EXPECT_LT((a.p.pts[i].p_w - b.p.pts[i].p_w).norm(), tol * (1.0 + a.p.pts[i].p_w.norm())) << "point " << i;
  }
}

}  // namespace

TEST(TrackingSchurLM, SameStepsAsCeres) {
  for (bool fisheye : {false, true}) {
    const auto cam = makeCam(fisheye);
    // Window shapes of the local BA: few / many free poses, one free pose, no free pose (points only).
    const int shapes[][3] = {{6, 2, 150}, {12, 4, 300}, {3, 2, 80}, {4, 4, 60}};
    for (const auto& s : shapes) {
      const Problem start = makeProblem(*cam, s[0], s[1], s[2], 11u + s[0]);
      for (int iterations : {1, 3, 10, 50}) {
        BAOptions opt;
        opt.max_num_iterations = iterations;
        opt.max_solver_time_in_seconds = 100.0;
        opt.drop_points_behind = false;  // Ceres' rule for steps that move a point behind a camera
        const BARun ceres = solve(*cam, start, opt, true);
        const BARun schur = solve(*cam, start, opt, false);
        SCOPED_TRACE(::testing::Message() << cam->modelName() << " kfs " << s[0] << " fixed " << s[1]
                                          << " iterations " << iterations);
        ASSERT_TRUE(ceres.ok);
        if (iterations >= 10) {
          EXPECT_LT(ceres.sum.final_cost, 0.5 * ceres.sum.initial_cost);
        }
        EXPECT_LE(schur.sum.iterations, iterations + 1);
        expectSameSolution(ceres, schur, 1e-6);
        for (size_t k = 0; k < start.kfs.size(); ++k) {
          if (!start.kfs[k].fixed) continue;
          EXPECT_EQ(schur.p.kfs[k].T_c_w.matrix(), start.kfs[k].T_c_w.matrix());
        }
      }
    }
  }
}

TEST(TrackingSchurLM, StopRules) {
  const auto cam = makeCam(false);
  const Problem start = makeProblem(*cam, 6, 2, 150, 3u);
  // A set abort flag stops after the initial evaluation: usable, nothing moved (as Ceres' callback does).
  std::atomic<bool> abort{true};
  BAOptions opt;
  opt.max_num_iterations = 10;
  opt.abort = &abort;
  for (bool use_ceres : {true, false}) {
    const BARun r = solve(*cam, start, opt, use_ceres);
    EXPECT_TRUE(r.ok) << use_ceres;
    EXPECT_EQ(r.sum.iterations, 1) << use_ceres;
    EXPECT_EQ(r.sum.final_cost, r.sum.initial_cost) << use_ceres;
    for (size_t i = 0; i < start.pts.size(); ++i) {
      EXPECT_EQ(r.p.pts[i].p_w, start.pts[i].p_w);
    }
  }
  // Zero iterations: no step either; one iteration: exactly one step, cost down.
  opt.abort = nullptr;
  opt.max_num_iterations = 0;
  const BARun none = solve(*cam, start, opt, false);
  EXPECT_TRUE(none.ok);
  EXPECT_EQ(none.sum.iterations, 1);
  EXPECT_EQ(none.sum.final_cost, none.sum.initial_cost);
  opt.max_num_iterations = 1;
  const BARun one = solve(*cam, start, opt, false);
  EXPECT_EQ(one.sum.iterations, 2);
  EXPECT_LT(one.sum.final_cost, 0.9 * one.sum.initial_cost);
}

// A point far away whose observations disagree with any depth in front of the cameras (their rays diverge): the
// Gauss-Newton step moves it along its ray beyond infinity, behind the cameras. Ceres' rule would reject that step
// and halve the trust region again and again (no progress for the other points); the solver instead takes the point
// out of the problem at its last valid position (ORB-SLAM drops edges of negative depth) and converges on the rest.
TEST(TrackingSchurLM, PointDrivenBehindACameraLeavesTheProblem) {
  const auto cam = makeCam(false);
  Problem p = makeProblem(*cam, 4, 2, 60, 5);
  const Eigen::Isometry3d T_w_c0 = p.kfs[0].T_c_w.inverse();
  const Eigen::Vector3d far = T_w_c0 * Eigen::Vector3d(0.3, -0.2, 400.0);
  const int id = static_cast<int>(p.pts.size());
  p.pts.push_back({far});
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam->project(p.kfs[k].T_c_w * far, &uv));
    p.obs.push_back({k, id, uv + Eigen::Vector2d(k % 2 == 0 ? 6.0 : -6.0, 0.0), 1.0});  // rays diverge
  }
  BAOptions opt;
  opt.max_num_iterations = 10;
  const BARun r = solve(*cam, p, opt, false);
  ASSERT_TRUE(r.ok);
  EXPECT_GE(r.sum.excluded_points, 1);
  opt.drop_points_behind = false;  // Ceres' rule on the same problem: no point excluded
  EXPECT_EQ(solve(*cam, p, opt, false).sum.excluded_points, 0);
  opt.drop_points_behind = true;
  // The far point stays in front of its first camera (it left the problem at a valid position) ...
  EXPECT_GT((r.p.kfs[0].T_c_w * r.p.pts[static_cast<size_t>(id)].p_w).z(), 0.0);
  // ... and the rest converges as without that point: the same final cost within 1 %.
  Problem q = p;
  q.pts.pop_back();
  q.obs.resize(q.obs.size() - 4);
  const BARun ref = solve(*cam, q, opt, false);
  ASSERT_TRUE(ref.ok);
  EXPECT_EQ(ref.sum.excluded_points, 0);
  EXPECT_NEAR(r.sum.final_cost, ref.sum.final_cost, 0.01 * ref.sum.final_cost);
  for (size_t k = 2; k < 4; ++k)
    EXPECT_LT((r.p.kfs[k].T_c_w.translation() - ref.p.kfs[k].T_c_w.translation()).norm(), 1e-3);
}
