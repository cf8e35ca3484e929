// Two-view initialization, PnP, pose refinement and sliding-window BA on synthetic data, with a pinhole and an
// equidistant fisheye model.
#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/local_mapper.h"
#include "iraf_vo/tracking/multiview.h"
#include "iraf_vo/tracking/pose_optimization.h"
#include "iraf_vo/tracking/two_view.h"
#include "unit/tracking_test_utils.h"

#include <gtest/gtest.h>

using namespace iraf_vo;
using namespace iraf_vo::test;

namespace {

std::shared_ptr<CameraModel> makeCam(bool fisheye) {
  if (fisheye) return std::make_shared<TestFisheye>(752, 480, 250.0, 376.0, 240.0);
  return std::make_shared<TestPinhole>(752, 480, 458.0, 367.0, 248.0);
}

// Matched bearings of random 3D points seen from T1 = identity and T2 (pixel noise through the model).
void twoViews(const CameraModel& cam, const Eigen::Isometry3d& T2_c_w, bool planar, std::vector<Eigen::Vector3d>* b1,
              std::vector<Eigen::Vector3d>* b2, std::mt19937* rng) {
  std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(3, 7);
  std::normal_distribution<double> nd(0.0, 0.5);
  while (b1->size() < 300) {
    Eigen::Vector3d X(ux(*rng), uy(*rng), planar ? 5.0 : uz(*rng));
    Eigen::Vector2d u1, u2;
    const Eigen::Vector3d X2 = T2_c_w * X;
    if (!cam.project(X, &u1) || !cam.project(X2, &u2) || X2.z() < 0.5) continue;
    if (u1.x() < 0 || u1.y() < 0 || u1.x() >= cam.width() || u1.y() >= cam.height()) continue;
    if (u2.x() < 0 || u2.y() < 0 || u2.x() >= cam.width() || u2.y() >= cam.height()) continue;
    u1 += Eigen::Vector2d(nd(*rng), nd(*rng));
    u2 += Eigen::Vector2d(nd(*rng), nd(*rng));
    Eigen::Vector3d a, b;
    ASSERT_TRUE(cam.unproject(u1, &a));
    ASSERT_TRUE(cam.unproject(u2, &b));
    b1->push_back(a);
    b2->push_back(b);
  }
}

void checkInit(bool fisheye, bool planar) {
  auto cam = makeCam(fisheye);
  std::mt19937 rng(fisheye * 10 + planar);
  const Eigen::Isometry3d T2 = makePose({3.0, -4.0, 2.0}, {0.4, 0.05, 0.1});  // T_c2_c1
  std::vector<Eigen::Vector3d> b1, b2;
  twoViews(*cam, T2, planar, &b1, &b2, &rng);
  // 10 % gross outliers
  for (size_t i = 0; i < b2.size(); i += 10) std::swap(b2[i], b2[(i + 137) % b2.size()]);
  TwoViewParams p;
  const TwoViewResult r = initializeTwoView(b1, b2, cam->focal(), p);
  ASSERT_TRUE(r.ok) << r.reason;
  if (planar) {
    EXPECT_EQ(r.model, "homography");
  }
  EXPECT_LT(rotationErrorDeg(r.R_21, T2.rotation()), 0.5) << r.model;
  const double tdir = std::acos(std::clamp(r.t_21.normalized().dot(T2.translation().normalized()), -1.0, 1.0));
  EXPECT_LT(tdir * 180.0 / M_PI, 2.0) << r.model;
  EXPECT_GE(r.num_triangulated, 200);
  // Triangulated points are consistent with the true structure up to the scale of t.
  const double s = T2.translation().norm();
  int checked = 0;
  for (size_t i = 0; i < b1.size(); ++i) {
    if (!r.triangulated[i]) continue;
    EXPECT_LT(std::acos(std::clamp(r.points[i].normalized().dot(b1[i].normalized()), -1.0, 1.0)), 0.01);
    EXPECT_GT(r.points[i].z() * s, 2.0);
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

}  // namespace

TEST(TrackingGeometry, TwoViewInitPinholeGeneral) { checkInit(false, false); }
TEST(TrackingGeometry, TwoViewInitPinholePlanar) { checkInit(false, true); }
TEST(TrackingGeometry, TwoViewInitFisheyeGeneral) { checkInit(true, false); }

TEST(TrackingGeometry, TwoViewRejectsPureRotation) {
  auto cam = makeCam(false);
  std::mt19937 rng(3);
  std::vector<Eigen::Vector3d> b1, b2;
  twoViews(*cam, makePose({2.0, 3.0, 1.0}, {0, 0, 0}), false, &b1, &b2, &rng);
  const TwoViewResult r = initializeTwoView(b1, b2, cam->focal(), TwoViewParams());
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

namespace {

// A street seen by a forward-driving KITTI-like camera (1241x376, f 719): points on facades 4-8 m to the side
// and on the road, 4-40 m ahead; T2 = 1 m forward and a 0.5 deg yaw (10 Hz at 10 m/s). Most points are
// far or near the focus of expansion: the median parallax is below 1 deg, the 50 best points have more.
void streetViews(const CameraModel& cam, const Eigen::Isometry3d& T2_c_w, std::vector<Eigen::Vector3d>* b1,
                 std::vector<Eigen::Vector3d>* b2, std::mt19937* rng) {
  std::uniform_real_distribution<double> side(3, 8), up(-3, 1.6), ahead(4, 40), u01(0, 1);
  std::normal_distribution<double> nd(0.0, 0.5);
  while (b1->size() < 300) {
    const double r = u01(*rng);
    Eigen::Vector3d X = r < 0.4   ? Eigen::Vector3d(-side(*rng), up(*rng), ahead(*rng))
                        : r < 0.8 ? Eigen::Vector3d(side(*rng), up(*rng), ahead(*rng))
                                  : Eigen::Vector3d(u01(*rng) * 8 - 4, 1.65, ahead(*rng));  // road (y down)
    Eigen::Vector2d u1, u2;
    const Eigen::Vector3d X2 = T2_c_w * X;
    if (!cam.project(X, &u1) || !cam.project(X2, &u2) || X2.z() < 1.0) continue;
    if (u1.x() < 0 || u1.y() < 0 || u1.x() >= cam.width() || u1.y() >= cam.height()) continue;
    if (u2.x() < 0 || u2.y() < 0 || u2.x() >= cam.width() || u2.y() >= cam.height()) continue;
    Eigen::Vector3d a, b;
    ASSERT_TRUE(cam.unproject(u1 + Eigen::Vector2d(nd(*rng), nd(*rng)), &a));
    ASSERT_TRUE(cam.unproject(u2 + Eigen::Vector2d(nd(*rng), nd(*rng)), &b));
    b1->push_back(a);
    b2->push_back(b);
  }
}

}  // namespace

// Forward motion initializes with the ORB-SLAM parallax test (the 50th best point >= 1 deg; median >= 0.5 deg),
// not with the median rule (median >= 1 deg).
TEST(TrackingGeometry, TwoViewInitForwardMotion) {
  TestPinhole cam(1241, 376, 719.0, 607.0, 185.0);
  std::mt19937 rng(21);
  const Eigen::Isometry3d T2 = makePose({0.0, 0.5, 0.0}, {0.0, 0.0, -1.0});  // T_c2_c1: camera 1 m forward
  std::vector<Eigen::Vector3d> b1, b2;
  streetViews(cam, T2, &b1, &b2, &rng);
  TwoViewParams p;
  const TwoViewResult r = initializeTwoView(b1, b2, cam.focal(), p);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_LT(r.median_parallax_deg, 1.0);  // the old median rule would have refused
  EXPECT_GE(r.median_parallax_deg, 0.5);
  EXPECT_GE(r.parallax_deg, 1.0);
  EXPECT_LT(rotationErrorDeg(r.R_21, T2.rotation()), 0.3);
  const double tdir = std::acos(std::clamp(r.t_21.normalized().dot(T2.translation().normalized()), -1.0, 1.0));
  EXPECT_LT(tdir * 180.0 / M_PI, 10.0);  // 1 m baseline, 0.5 px noise: the direction of t is weakly observed (~6 deg)
  p.min_parallax_points = 0;  // median rule
  p.determined_parallax_points = 0;  // alone
  const TwoViewResult median_rule = initializeTwoView(b1, b2, cam.focal(), p);
  EXPECT_FALSE(median_rule.ok);
  EXPECT_NE(median_rule.reason.find("parallax too low"), std::string::npos) << median_rule.reason;
}

// A camera standing still (pixel noise only) and a camera only rotating (fast pan) must not initialize with the
// default parallax test (1 deg on the 50th best point). Measured: 0.5 deg is not enough, the 3 deg pan then
// initializes through a homography with a wrong translation.
TEST(TrackingGeometry, TwoViewRefusesNoParallax) {
  for (const bool fisheye : {false, true}) {
    auto cam = makeCam(fisheye);
    for (const Eigen::Vector3d& rpy : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.5, 3.0, 0.2)}) {
      std::mt19937 rng(5);
      std::vector<Eigen::Vector3d> b1, b2;
      twoViews(*cam, makePose(rpy, {0, 0, 0}), false, &b1, &b2, &rng);
      const TwoViewResult r = initializeTwoView(b1, b2, cam->focal(), TwoViewParams());
      EXPECT_FALSE(r.ok) << "fisheye " << fisheye << " rotation " << rpy.transpose() << ": " << r.model;
    }
  }
}

TEST(TrackingGeometry, TriangulateBearings) {
  const Eigen::Isometry3d T1 = makePose({0, 0, 0}, {0, 0, 0}), T2 = makePose({0, 5, 0}, {-0.5, 0, 0});
  const Eigen::Vector3d X(0.3, -0.2, 4.0);
  Eigen::Vector3d Y;
  ASSERT_TRUE(triangulateBearings(T1, (T1 * X).normalized(), T2, (T2 * X).normalized(), &Y));
  EXPECT_LT((X - Y).norm(), 1e-9);
  EXPECT_GT(parallaxAngle(T1, T2, X), 0.05);
}

TEST(TrackingGeometry, PnPWithOutliers) {
  for (bool fisheye : {false, true}) {
    auto cam = makeCam(fisheye);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(2, 8), upx(0, 700);
    std::normal_distribution<double> nd(0.0, 0.5);
    const Eigen::Isometry3d T_c_w = makePose({5, -10, 20}, {0.3, -0.2, 0.5});
    std::vector<Eigen::Vector3d> P, B;
    std::vector<bool> is_outlier;
    while (P.size() < 200) {
      const Eigen::Vector3d Xc(ux(rng), uy(rng), uz(rng));
      Eigen::Vector2d uv;
      if (!cam->project(Xc, &uv) || uv.x() < 0 || uv.y() < 0 || uv.x() >= 752 || uv.y() >= 480) continue;
      const bool outlier = P.size() % 10 < 3;  // 30 %
      if (outlier) uv = Eigen::Vector2d(upx(rng), upx(rng) * 480 / 700);
      uv += Eigen::Vector2d(nd(rng), nd(rng));
      Eigen::Vector3d b;
      ASSERT_TRUE(cam->unproject(uv, &b));
      P.push_back(T_c_w.inverse() * Xc);
      B.push_back(b);
      is_outlier.push_back(outlier);
    }
    Eigen::Isometry3d T;
    std::vector<char> inl;
    const int n = solvePnPBearings(P, B, cam->focal(), 2.0, 300, &T, &inl);
    EXPECT_GE(n, 120) << cam->modelName();
    EXPECT_LT(rotationErrorDeg(T.rotation(), T_c_w.rotation()), 0.3) << cam->modelName();
    EXPECT_LT((T.translation() - T_c_w.translation()).norm(), 0.03) << cam->modelName();
    int wrong = 0;
    for (size_t i = 0; i < P.size(); ++i) wrong += inl[i] && is_outlier[i];
    EXPECT_LE(wrong, 3);

    // Pose-only Ceres refinement from a perturbed start rejects the outliers (chi2).
    std::vector<Eigen::Vector2d> uv;
    std::vector<double> sg(P.size(), 1.0);
    for (const auto& b : B) {
      Eigen::Vector2d u;
      cam->project(b, &u);
      uv.push_back(u);
    }
   for (bool ceres_solver : {false, true}) {
    SCOPED_TRACE(ceres_solver ? "ceres" : "eigen LM");
    Eigen::Isometry3d T0 = makePose({1, 1, -1}, {0.05, 0.05, -0.05}) * T_c_w;
    std::vector<char> inl2(P.size(), 1);
    PoseOptimizationOptions po;
    po.use_ceres = ceres_solver;
    const int n2 = optimizePose(*cam, P, uv, sg, po, &T0, &inl2);
    EXPECT_GE(n2, 120);
    EXPECT_LT(rotationErrorDeg(T0.rotation(), T_c_w.rotation()), 0.3);
    EXPECT_LT((T0.translation() - T_c_w.translation()).norm(), 0.03);
    int wrong2 = 0;
    for (size_t i = 0; i < P.size(); ++i) wrong2 += inl2[i] && is_outlier[i];
    EXPECT_LE(wrong2, 3);
   }
  }
}

TEST(TrackingGeometry, BundleAdjustmentConverges) {
  for (bool fisheye : {false, true}) {
    auto cam = makeCam(fisheye);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> ux(-3, 3), uy(-2, 2), uz(3, 8);
    std::normal_distribution<double> nd(0.0, 1.0);
    std::vector<BAKeyframe> kfs(6), truth_kfs;
    for (int k = 0; k < 6; ++k) {
      kfs[k].T_c_w = makePose({1.0 * k, -2.0 * k, 0.5 * k}, {0.2 * k, 0.03 * k, 0.02 * k}).inverse();
      kfs[k].fixed = k < 2;
    }
    truth_kfs = kfs;
    std::vector<BAPoint> pts, truth_pts;
    std::vector<BAObservation> obs;
    for (int i = 0; i < 200; ++i) {
      BAPoint q;
      q.p_w = Eigen::Vector3d(ux(rng), uy(rng), uz(rng));
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector2d uv;
        if (!cam->project(kfs[k].T_c_w * q.p_w, &uv)) continue;
        obs.push_back({k, static_cast<int>(pts.size()), uv + 0.3 * Eigen::Vector2d(nd(rng), nd(rng)), 1.0});
      }
      pts.push_back(q);
    }
    truth_pts = pts;
    // Perturb the free poses and all points.
    for (int k = 2; k < 6; ++k)
      kfs[k].T_c_w = makePose({0.5 * nd(rng), 0.5 * nd(rng), 0.5 * nd(rng)}, 0.03 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng))) *
                     kfs[k].T_c_w;
    for (auto& q : pts) q.p_w += 0.05 * Eigen::Vector3d(nd(rng), nd(rng), nd(rng));
    // A few gross outliers (handled by the Huber loss, flagged by chi2).
    for (size_t j = 0; j < obs.size(); j += 50) obs[j].uv += Eigen::Vector2d(40, -30);
    const double before = reprojectionRmse(*cam, kfs, pts, obs);
    BAOptions opt;
    opt.max_num_iterations = 50;
    opt.max_solver_time_in_seconds = 5.0;
    BASummary sum;
    ASSERT_TRUE(bundleAdjust(*cam, &kfs, &pts, obs, opt, &sum));
    // RMSE over the inlier observations
    std::vector<BAObservation> clean;
    int flagged_outliers = 0;
    for (size_t j = 0; j < obs.size(); ++j) {
      if (j % 50 == 0) {
        flagged_outliers += sum.outlier[j];
        continue;
      }
      clean.push_back(obs[j]);
    }
    const double after = reprojectionRmse(*cam, kfs, pts, clean);
    EXPECT_GT(before, 5.0);
    EXPECT_LT(after, 0.5) << cam->modelName();
    EXPECT_GE(flagged_outliers, static_cast<int>(obs.size() / 50) - 1);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LT((kfs[k].T_c_w.matrix() - truth_kfs[k].T_c_w.matrix()).norm(), 1e-12) << "fixed keyframe moved";
    }
    for (int k = 2; k < 6; ++k) {
      EXPECT_LT(rotationErrorDeg(kfs[k].T_c_w.rotation(), truth_kfs[k].T_c_w.rotation()), 0.2);
      EXPECT_LT((kfs[k].T_c_w.translation() - truth_kfs[k].T_c_w.translation()).norm(), 0.04) << cam->modelName();
    }
  }
}

// A fisheye sees ~90 deg off its axis: a point just in front of the start pose's image plane, just behind the true
// pose's (a match on the edge of the view that agrees with the start pose), does not project at trial poses towards
// the truth. The refinement drops it from the solve and reaches the true pose from the other points' observations
// (rejecting those trials instead left the pose at the start); it is then classified an outlier.
TEST(TrackingGeometry, PoseRefinementDropsAPointThatLeavesTheView) {
  {
    auto cam = makeCam(true);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-2, 2), uy(-1.5, 1.5), uz(3, 8);
    std::normal_distribution<double> nd(0.0, 0.5);
    const Eigen::Isometry3d T_c_w = makePose({2, -1, 3}, {0.1, -0.2, 0.3});
    const Eigen::Isometry3d T_start = makePose({2, 2, -1}, {0.03, 0.03, 0.0}) * T_c_w;
    std::vector<Eigen::Vector3d> P;
    std::vector<Eigen::Vector2d> uv;
    while (P.size() < 80) {
      const Eigen::Vector3d Xc(ux(rng), uy(rng), uz(rng));
      Eigen::Vector2d u;
      if (!cam->project(Xc, &u)) continue;
      P.push_back(T_c_w.inverse() * Xc);
      uv.push_back(u + Eigen::Vector2d(nd(rng), nd(rng)));
    }
    // 1 cm in front of the start pose's image plane, 3 m to the side where the true camera sees it most behind.
    Eigen::Vector3d X_edge;
    double z_true = 1.0;
    for (int k = 0; k < 16; ++k) {
      const double a = k * M_PI / 8;
      const Eigen::Vector3d X = T_start.inverse() * Eigen::Vector3d(3.0 * std::cos(a), 3.0 * std::sin(a), 0.01);
      if ((T_c_w * X).z() < z_true) z_true = (T_c_w * (X_edge = X)).z();
    }
    ASSERT_LT(z_true, -0.01);
    Eigen::Vector2d u_edge;
    ASSERT_TRUE(cam->project(T_start * X_edge, &u_edge));
    P.push_back(X_edge);
    uv.push_back(u_edge);  // agrees with the start pose: the match pulls towards it
    std::vector<double> sg(P.size(), 1.0);
    std::vector<char> inl(P.size(), 1);
    Eigen::Isometry3d T = T_start;
    const int n = optimizePose(*cam, P, uv, sg, PoseOptimizationOptions(), &T, &inl);
    EXPECT_GE(n, 75);
    EXPECT_LT(rotationErrorDeg(T.rotation(), T_c_w.rotation()), 0.1);
    EXPECT_LT((T.translation() - T_c_w.translation()).norm(), 0.01);
    EXPECT_FALSE(inl.back());
  }
}

// A new point's match is kept only when its distances from the two keyframes agree with the keypoints' octaves:
// a corner found at octave o from distance d is found at octave 0 from d * sigma(o).
TEST(TrackingGeometry, NewPointScaleConsistency) {
  const double sf = 1.2;
  const auto ratio = [sf](int o1, int o2) { return std::pow(sf, o1) / std::pow(sf, o2); };
  // True matches: same octave from about the same distance; two octaves apart from 1.44x the distance.
  EXPECT_TRUE(scaleConsistent(300.0, 295.0, ratio(0, 0), sf));
  EXPECT_TRUE(scaleConsistent(10.0, 14.4, ratio(2, 0), sf));
  EXPECT_TRUE(scaleConsistent(14.4, 10.0, ratio(0, 2), sf));
  // Wrong matches: the same distance but five octaves apart; the octaves say the point came closer, the
  // triangulated distances say it went 2.5x farther.
  EXPECT_FALSE(scaleConsistent(60.0, 58.0, ratio(0, 5), sf));
  EXPECT_FALSE(scaleConsistent(60.0, 58.0, ratio(5, 0), sf));
  EXPECT_FALSE(scaleConsistent(10.0, 25.0, ratio(0, 2), sf));
  // No distance: refused, never a division by zero.
  EXPECT_FALSE(scaleConsistent(0.0, 10.0, 1.0, sf));
  EXPECT_FALSE(scaleConsistent(10.0, 0.0, 1.0, sf));
}
