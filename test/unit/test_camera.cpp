// Camera models: round trip, analytic Jacobians, agreement with OpenCV, yaml loading and error reporting, and
// callers that ask a model its kind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <random>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/camera/kannala_brandt.h"
#include "iraf_vo/camera/pinhole_radtan.h"
#include "iraf_vo/pipeline/pipeline_params.h"

using namespace iraf_vo;

#include "common/tmp_dir.h"

namespace {

PinholeRadtan euroc() {
  return PinholeRadtan(752, 480, 458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                       1.76187114e-05);
}
KannalaBrandt tumvi() {
  return KannalaBrandt(512, 512, 190.978477, 190.973307, 254.931706, 256.897442, 0.0034823894022493434,
                       0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182);
}

std::string tmpPath(const std::string& name) {
  return tmpRoot() + "iraf_vo_cam_" + name;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}

/// Every pixel of a 4-px grid (plus the exact corners) unprojects, and projects back within 1e-6 px.
void checkRoundTrip(const CameraModel& cam) {
  double max_err = 0.0;
  int n = 0;
  std::vector<double> us, vs;
  for (int u = 0; u < cam.width(); u += 4) us.push_back(u);
  for (int v = 0; v < cam.height(); v += 4) vs.push_back(v);
  us.push_back(cam.width() - 1);
  vs.push_back(cam.height() - 1);
  for (double u : us) {
    for (double v : vs) {
      const Eigen::Vector2d uv(u + 0.25, v + 0.75);
      Eigen::Vector3d b;
      ASSERT_TRUE(cam.unproject(uv, &b)) << cam.modelName() << " at " << uv.transpose();
      EXPECT_NEAR(b.norm(), 1.0, 1e-12);
      Eigen::Vector2d uv2;
      // Scale must not matter.
      ASSERT_TRUE(cam.project(3.7 * b, &uv2)) << cam.modelName() << " at " << uv.transpose();
      max_err = std::max(max_err, (uv2 - uv).norm());
      ++n;
    }
  }
  EXPECT_LT(max_err, 1e-6) << cam.modelName() << " over " << n << " pixels";
}

void checkJacobian(const CameraModel& cam, const std::vector<Eigen::Vector3d>& pts) {
  for (const Eigen::Vector3d& p : pts) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    ASSERT_TRUE(cam.project(p, &uv, &J)) << p.transpose();
    Eigen::Matrix<double, 2, 3> Jn;
    const double h = 1e-6 * std::max(1.0, p.norm());
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dp = Eigen::Vector3d::Zero();
      dp[k] = h;
      Eigen::Vector2d up, um;
      ASSERT_TRUE(cam.project(p + dp, &up));
      ASSERT_TRUE(cam.project(p - dp, &um));
      Jn.col(k) = (up - um) / (2.0 * h);
    }
    EXPECT_LT((J - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << cam.modelName() << " at " << p.transpose()
                                                                 << "\nanalytic\n" << J << "\nnumeric\n" << Jn;
  }
}

std::vector<Eigen::Vector3d> samplePoints(const CameraModel& cam, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<Eigen::Vector3d> pts;
  while (static_cast<int>(pts.size()) < n) {
    const Eigen::Vector2d uv(U(rng) * (cam.width() - 1), U(rng) * (cam.height() - 1));
    Eigen::Vector3d b;
    if (cam.unproject(uv, &b)) pts.push_back(b * (0.5 + 10.0 * U(rng)));
  }
  return pts;
}

}  // namespace

TEST(PinholeRadtan, RoundTripWholeImage) { checkRoundTrip(euroc()); }
TEST(KannalaBrandt, RoundTripWholeImage) { checkRoundTrip(tumvi()); }

TEST(PinholeRadtan, AnalyticJacobianMatchesNumeric) {
  const PinholeRadtan cam = euroc();
  std::vector<Eigen::Vector3d> pts = samplePoints(cam, 200, 1);
  pts.push_back(Eigen::Vector3d(0, 0, 2));
  checkJacobian(cam, pts);
  // Tangential + k3 terms exercised with exaggerated values.
  checkJacobian(PinholeRadtan(640, 480, 500, 510, 320, 240, -0.1, 0.01, 0.002, -0.003, 0.001),
                {Eigen::Vector3d(0.3, -0.2, 1.0), Eigen::Vector3d(-0.5, 0.4, 2.0)});
}

TEST(KannalaBrandt, AnalyticJacobianMatchesNumeric) {
  const KannalaBrandt cam = tumvi();
  std::vector<Eigen::Vector3d> pts = samplePoints(cam, 200, 2);
  pts.push_back(Eigen::Vector3d(1e-3, -2e-3, 1.5));
  pts.push_back(Eigen::Vector3d(1.0, 0.5, -0.2));  // behind the image plane, still in the fisheye FOV
  checkJacobian(cam, pts);
}

TEST(KannalaBrandt, OpticalAxisAndBehind) {
  const KannalaBrandt cam = tumvi();
  Eigen::Vector2d uv;
  Eigen::Matrix<double, 2, 3> J;
  ASSERT_TRUE(cam.project(Eigen::Vector3d(0, 0, 2), &uv, &J));
  EXPECT_NEAR(uv.x(), cam.cx(), 1e-12);
  EXPECT_NEAR(uv.y(), cam.cy(), 1e-12);
  EXPECT_NEAR(J(0, 0), cam.fx() / 2.0, 1e-9);
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, -1), &uv));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0, 0, 0), &uv));
  // A ray 100 deg off axis projects (fisheye), but has no normalized coordinates.
  const double a = 100.0 * M_PI / 180.0;
  ASSERT_TRUE(cam.project(Eigen::Vector3d(std::sin(a), 0, std::cos(a)), &uv));
  Eigen::Vector3d b;
  ASSERT_TRUE(cam.unproject(uv, &b));
  EXPECT_NEAR(std::acos(b.z()), a, 1e-9);
  Eigen::Vector2d xy;
  EXPECT_FALSE(cam.undistortToNormalized(uv, &xy));
}

TEST(PinholeRadtan, RejectsBehindAndNaN) {
  const PinholeRadtan cam = euroc();
  Eigen::Vector2d uv;
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.1, 0.1, -1.0), &uv));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(0.1, 0.1, 0.0), &uv));
  EXPECT_FALSE(cam.project(Eigen::Vector3d(NAN, 0.1, 1.0), &uv));
  Eigen::Vector3d b;
  EXPECT_FALSE(cam.unproject(Eigen::Vector2d(NAN, 3.0), &b));
  // Fold-over domain: radial polynomial with a turning point at r^2 = 1 / (3 * 0.3).
  const PinholeRadtan strong(640, 480, 400, 400, 320, 240, -0.3, 0.0, 0.0, 0.0);
  EXPECT_NEAR(strong.maxRadiusSquared(), 1.0 / 0.9, 2e-3);
  EXPECT_TRUE(strong.project(Eigen::Vector3d(1.0, 0.0, 1.0), &uv));
  EXPECT_FALSE(strong.project(Eigen::Vector3d(1.1, 0.0, 1.0), &uv));
}

TEST(PinholeRadtan, UndistortMatchesOpenCV) {
  const PinholeRadtan cam = euroc();
  const cv::Matx33d K(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
  const cv::Vec4d D(cam.k1(), cam.k2(), cam.p1(), cam.p2());
  const std::vector<cv::Point2d> px{{100.0, 50.0}, {367.215, 248.375}, {700.0, 400.0}, {20.0, 460.0}};
  std::vector<cv::Point2d> ref;
  cv::undistortPoints(px, ref, K, D, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-14));
  std::vector<Eigen::Vector2d> uv;
  for (const auto& p : px) uv.emplace_back(p.x, p.y);
  std::vector<Eigen::Vector2d> xy;
  std::vector<unsigned char> ok;
  ASSERT_EQ(cam.undistortPoints(uv, &xy, &ok), px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    EXPECT_NEAR(xy[i].x(), ref[i].x, 1e-7) << "pixel " << i;
    EXPECT_NEAR(xy[i].y(), ref[i].y, 1e-7) << "pixel " << i;
  }
  // Corner pixel (100, 50) is strongly distorted: normalized coords must differ from the pinhole ones.
  EXPECT_GT(std::abs(xy[0].x() - (100.0 - cam.cx()) / cam.fx()), 0.05);
}

TEST(KannalaBrandt, UndistortMatchesOpenCVFisheye) {
  const KannalaBrandt cam = tumvi();
  const cv::Matx33d K(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
  const cv::Vec4d D(cam.k1(), cam.k2(), cam.k3(), cam.k4());
  const std::vector<cv::Point2d> px{{100.0, 50.0}, {254.0, 256.0}, {400.0, 380.0}, {60.0, 440.0}};
  std::vector<cv::Point2d> ref;
  cv::fisheye::undistortPoints(px, ref, K, D, cv::noArray(), cv::noArray(),
                               cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-14));
  std::vector<cv::Point2f> uv, xy;
  for (const auto& p : px) uv.emplace_back(p.x, p.y);  // float overload, values are exact in float
  std::vector<unsigned char> ok;
  ASSERT_EQ(cam.undistortPoints(uv, &xy, &ok), px.size());
  for (size_t i = 0; i < px.size(); ++i) {
    EXPECT_NEAR(xy[i].x, ref[i].x, 1e-5) << "pixel " << i;
    EXPECT_NEAR(xy[i].y, ref[i].y, 1e-5) << "pixel " << i;
    // Double path, tighter.
    Eigen::Vector2d n;
    ASSERT_TRUE(cam.undistortToNormalized(Eigen::Vector2d(px[i].x, px[i].y), &n));
    EXPECT_NEAR(n.x(), ref[i].x, 1e-8);
    EXPECT_NEAR(n.y(), ref[i].y, 1e-8);
  }
  // OpenCV's forward fisheye projection agrees with project().
  std::vector<cv::Point3d> P{{0.3, -0.2, 1.0}, {-1.0, 0.8, 1.2}};
  std::vector<cv::Point2d> proj;
  cv::fisheye::projectPoints(P, proj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D);
  for (size_t i = 0; i < P.size(); ++i) {
    Eigen::Vector2d uv2;
    ASSERT_TRUE(cam.project(Eigen::Vector3d(P[i].x, P[i].y, P[i].z), &uv2));
    EXPECT_NEAR(uv2.x(), proj[i].x, 1e-6);
    EXPECT_NEAR(uv2.y(), proj[i].y, 1e-6);
  }
}

TEST(PinholeRadtan, ProjectMatchesOpenCV) {
  const PinholeRadtan cam = euroc();
  const cv::Matx33d K(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
  const cv::Vec4d D(cam.k1(), cam.k2(), cam.p1(), cam.p2());
  std::vector<cv::Point3d> P{{0.3, -0.2, 1.0}, {-0.7, 0.4, 1.2}};
  std::vector<cv::Point2d> proj;
  cv::projectPoints(P, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, proj);
  for (size_t i = 0; i < P.size(); ++i) {
    Eigen::Vector2d uv;
    ASSERT_TRUE(cam.project(Eigen::Vector3d(P[i].x, P[i].y, P[i].z), &uv));
    EXPECT_NEAR(uv.x(), proj[i].x, 1e-6);
    EXPECT_NEAR(uv.y(), proj[i].y, 1e-6);
  }
}

TEST(CameraLoader, SharedEurocSensorYaml) {
  const std::string path = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600/mav0/cam0/sensor.yaml";
  if (!std::ifstream(path)) GTEST_SKIP() << "shared data absent: " << path;
  std::string err;
  CameraModelPtr cam = loadCamera(path, &err);
  ASSERT_TRUE(cam) << err;
  EXPECT_EQ(cam->modelName(), "pinhole-radtan");
  EXPECT_EQ(cam->width(), 752);
  EXPECT_EQ(cam->height(), 480);
  const std::vector<double> expected{458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                                     1.76187114e-05};
  const std::vector<double> p = cam->parameters();
  ASSERT_EQ(p.size(), expected.size());
  for (size_t i = 0; i < p.size(); ++i) EXPECT_DOUBLE_EQ(p[i], expected[i]) << i;
  EXPECT_NEAR(cam->T_BS(0, 1), -0.999880929698, 1e-12);
  EXPECT_NEAR(cam->T_BS(1, 3), -0.064676986768, 1e-12);
  EXPECT_DOUBLE_EQ(cam->T_BS(3, 3), 1.0);
}

TEST(CameraLoader, RepoConfigs) {
  std::string err;
  CameraModelPtr e = loadCamera(std::string(IRAF_VO_SOURCE_DIR) + "/config/euroc_cam0.yaml", &err);
  ASSERT_TRUE(e) << err;
  EXPECT_EQ(e->modelName(), "pinhole-radtan");
  EXPECT_DOUBLE_EQ(e->parameters()[0], 458.654);
  EXPECT_DOUBLE_EQ(e->parameters()[7], 1.76187114e-05);
  CameraModelPtr t = loadCamera(std::string(IRAF_VO_SOURCE_DIR) + "/config/tumvi_cam0.yaml", &err);
  ASSERT_TRUE(t) << err;
  EXPECT_EQ(t->modelName(), "kannala-brandt");
  EXPECT_EQ(t->width(), 512);
  EXPECT_NEAR(t->parameters()[0], 190.978, 1e-3);
  EXPECT_NEAR(t->parameters()[4], 0.0034824, 1e-7);
  // T_BS = inverse(T_cam_imu): translation of the camera in the IMU frame.
  EXPECT_NEAR(t->T_BS(0, 3), 0.04557484, 1e-6);
  EXPECT_NEAR(t->T_BS(1, 3), -0.0711618, 1e-6);
  EXPECT_NEAR(t->T_BS(2, 3), -0.04468125, 1e-6);
}

TEST(CameraLoader, OpenCVDirectiveAndCameraInfoAndRoundTrip) {
  const std::string p1 = tmpPath("directive.yaml");
  writeFile(p1,
            "%YAML:1.0\n---\ncamera_model: pinhole\nintrinsics: [190.978, 190.973, 254.932, 256.897]\n"
            "distortion_model: equidistant\ndistortion_coefficients: [0.0034824, 0.00071503, -0.0020532, 0.00020294]\n"
            "resolution: [512, 512]\n");
  std::string err;
  CameraModelPtr a = loadCamera(p1, &err);
  ASSERT_TRUE(a) << err;
  EXPECT_EQ(a->modelName(), "kannala-brandt");
  EXPECT_TRUE(a->T_BS.isIdentity());

  const std::string p2 = tmpPath("camera_info.yaml");
  writeFile(p2,
            "image_width: 752\nimage_height: 480\ncamera_name: cam0\n"
            "camera_matrix:\n  rows: 3\n  cols: 3\n  data: [458.654, 0, 367.215, 0, 457.296, 248.375, 0, 0, 1]\n"
            "distortion_model: plumb_bob\n"
            "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0]\n"
            "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n");
  CameraModelPtr b = loadCamera(p2, &err);
  ASSERT_TRUE(b) << err;
  EXPECT_EQ(b->modelName(), "pinhole-radtan");
  EXPECT_EQ(b->parameters().size(), 8u);
  EXPECT_DOUBLE_EQ(b->parameters()[1], 457.296);
  EXPECT_DOUBLE_EQ(b->parameters()[3], 248.375);

  // saveCamera -> loadCamera gives the same model and T_BS.
  auto c = std::make_shared<PinholeRadtan>(euroc());
  c->T_BS(0, 3) = 0.25;
  const std::string p3 = tmpPath("saved.yaml");
  ASSERT_TRUE(saveCamera(*c, p3, &err)) << err;
  CameraModelPtr d = loadCamera(p3, &err);
  ASSERT_TRUE(d) << err;
  EXPECT_EQ(d->parameters(), c->parameters());
  EXPECT_DOUBLE_EQ(d->T_BS(0, 3), 0.25);
}

TEST(CameraLoader, BadFilesNameFileAndKey) {
  const std::string good_rest =
      "distortion_model: radial-tangential\ndistortion_coefficients: [-0.28, 0.07, 0.0002, 0.00002]\n";
  struct Case {
    std::string text, key;
  };
  const std::vector<Case> cases{
      {"camera_model: pinhole\nresolution: [752, 480]\n" + good_rest, "intrinsics"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367]\nresolution: [752, 480]\n" + good_rest, "intrinsics"},
      {"camera_model: pinhole\nintrinsics: [.nan, 457, 367, 248]\nresolution: [752, 480]\n" + good_rest, "intrinsics"},
      {"camera_model: pinhole\nintrinsics: [-458, 457, 367, 248]\nresolution: [752, 480]\n" + good_rest, "intrinsics"},
      {"camera_model: pinhole\nintrinsics: [458, 0, 367, 248]\nresolution: [752, 480]\n" + good_rest, "intrinsics"},
      {"camera_model: omni\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 480]\n" + good_rest, "camera_model"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 0]\n" + good_rest, "resolution"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 480]\n"
       "distortion_model: fov\ndistortion_coefficients: [0.1]\n", "distortion_model"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 480]\n"
       "distortion_model: equidistant\ndistortion_coefficients: [0.1, 0.2]\n", "distortion_coefficients"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 480]\n"
       "distortion_model: radial-tangential\n", "distortion_coefficients"},
      {"camera_model: pinhole\nintrinsics: [458, 457, 367, 248]\nresolution: [752, 480]\n" + good_rest +
       "T_BS:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]\n", "T_BS.data"},
      {"image_width: 752\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 2, 0, 1, 2, 0, 0, 1]\n"
       "distortion_model: rational_polynomial\ndistortion_coefficients:\n  rows: 1\n  cols: 8\n  data: [0,0,0,0,0,0,0,0]\n",
       "distortion_model"},
      {"image_width: 752\nimage_height: -1\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 2, 0, 1, 2, 0, 0, 1]\n"
       "distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0,0,0,0,0]\n",
       "image_height"},
      {"image_width: 752\nimage_height: 480\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 2, 0, 1, 2]\n"
       "distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0,0,0,0,0]\n",
       "camera_matrix.data"},
      {"just: [a, list\n", "yaml parse error"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = tmpPath("bad_" + std::to_string(i) + ".yaml");
    writeFile(path, cases[i].text);
    std::string err;
    EXPECT_FALSE(loadCamera(path, &err)) << "case " << i;
    EXPECT_NE(err.find(path), std::string::npos) << "case " << i << ": " << err;
    EXPECT_NE(err.find(cases[i].key), std::string::npos) << "case " << i << " expected key " << cases[i].key << ": " << err;
  }
  std::string err;
  EXPECT_FALSE(loadCamera("/nonexistent/dir/cam.yaml", &err));
  EXPECT_NE(err.find("/nonexistent/dir/cam.yaml"), std::string::npos) << err;
  // Factory validation.
  EXPECT_FALSE(makeCamera("pinhole-radtan", 640, 480, {500, 500, 320, 240, 0, 0, 0}, &err));
  EXPECT_FALSE(makeCamera("kannala-brandt", 640, 480, {500, NAN, 320, 240, 0, 0, 0, 0}, &err));
  EXPECT_NE(err.find("fy"), std::string::npos) << err;
  EXPECT_FALSE(makeCamera("double-sphere", 640, 480, {500, 500, 320, 240, 0, 0, 0, 0}, &err));
  EXPECT_TRUE(makeCamera("kannala-brandt", 640, 480, {500, 500, 320, 240, 0, 0, 0, 0}, &err));
}

// The callers ask a model its kind, not its name: a fisheye they have never heard of gets the fisheye rule.
namespace {
class UnknownFisheye final : public KannalaBrandt {
 public:
  UnknownFisheye() : KannalaBrandt(512, 512, 190.978, 190.978, 256, 256) {}
  std::string modelName() const override { return "double-sphere"; }
  std::string distortionModel() const override { return "double-sphere"; }
};
}  // namespace

TEST(CameraKind, AModelUnknownToTheCallersIsRuledByItsKind) {
  const UnknownFisheye unknown;
  const KannalaBrandt kb(512, 512, 190.978, 190.978, 256, 256);
  const PinholeRadtan pinhole(512, 512, 190.978, 190.978, 256, 256);
  EXPECT_TRUE(unknown.isFisheye());
  EXPECT_FALSE(pinhole.isFisheye());
  PipelineParams p_unknown, p_kb, p_pinhole;
  applyResolutionRule(unknown, &p_unknown);
  applyResolutionRule(kb, &p_kb);
  applyResolutionRule(pinhole, &p_pinhole);
  EXPECT_EQ(p_unknown.tracker.min_triangulation_parallax_deg, 2.4);  // 1 deg * 458.654 / 191
  EXPECT_EQ(p_kb.tracker.min_triangulation_parallax_deg, 2.4);
  EXPECT_EQ(p_pinhole.tracker.min_triangulation_parallax_deg, 1.0);
  // The nodelet's per-stage rule.
  TrackerParams t;
  applyTrackerResolutionRule(unknown, {}, &t);
  EXPECT_EQ(t.min_triangulation_parallax_deg, 2.4);
  // The sensor.yaml writer asks the model for its distortion_model.
  const std::string path = tmpPath("unknown.yaml");
  std::string err;
  ASSERT_TRUE(saveCamera(unknown, path, &err)) << err;
  std::ifstream f(path);
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("distortion_model: double-sphere"), std::string::npos) << text;
  std::remove(path.c_str());
}
