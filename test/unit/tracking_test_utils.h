// Synthetic helpers shared by the tracking tests: the core camera models without distortion (pinhole and
// equidistant fisheye) and a synthetic feature renderer (random 3D points with random ORB-like descriptors).
#pragma once

#include <iraf_vo/camera/camera_model.h>
#include <iraf_vo/camera/kannala_brandt.h>
#include <iraf_vo/camera/pinhole_radtan.h>
#include <iraf_vo/features/feature_frame.h>
#include <iraf_vo/tracking/frame.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

namespace iraf_vo {
namespace test {

// The core camera models without distortion, with the tests' (w, h, f, cx, cy) signature.
struct TestPinhole : PinholeRadtan {
  TestPinhole(int w, int h, double f, double cx, double cy) : PinholeRadtan(w, h, f, f, cx, cy) {}
};

/// Equidistant fisheye (Kannala-Brandt with k1..k4 = 0): r = f * theta.
struct TestFisheye : KannalaBrandt {
  TestFisheye(int w, int h, double f, double cx, double cy) : KannalaBrandt(w, h, f, f, cx, cy) {}
};

inline Eigen::Isometry3d makePose(const Eigen::Vector3d& rpy_deg, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double d = M_PI / 180.0;
  T.linear() = (Eigen::AngleAxisd(rpy_deg.z() * d, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy_deg.y() * d, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy_deg.x() * d, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = t;
  return T;
}

inline double rotationErrorDeg(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return Eigen::AngleAxisd(A.transpose() * B).angle() * 180.0 / M_PI;
}

/// A static world of textured points: every point has a random 32-byte descriptor; a frame sees the points that
/// project into the image, with pixel noise and a few flipped descriptor bits. Keypoint octave from depth.
struct SyntheticWorld {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<uint8_t, 32>> desc;
  std::mt19937 rng{7};

  void addBox(int n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y()), uz(lo.z(), hi.z());
    std::uniform_int_distribution<int> ub(0, 255);
    for (int i = 0; i < n; ++i) {
      points.emplace_back(ux(rng), uy(rng), uz(rng));
      std::array<uint8_t, 32> d;
      for (auto& b : d) b = static_cast<uint8_t>(ub(rng));
      desc.push_back(d);
    }
  }

  FeatureFrame render(const CameraModel& cam, const Eigen::Isometry3d& T_w_c, double stamp, double noise_px = 0.5,
                      int flip_bits = 4) {
    FeatureFrame f;
    f.stamp = stamp;
    f.width = cam.width();
    f.height = cam.height();
    std::normal_distribution<double> nd(0.0, noise_px);
    std::uniform_int_distribution<int> bit(0, 255);
    const Eigen::Isometry3d T_c_w = T_w_c.inverse();
    std::vector<int> vis;
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d pc = T_c_w * points[i];
      if (pc.z() < 0.1) continue;
      Eigen::Vector2d uv;
      if (!cam.project(pc, &uv)) continue;
      uv += Eigen::Vector2d(nd(rng), nd(rng));
      if (uv.x() < 1 || uv.y() < 1 || uv.x() > cam.width() - 2 || uv.y() > cam.height() - 2) continue;
      cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f);
      kp.octave = 0;
      kp.angle = -1.f;
      kp.response = 1.f;
      f.keypoints.push_back(kp);
      vis.push_back(static_cast<int>(i));
    }
    f.descriptors.create(static_cast<int>(vis.size()), 32, CV_8U);
    for (size_t k = 0; k < vis.size(); ++k) {
      auto d = desc[vis[k]];
      for (int b = 0; b < flip_bits; ++b) {
        const int x = bit(rng);
        d[x / 8] ^= static_cast<uint8_t>(1u << (x % 8));
      }
      std::memcpy(f.descriptors.ptr<uint8_t>(static_cast<int>(k)), d.data(), 32);
    }
    f.stability.assign(vis.size(), 1.f);
    return f;
  }
};

/// Sim(3) ATE RMSE of estimated vs true positions (Eigen::umeyama with scaling).
inline double ateRmse(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt) {
  const int n = static_cast<int>(est.size());
  if (n < 3) return 1e9;
  Eigen::Matrix3Xd A(3, n), B(3, n);
  for (int i = 0; i < n; ++i) {
    A.col(i) = est[i];
    B.col(i) = gt[i];
  }
  const Eigen::Matrix4d S = Eigen::umeyama(A, B, true);
  double s = 0;
  for (int i = 0; i < n; ++i) s += ((S * A.col(i).homogeneous()).head<3>() - B.col(i)).squaredNorm();
  return std::sqrt(s / n);
}

/// Keypoints of hand-placed map points as one camera sees them (PointView::add), for pose-tracker tests.
struct PointView {
  FeatureFrame features;
  std::vector<int> keypoint_of_point;  // -1: not in the view

  /// Keypoints (octave 0, no noise) of the points `ids` seen from T_c_w, with their descriptors (flip_bits bits
  /// changed).
  void add(const CameraModel& cam, const Eigen::Isometry3d& T_c_w, const std::vector<Eigen::Vector3d>& P,
           const std::vector<std::array<uint8_t, 32>>& D, const std::vector<int>& ids, int flip_bits) {
    keypoint_of_point.resize(P.size(), -1);
    for (int i : ids) {
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = T_c_w * P[i];
      if (pc.z() < 0.1 || !cam.project(pc, &uv)) continue;
      if (uv.x() < 2 || uv.y() < 2 || uv.x() > cam.width() - 3 || uv.y() > cam.height() - 3) continue;
      cv::KeyPoint kp(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 31.f);
      kp.octave = 0;
      kp.angle = -1.f;
      kp.response = 1.f;
      std::array<uint8_t, 32> d = D[i];
      for (int b = 0; b < flip_bits; ++b) d[(7 * b + i) % 32] ^= static_cast<uint8_t>(1u << (b % 8));
      cv::Mat row(1, 32, CV_8U);
      std::memcpy(row.ptr<uint8_t>(0), d.data(), 32);
      features.descriptors.push_back(row);
      keypoint_of_point[i] = static_cast<int>(features.keypoints.size());
      features.keypoints.push_back(kp);
      features.stability.push_back(1.f);
    }
  }

  /// The tracker's frame of these keypoints (false + err: Frame::fromFeatures refused them).
  bool toFrame(const CameraModel& cam, long index, Frame* f, std::string* err) const {
    FeatureFrame ff = features;
    ff.width = cam.width();
    ff.height = cam.height();
    ff.stamp = 0.05 * index;
    return Frame::fromFeatures(ff, cam, index, f, err);
  }
};

// A frame with n keypoints on a grid, camera centre at (x, 0, 0) looking down +z.
inline Frame gridFrame(long index, int n, double x) {
  Frame f;
  f.index = index;
  for (int i = 0; i < n; ++i) {
    cv::KeyPoint kp(10.f + 20.f * (i % 30), 10.f + 20.f * (i / 30), 31.f);
    kp.octave = 0;
    f.keypoints.push_back(kp);
  }
  f.descriptors = cv::Mat::zeros(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) f.descriptors.at<uint8_t>(i, 0) = static_cast<uint8_t>(i);
  f.bearings.assign(n, Eigen::Vector3d::UnitZ());
  f.valid.assign(n, 1);
  f.point_id.assign(n, -1);
  f.T_c_w = Eigen::Isometry3d::Identity();
  f.T_c_w.translation() = Eigen::Vector3d(-x, 0, 0);
  return f;
}

}  // namespace test
}  // namespace iraf_vo
