// Simulator renderer: determinism, reprojection of ray hits, depth of a known plane, FAST corner
// stability between consecutive frames, trajectory constraints (trackable by a monocular VO).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <memory>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/renderer.h"
#include "iraf_vo/sim/scene.h"
#include "iraf_vo/sim/sequence.h"

namespace {

using iraf_vo::Renderer;
using iraf_vo::Scene;
using iraf_vo::SceneParams;
using iraf_vo::SimParams;
using iraf_vo::TrajectoryParams;

/// The default room (texture generation ~1 s), built once for the whole binary.
std::shared_ptr<const Scene> defaultRoom(uint64_t seed = 1) {
  static std::shared_ptr<const Scene> room;
  if (seed != 1) {
    SceneParams p;
    p.seed = seed;
    p.texels_per_m = 128;
    return std::make_shared<const Scene>(Scene::makeDefaultRoom(p));
  }
  if (!room) {
    SceneParams p;
    p.photo_dir = IRAF_VO_OPENCV_DATA;
    room = std::make_shared<const Scene>(Scene::makeDefaultRoom(p));
  }
  return room;
}

iraf_vo::CameraModelPtr camera(const std::string& name, int w = 0, int h = 0) {
  std::string err;
  auto cam = iraf_vo::makeSimCamera(name, w, h, &err);
  EXPECT_TRUE(cam) << err;
  return cam;
}

cv::Mat toU8(const cv::Mat& radiance) {
  cv::Mat u8;
  radiance.convertTo(u8, CV_8U);
  return u8;
}

TEST(SimRender, DeterministicForASeed) {
  SceneParams p;
  p.texels_per_m = 128;  // small textures: fast
  p.seed = 7;
  auto a = std::make_shared<const Scene>(Scene::makeDefaultRoom(p));
  auto b = std::make_shared<const Scene>(Scene::makeDefaultRoom(p));
  p.seed = 8;
  auto c = std::make_shared<const Scene>(Scene::makeDefaultRoom(p));
  SimParams sp;
  auto cam = camera("pinhole", 188, 120);
  TrajectoryParams traj;
  cv::Mat ia, ib, ic;
  Renderer(cam, a, sp).renderFrame(traj, 5, &ia);
  SimParams sp1 = sp;
  sp1.threads = 1;  // single- and multi-threaded renders agree exactly
  Renderer(cam, b, sp1).renderFrame(traj, 5, &ib);
  Renderer(cam, c, sp).renderFrame(traj, 5, &ic);
  EXPECT_EQ(cv::norm(ia, ib, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(ia, ic, cv::NORM_L1) / ia.total(), 5.0) << "a different seed must give other textures";
  // Photometric events with noise are deterministic too.
  iraf_vo::PhotometricParams ph;
  ASSERT_TRUE(iraf_vo::photometricPreset("mixed", 100, false, 3, &ph));
  cv::Mat o1, o2;
  iraf_vo::applyPhotometric(ia, 42, ph, &o1);
  iraf_vo::applyPhotometric(ia, 42, ph, &o2);
  EXPECT_EQ(cv::norm(o1, o2, cv::NORM_INF), 0.0);
}

TEST(SimRender, SpanRendererMatchesReferencePath) {
  // The vectorized 16-pixel span renderer and the per-ray reference (Scene::castRay + Scene::shade)
  // compute the same image and depth.
  for (const char* name : {"pinhole", "fisheye"}) {
    auto cam = camera(name, 200, 150);
    SimParams a, b;
    b.span_renderer = false;
    cv::Mat ia, ib, da, db;
    const Eigen::Isometry3d T = iraf_vo::trajectoryPose(TrajectoryParams(), 2.3);
    Renderer(cam, defaultRoom(), a).render(T, &ia, &da);
    Renderer(cam, defaultRoom(), b).render(T, &ib, &db);
    cv::Mat diff = cv::abs(ia - ib);
    EXPECT_LT(cv::countNonZero(diff > 1.0), 0.002 * ia.total()) << name;  // rounding at face borders only
    EXPECT_LT(cv::mean(diff)[0], 0.05) << name;
    EXPECT_LT(cv::countNonZero(cv::abs(da - db) > 1e-3f), 0.002 * da.total()) << name;
  }
}

TEST(SimRender, ImageHasTextureAndReasonableBrightness) {
  auto cam = camera("pinhole");
  Renderer r(cam, defaultRoom(), SimParams());
  cv::Mat rad;
  r.renderFrame(TrajectoryParams(), 0, &rad);
  cv::Scalar mean, stddev;
  cv::meanStdDev(rad, mean, stddev);
  EXPECT_GT(mean[0], 60.0);
  EXPECT_LT(mean[0], 170.0);
  EXPECT_GT(stddev[0], 20.0);
  std::vector<cv::KeyPoint> kps;
  cv::FAST(toU8(rad), kps, 20);
  EXPECT_GT(kps.size(), 300u) << "the textures must give FAST corners";
}

void checkReprojection(const std::string& cam_name) {
  auto cam = camera(cam_name);
  Renderer r(cam, defaultRoom(), SimParams());
  const TrajectoryParams traj;
  int checked = 0;
  for (int frame : {0, 37, 150}) {
    const Eigen::Isometry3d T_W_C = iraf_vo::trajectoryPose(traj, r.frameTime(frame));
    for (double fu : {0.1, 0.3, 0.5, 0.77, 0.93})
      for (double fv : {0.12, 0.5, 0.88}) {
        const Eigen::Vector2d uv(fu * (cam->width() - 1), fv * (cam->height() - 1));
        Eigen::Vector3d p_W;
        double depth = 0;
        ASSERT_TRUE(r.castPixel(T_W_C, uv, &p_W, &depth)) << cam_name << " pixel " << uv.transpose();
        const Eigen::Vector3d p_C = T_W_C.inverse() * p_W;
        EXPECT_NEAR(p_C.z(), depth, 1e-6);
        Eigen::Vector2d back;
        ASSERT_TRUE(cam->project(p_C, &back)) << cam_name << " " << p_C.transpose();
        EXPECT_LT((back - uv).norm(), 1e-3) << cam_name << " pixel " << uv.transpose() << " -> " << back.transpose();
        // The hit lies on a surface of the scene (inside the room, on a face of it or of a box).
        const Eigen::Vector3f lo = r.scene().roomLo(), hi = r.scene().roomHi();
        EXPECT_TRUE((p_W.cast<float>().array() >= lo.array() - 1e-3f).all() &&
                    (p_W.cast<float>().array() <= hi.array() + 1e-3f).all());
        ++checked;
      }
  }
  EXPECT_EQ(checked, 45);
}

TEST(SimRender, HitPointsReprojectPinhole) { checkReprojection("pinhole"); }
TEST(SimRender, HitPointsReprojectFisheye) { checkReprojection("fisheye"); }

TEST(SimRender, DepthMapOfAKnownPlane) {
  // Empty 8 x 6 x 3 room, camera at (0, 0, 1.5) looking along +x: the wall x = 4 is at depth 4.
  SceneParams p;
  std::vector<iraf_vo::SceneTexture> tex;
  for (int i = 0; i < 6; ++i) tex.emplace_back(iraf_vo::makeProceduralTexture(64, 64, 32, i), 32.f);
  auto scene = std::make_shared<const Scene>(p, tex, std::vector<iraf_vo::SceneBox>{});
  auto cam = camera("pinhole", 376, 240);
  Renderer r(cam, scene, SimParams());
  Eigen::Isometry3d T_W_C = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d R;
  R << 0, 0, 1,  // camera z -> world x, camera x -> world -y, camera y -> world -z
      -1, 0, 0,
      0, -1, 0;
  T_W_C.linear() = R;
  T_W_C.translation() = Eigen::Vector3d(0, 0, 1.5);
  cv::Mat rad, depth;
  r.render(T_W_C, &rad, &depth);
  ASSERT_EQ(depth.type(), CV_32FC1);
  int wall = 0, other = 0;
  for (int v = 0; v < depth.rows; v += 3)
    for (int u = 0; u < depth.cols; u += 3) {
      Eigen::Vector3d b;
      ASSERT_TRUE(cam->unproject(Eigen::Vector2d(u, v), &b));
      const Eigen::Vector3d d = R * b;
      // Analytic intersection with the planes x = 4, y = +-3, z = 0, z = 3 (first hit).
      double t = 4.0 / d.x();
      if (d.y() != 0) t = std::min(t, 3.0 / std::abs(d.y()));
      if (d.z() < 0) t = std::min(t, 1.5 / -d.z());
      if (d.z() > 0) t = std::min(t, 1.5 / d.z());
      const double expected = t * b.z();
      EXPECT_NEAR(depth.at<float>(v, u), expected, 2e-3 * expected) << "pixel " << u << "," << v;
      (std::abs(expected - 4.0) < 1e-9 ? wall : other)++;
    }
  EXPECT_GT(wall, other) << "most of the image sees the wall x = 4 (depth 4)";
  EXPECT_NEAR(depth.at<float>(120, 188), 4.0f, 1e-3f);
}

TEST(SimRender, FastCornersStableBetweenFrames) {
  auto cam = camera("pinhole");
  Renderer r(cam, defaultRoom(), SimParams());
  const TrajectoryParams traj;
  iraf_vo::PhotometricParams clean;
  ASSERT_TRUE(iraf_vo::photometricPreset("clean", 400, false, 1, &clean));
  int total = 0, good = 0, tracked = 0, repeated = 0;
  for (int k : {10, 120, 250}) {
    cv::Mat rad0, rad1, img0, img1;
    r.renderFrame(traj, k, &rad0);
    r.renderFrame(traj, k + 1, &rad1);
    iraf_vo::applyPhotometric(rad0, k, clean, &img0);
    iraf_vo::applyPhotometric(rad1, k + 1, clean, &img1);
    std::vector<cv::KeyPoint> kps;
    cv::FAST(img0, kps, 25, true);
    cv::KeyPointsFilter::retainBest(kps, 300);
    ASSERT_GT(kps.size(), 100u) << "frame " << k;
    std::vector<cv::KeyPoint> kps1;
    cv::FAST(img1, kps1, 25, true);
    const Eigen::Isometry3d T0 = iraf_vo::trajectoryPose(traj, r.frameTime(k));
    const Eigen::Isometry3d T1 = iraf_vo::trajectoryPose(traj, r.frameTime(k + 1));
    const int half = 7, search = 4;
    for (const cv::KeyPoint& kp : kps) {
      Eigen::Vector3d p_W;
      if (!r.castPixel(T0, Eigen::Vector2d(kp.pt.x, kp.pt.y), &p_W)) continue;
      Eigen::Vector2d pred;
      if (!cam->project(T1.inverse() * p_W, &pred) || !cam->isInImage(pred, 16) ||
          !cam->isInImage(Eigen::Vector2d(kp.pt.x, kp.pt.y), 16))
        continue;
      ++total;
      // Repeatability: frame k+1 has a FAST corner where the ground truth moves this one.
      for (const cv::KeyPoint& q : kps1)
        if (std::hypot(q.pt.x - pred.x(), q.pt.y - pred.y()) < 1.5) {
          ++repeated;
          break;
        }
      // Tracking: the 15x15 patch of frame k found in frame k+1 (normalized cross-correlation, sub-pixel
      // parabola) within 1 px of the ground-truth prediction.
      const cv::Rect patch(cvRound(kp.pt.x) - half, cvRound(kp.pt.y) - half, 2 * half + 1, 2 * half + 1);
      const cv::Point c(cvRound(pred.x()), cvRound(pred.y()));
      const cv::Rect area(c.x - half - search, c.y - half - search, 2 * (half + search) + 1, 2 * (half + search) + 1);
      cv::Mat score;
      cv::matchTemplate(img1(area), img0(patch), score, cv::TM_CCOEFF_NORMED);
      double best;
      cv::Point m;
      cv::minMaxLoc(score, nullptr, &best, nullptr, &m);
      if (best < 0.8) continue;
      ++tracked;
      auto sub = [&](int x, int y, bool horiz) {
        const int x0 = horiz ? x - 1 : x, y0 = horiz ? y : y - 1, x2 = horiz ? x + 1 : x, y2 = horiz ? y : y + 1;
        if (x0 < 0 || y0 < 0 || x2 >= score.cols || y2 >= score.rows) return 0.0;
        const double a = score.at<float>(y0, x0), b = score.at<float>(y, x), cc = score.at<float>(y2, x2);
        const double den = a - 2 * b + cc;
        return std::abs(den) > 1e-9 ? 0.5 * (a - cc) / den : 0.0;
      };
      const double tx = area.x + half + m.x + sub(m.x, m.y, true) + (kp.pt.x - cvRound(kp.pt.x));
      const double ty = area.y + half + m.y + sub(m.x, m.y, false) + (kp.pt.y - cvRound(kp.pt.y));
      if (std::hypot(tx - pred.x(), ty - pred.y()) < 1.0) ++good;
    }
  }
  ASSERT_GT(total, 300);
  EXPECT_GT(tracked, 0.9 * total);
  EXPECT_GT(repeated, 0.7 * total) << repeated << " of " << total << " FAST corners re-detected at the GT position";
  // Corners sit on texture features, not on rendering artefacts: LK agrees with the ground-truth motion.
  EXPECT_GT(good, 0.85 * tracked) << good << " of " << tracked << " tracked corners within 1 px of the GT motion";
  std::cout << "FAST stability: " << total << " corners, " << repeated << " re-detected (1.5 px), " << tracked
            << " matched, " << good << " within 1 px of the GT motion\n";
}

TEST(SimTrajectory, TrackableByMonocularVo) {
  const TrajectoryParams traj;
  auto cam = camera("pinhole", 188, 120);
  Renderer r(cam, defaultRoom(), SimParams());
  const int n = 400;
  double max_rot_deg = 0, min_step = 1e9, min_med = 1e9, max_med = 0;
  for (int i = 0; i + 1 < n; ++i) {
    const Eigen::Isometry3d a = iraf_vo::trajectoryPose(traj, r.frameTime(i));
    const Eigen::Isometry3d b = iraf_vo::trajectoryPose(traj, r.frameTime(i + 1));
    max_rot_deg = std::max(max_rot_deg, Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180 / M_PI);
    min_step = std::min(min_step, (b.translation() - a.translation()).norm());
    // The camera stays inside the room, away from the boxes.
    const Eigen::Vector3f c = a.translation().cast<float>();
    for (const auto& box : r.scene().boxes()) {
      const Eigen::Vector3f q = c.cwiseMax(box.lo).cwiseMin(box.hi);
      EXPECT_GT((q - c).norm(), 0.8f) << "frame " << i;
    }
    if (i % 20 == 0) {
      // Median depth of a grid of pixels: textured surfaces 1.5-6 m away.
      std::vector<double> depths;
      for (int v = 10; v < 120; v += 20)
        for (int u = 10; u < 188; u += 20) {
          Eigen::Vector3d p;
          double z;
          if (r.castPixel(a, Eigen::Vector2d(u, v), &p, &z)) depths.push_back(z);
        }
      ASSERT_FALSE(depths.empty());
      std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
      const double med = depths[depths.size() / 2];
      min_med = std::min(min_med, med), max_med = std::max(max_med, med);
      EXPECT_GT(med, 1.5) << "frame " << i;
      EXPECT_LT(med, 6.0) << "frame " << i;
    }
  }
  std::cout << "trajectory: max rotation " << max_rot_deg << " deg/frame, min translation " << min_step
            << " m/frame, median depth " << min_med << " .. " << max_med << " m\n";
  EXPECT_LT(max_rot_deg, 1.5);
  EXPECT_GT(min_step, 0.005) << "translation from the first frames (monocular initialization)";
}

TEST(SimRender, BadInputIsRejected) {
  SimParams bad;
  bad.supersample = 0;
  EXPECT_FALSE(iraf_vo::validate(bad).empty());
  EXPECT_THROW(Renderer(nullptr, defaultRoom(), SimParams()), std::invalid_argument);
  EXPECT_THROW(Renderer(camera("pinhole", 64, 40), defaultRoom(), bad), std::invalid_argument);
  EXPECT_THROW(iraf_vo::SceneTexture(cv::Mat(100, 64, CV_8UC1), 64.f), std::invalid_argument);
  std::string err;
  EXPECT_FALSE(iraf_vo::makeSimCamera("/nonexistent/sensor.yaml", 0, 0, &err));
  EXPECT_NE(err.find("/nonexistent/sensor.yaml"), std::string::npos) << err;
  // A ray from outside the room or with a NaN direction: no hit, no crash.
  iraf_vo::SceneHit hit;
  EXPECT_FALSE(defaultRoom()->castRay(Eigen::Vector3f(100, 0, 1), Eigen::Vector3f(1, 0, 0), &hit));
  EXPECT_FALSE(defaultRoom()->castRay(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(NAN, 0, 0), &hit));
  // A camera outside the room or a NaN pose renders black (no crash).
  {
    Renderer r(camera("pinhole", 64, 40), defaultRoom(), SimParams());
    cv::Mat img, depth;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(50, 0, 1);
    r.render(T, &img, &depth);
    EXPECT_EQ(cv::countNonZero(img), 0);
    T.translation() = Eigen::Vector3d(NAN, 0, 1);
    r.render(T, &img, &depth);
    EXPECT_EQ(cv::countNonZero(img), 0);
    EXPECT_EQ(cv::countNonZero(depth), 0);
  }
  // Axis-parallel rays (exactly zero components) hit the right face.
  ASSERT_TRUE(defaultRoom()->castRay(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(-1, 0, 0), &hit));
  EXPECT_NEAR(hit.point.x(), -4.f, 1e-4f);
  ASSERT_TRUE(defaultRoom()->castRay(Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 0, -1), &hit));
  EXPECT_NEAR(hit.t, 1.f, 1e-5f);
  EXPECT_EQ(hit.surface, 4);  // floor
  EXPECT_FLOAT_EQ(hit.normal.z(), 1.f);
}

TEST(SimRender, SupersamplingAndMotionBlur) {
  auto cam = camera("pinhole", 188, 120);
  SimParams sp;
  cv::Mat a, b, c;
  Renderer(cam, defaultRoom(), sp).renderFrame(TrajectoryParams(), 3, &a);
  sp.supersample = 2;
  Renderer(cam, defaultRoom(), sp).renderFrame(TrajectoryParams(), 3, &b);
  // Same image content, slightly different anti-aliasing.
  EXPECT_LT(cv::norm(a, b, cv::NORM_L1) / a.total(), 8.0);
  sp.supersample = 1;
  sp.motion_blur_samples = 6;
  sp.exposure_time_s = 0.05;
  TrajectoryParams fast;
  fast.speed = 4.0;
  cv::Mat sharp;
  Renderer(cam, defaultRoom(), SimParams()).renderFrame(fast, 3, &sharp);
  Renderer(cam, defaultRoom(), sp).renderFrame(fast, 3, &c);
  cv::Mat gs, gc;
  cv::Laplacian(sharp, gs, CV_32F);
  cv::Laplacian(c, gc, CV_32F);
  EXPECT_LT(cv::norm(gc), 0.8 * cv::norm(gs)) << "motion blur removes high frequencies";
}

}  // namespace
