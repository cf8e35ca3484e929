// Camera models shared by every stage (simulator, tracker, BA, evaluation).
// ROS-free. Implementations: PinholeRadtan (EuRoC cam0) and KannalaBrandt (TUM-VI cam0, equidistant).
// Construction from files: iraf_vo/camera/camera_loader.h (loadCamera, makeCamera).
// Callers ask a model what they need (kind(), focal(), distortionModel()), never compare modelName(): a new model
// is a new class here plus its name in the loader.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <opencv2/core/types.hpp>
#include <string>
#include <vector>

namespace iraf_vo {

/// The projection family: what the rules that differ between lenses branch on (the resolution rule's
/// triangulation parallax follows the focal length of a fisheye).
enum class CameraKind { kPinhole, kFisheye };

class CameraModel {
 public:
  virtual ~CameraModel() = default;

  /// "pinhole-radtan" or "kannala-brandt" (one name per model across code, yaml and docs).
  virtual std::string modelName() const = 0;
  /// Pinhole (perspective, narrow field of view) or fisheye; every model states its own.
  virtual CameraKind kind() const = 0;
  bool isFisheye() const { return kind() == CameraKind::kFisheye; }
  /// The distortion_model name of the EuRoC / Kalibr sensor.yaml layout ("radial-tangential", "equidistant").
  virtual std::string distortionModel() const = 0;
  int width() const { return width_; }
  int height() const { return height_; }

  /// Project a 3D point in the camera frame (z forward, REP-103 optical frame) to distorted pixels.
  /// Returns false when the point is behind the camera / outside the model's valid domain.
  /// If J is non-null it receives d(pixel)/d(point) (2x3).
  virtual bool project(const Eigen::Vector3d& p_c, Eigen::Vector2d* uv,
                       Eigen::Matrix<double, 2, 3>* J = nullptr) const = 0;

  /// Unproject a distorted pixel to a unit-norm bearing vector in the camera frame.
  virtual bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const = 0;

  /// Undistort a pixel to normalized image coordinates (x/z, y/z). Fails for rays with z <= 0.
  bool undistortToNormalized(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const;

  /// Batch undistortToNormalized. xy gets one entry per input (0,0 where it failed); valid (optional)
  /// gets 1/0 per point. Returns the number of points that undistorted successfully.
  size_t undistortPoints(const std::vector<Eigen::Vector2d>& uv, std::vector<Eigen::Vector2d>* xy,
                         std::vector<unsigned char>* valid = nullptr) const;
  /// Same for OpenCV keypoint coordinates (e.g. cv::KeyPoint::pt); output in normalized coordinates.
  size_t undistortPoints(const std::vector<cv::Point2f>& uv, std::vector<cv::Point2f>* xy,
                         std::vector<unsigned char>* valid = nullptr) const;

  /// True when uv lies inside [border, width-1-border] x [border, height-1-border].
  bool isInImage(const Eigen::Vector2d& uv, double border = 0.0) const;

  /// Intrinsic parameters in the model's own order (fx fy cx cy, then distortion), for BA.
  virtual std::vector<double> parameters() const = 0;

  /// Focal length in pixels (mean of fx, fy): converts pixel thresholds to angles.
  virtual double focal() const = 0;

  /// One-line human-readable summary: model, resolution, parameters.
  std::string describe() const;

  /// 4x4 row-major T_BS (sensor to body), identity when the file has none.
  Eigen::Matrix4d T_BS = Eigen::Matrix4d::Identity();

 protected:
  int width_ = 0;
  int height_ = 0;
};

using CameraModelPtr = std::shared_ptr<const CameraModel>;

}  // namespace iraf_vo
