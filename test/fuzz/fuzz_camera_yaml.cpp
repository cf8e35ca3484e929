// libFuzzer target: bytes -> loadCameraFromString (every yaml layout of camera_loader.h). A camera that
// loads must be usable: finite focal length, positive size, and project/unproject never crash or return
// non-finite values when they report success. Built and run by scripts/fuzz.sh.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "iraf_vo/camera/camera_loader.h"

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string err;
  iraf_vo::CameraModelPtr cam = iraf_vo::loadCameraFromString(text, "fuzz.yaml", &err);
  if (!cam) {
    FUZZ_CHECK(!err.empty());
    FUZZ_CHECK(err.find("fuzz.yaml") != std::string::npos);  // the error names the source
    return 0;
  }
  FUZZ_CHECK(cam->width() > 0 && cam->height() > 0);
  FUZZ_CHECK(std::isfinite(cam->focal()) && cam->focal() > 0);
  for (double v : cam->parameters()) FUZZ_CHECK(std::isfinite(v));
  FUZZ_CHECK(cam->T_BS.allFinite());
  (void)cam->describe();
  const double pts[][3] = {{0, 0, 1}, {0.3, -0.2, 1}, {1, 1, 0.1}, {-2, 0.5, 1}, {0, 0, -1}, {1e6, 0, 1}};
  for (const auto& p : pts) {
    Eigen::Vector2d uv;
    Eigen::Matrix<double, 2, 3> J;
    if (cam->project(Eigen::Vector3d(p[0], p[1], p[2]), &uv, &J)) FUZZ_CHECK(uv.allFinite() && J.allFinite());
  }
  const double uvs[][2] = {{0, 0}, {cam->width() * 0.5, cam->height() * 0.5}, {cam->width() - 1.0, cam->height() - 1.0}};
  for (const auto& q : uvs) {
    Eigen::Vector3d b;
    if (cam->unproject(Eigen::Vector2d(q[0], q[1]), &b)) FUZZ_CHECK(b.allFinite() && std::abs(b.norm() - 1.0) < 1e-6);
    Eigen::Vector2d xy;
    if (cam->undistortToNormalized(Eigen::Vector2d(q[0], q[1]), &xy)) FUZZ_CHECK(xy.allFinite());
  }
  return 0;
}
