// The tracker's fast paths against the plain computations they replace (same results, same order).
#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/pose_optimization.h"
#include "tracking_test_utils.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <random>
#include <tuple>

using namespace iraf_vo;

namespace {

constexpr double kGridCell = 32.0;  // Frame's search-grid cell (px)

// Plain window search: every valid keypoint in the cells overlapping the window's bounding box, within radius r and
// the octave range, ordered by cell (row-major) and by keypoint index within a cell (the grid's visiting order).
std::vector<int> plainFeaturesInArea(const Frame& f, int width, int height, double u, double v, double r,
                                     int min_octave, int max_octave) {
  const int cols = std::max(1, static_cast<int>(std::ceil(width / kGridCell)));
  const int rows = std::max(1, static_cast<int>(std::ceil(height / kGridCell)));
  const int x0 = std::max(0, static_cast<int>((u - r) / kGridCell));
  const int x1 = std::min(cols - 1, static_cast<int>((u + r) / kGridCell));
  const int y0 = std::max(0, static_cast<int>((v - r) / kGridCell));
  const int y1 = std::min(rows - 1, static_cast<int>((v + r) / kGridCell));
  std::vector<std::tuple<int, int, int>> hits;  // (cell row, cell col, index)
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.valid[i]) continue;
    const cv::KeyPoint& kp = f.keypoints[i];
    const int cx = std::clamp(static_cast<int>(kp.pt.x / kGridCell), 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(kp.pt.y / kGridCell), 0, rows - 1);
    if (cx < x0 || cx > x1 || cy < y0 || cy > y1) continue;
    if (kp.octave < min_octave || kp.octave > max_octave) continue;
    const double du = kp.pt.x - u, dv = kp.pt.y - v;
    if (du * du + dv * dv <= r * r) hits.emplace_back(cy, cx, static_cast<int>(i));
  }
  std::sort(hits.begin(), hits.end());
  std::vector<int> out;
  for (const auto& h : hits) out.push_back(std::get<2>(h));
  return out;
}

}  // namespace

TEST(TrackingFastPaths, FeaturesInAreaMatchesPlainScanInOrder) {
  const int w = 752, h = 480;
  const test::TestPinhole cam(w, h, 450.0, 376.0, 240.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> ux(-3.f, w + 3.f), uy(-3.f, h + 3.f);
  std::uniform_int_distribution<int> oct(0, 7);
  FeatureFrame in;
  in.width = w;
  in.height = h;
  for (int i = 0; i < 3000; ++i) {
    cv::KeyPoint kp(ux(rng), uy(rng), 31.f);
    kp.octave = oct(rng);
    if (i % 7 == 0 && !in.keypoints.empty()) kp.pt = in.keypoints.back().pt;  // duplicates in one cell
    in.keypoints.push_back(kp);
  }
  in.keypoints[5].pt.x = std::numeric_limits<float>::quiet_NaN();  // invalid: never returned
  in.descriptors = cv::Mat::zeros(static_cast<int>(in.keypoints.size()), 32, CV_8U);
  Frame f;
  std::string error;
  ASSERT_TRUE(Frame::fromFeatures(in, cam, 0, &f, &error)) << error;

  std::uniform_real_distribution<double> qu(-60.0, w + 60.0), qv(-60.0, h + 60.0), qr(0.5, 120.0);
  std::vector<int> fast;
  size_t total = 0;
  for (int q = 0; q < 5000; ++q) {
    const double u = qu(rng), v = qv(rng), r = qr(rng);
    const int lo = oct(rng) - 1, hi = lo + oct(rng) / 2;
    f.featuresInArea(u, v, r, lo, hi, &fast);
    ASSERT_EQ(plainFeaturesInArea(f, w, h, u, v, r, lo, hi), fast) << u << " " << v << " " << r;
    total += fast.size();
  }
  EXPECT_GT(total, 10000u);
  // A Frame copy searches the same.
  const Frame copy = f;
  copy.featuresInArea(100.0, 100.0, 40.0, 0, 7, &fast);
  EXPECT_EQ(plainFeaturesInArea(f, w, h, 100.0, 100.0, 40.0, 0, 7), fast);
}

// bundleAdjust computes each observation's error once before and once after the solve; the summary must equal the
// plain per-observation computations (reprojectionRmse, reprojectionError2 + chi2) on the same poses and points.
TEST(TrackingFastPaths, BundleAdjustSummaryMatchesPlainErrors) {
  for (bool fisheye : {false, true}) {
    std::unique_ptr<CameraModel> cam;
    if (fisheye)
      cam.reset(new test::TestFisheye(640, 480, 300.0, 320.0, 240.0));
    else
      cam.reset(new PinholeRadtan(640, 480, 450.0, 452.0, 320.0, 240.0, -0.2, 0.05, 1e-3, -1e-3));
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(3, 8);
    std::normal_distribution<double> nd(0.0, 1.0);
    std::vector<BAKeyframe> kfs(5);
    for (int k = 0; k < 5; ++k) {
      kfs[k].T_c_w = test::makePose({1.0 * k, -1.5 * k, 0.5 * k}, {0.2 * k, 0.03 * k, 0.02 * k}).inverse();
      kfs[k].fixed = k < 2;
    }
    std::vector<BAPoint> pts;
    std::vector<BAObservation> obs;
    for (int i = 0; i < 150; ++i) {
      BAPoint q;
      q.p_w = Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
      for (int k = 0; k < 5; ++k) {
        Eigen::Vector2d uv;
        if (!cam->project(kfs[k].T_c_w * q.p_w, &uv)) continue;
        obs.push_back({k, static_cast<int>(pts.size()), uv + 0.5 * Eigen::Vector2d(nd(rng), nd(rng)), 1.0 + (i % 3)});
      }
      pts.push_back(q);
    }
    for (auto& q : pts) q.p_w += 0.05 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    for (size_t j = 0; j < obs.size(); j += 40) obs[j].uv += Eigen::Vector2d(30, -25);  // outliers
    pts[7].p_w = kfs[0].T_c_w.inverse() * Eigen::Vector3d(0.1, 0.1, -2.0);               // behind keyframe 0
    const double rmse_before = reprojectionRmse(*cam, kfs, pts, obs);
    BAOptions opt;
    opt.max_num_iterations = 20;
    opt.max_solver_time_in_seconds = 100.0;
    BASummary sum;
    ASSERT_TRUE(bundleAdjust(*cam, &kfs, &pts, obs, opt, &sum));
    EXPECT_EQ(rmse_before, sum.initial_rmse_px);
    EXPECT_EQ(reprojectionRmse(*cam, kfs, pts, obs), sum.final_rmse_px);
    int n_outliers = 0;
    for (size_t j = 0; j < obs.size(); ++j) {
      const BAObservation& o = obs[j];
      const double e2 = reprojectionError2(*cam, kfs[o.keyframe].T_c_w, pts[o.point].p_w, o.uv);
      const bool outlier = e2 < 0 || e2 / (o.sigma * o.sigma) > opt.chi2_threshold;
      EXPECT_EQ(outlier, sum.outlier[j] != 0) << j;
      n_outliers += outlier;
    }
    EXPECT_GT(n_outliers, 0);
  }
}

// octaveSigma keeps the powers of the last scale factor: every value equals std::pow, also when scale factors
// alternate and for octaves past the table.
TEST(TrackingFastPaths, OctaveSigmaEqualsPow) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> scale(1.01, 2.5);
  std::uniform_int_distribution<int> octave(-3, 40);
  const double scales[] = {1.2, 1.2, scale(rng), 1.2, scale(rng), 2.0, 1.2};
  for (double s : scales)
    for (int k = 0; k < 200; ++k) {
      const int o = octave(rng);
      ASSERT_EQ(std::pow(s, std::max(0, o)), octaveSigma(s, o)) << s << " " << o;
    }
  Frame f;
  f.scale_factor = 1.2;
  for (int o = 0; o < 8; ++o) EXPECT_EQ(std::pow(1.2, o), f.sigma(o));
}

// The pose LM's normal equations: lower triangle and gradient exactly as Eigen's dense expressions, and the damped
// LDLT step from the mirrored matrix equal to the one from Eigen's full (not exactly symmetric) sum.
TEST(TrackingFastPaths, NormalEquationsLowerTriangleMatchDenseSum) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-300.0, 300.0), uw(0.05, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix<double, 6, 6> H_dense = Eigen::Matrix<double, 6, 6>::Zero(), H_fast = H_dense;
    Eigen::Matrix<double, 6, 1> g_dense = Eigen::Matrix<double, 6, 1>::Zero(), g_fast = g_dense;
    for (int obs = 0; obs < 60; ++obs) {
      Eigen::Matrix<double, 2, 6> Jp;
      for (int k = 0; k < 12; ++k) Jp.data()[k] = u(rng);
      const Eigen::Vector2d r(0.01 * u(rng), 0.01 * u(rng));
      const double w = obs % 3 ? 1.0 : uw(rng);
      H_dense.noalias() += w * Jp.transpose() * Jp;
      g_dense.noalias() += w * Jp.transpose() * r;
      addWeightedNormalEquations(Jp, r, w, &H_fast, &g_fast);
    }
    for (int i = 0; i < 6; ++i) {
      ASSERT_EQ(g_dense(i), g_fast(i));
      for (int j = 0; j <= i; ++j) ASSERT_EQ(H_dense(i, j), H_fast(i, j)) << i << "," << j;
    }
    copyLowerToUpper(&H_fast);
    for (int i = 0; i < 6; ++i)
      for (int j = i + 1; j < 6; ++j) ASSERT_EQ(H_fast(j, i), H_fast(i, j));
    for (double lambda : {1e-7, 1e-4, 1e-1, 10.0}) {
      Eigen::Matrix<double, 6, 6> A_dense = H_dense, A_fast = H_fast;
      A_dense.diagonal() += lambda * H_dense.diagonal().cwiseMax(1e-9);
      A_fast.diagonal() += lambda * H_fast.diagonal().cwiseMax(1e-9);
      const Eigen::Matrix<double, 6, 1> dx_dense = A_dense.ldlt().solve(-g_dense);
      const Eigen::Matrix<double, 6, 1> dx_fast = A_fast.ldlt().solve(-g_fast);
      for (int i = 0; i < 6; ++i) ASSERT_EQ(dx_dense(i), dx_fast(i)) << lambda;
    }
  }
}
