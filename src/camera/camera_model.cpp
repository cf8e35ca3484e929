#include "iraf_vo/camera/camera_model.h"

#include <cstdio>

namespace iraf_vo {

bool CameraModel::undistortToNormalized(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const {
  Eigen::Vector3d b;
  if (!unproject(uv, &b)) return false;
  // Rays at or behind the image plane have no normalized coordinates.
  if (!(b.z() > 1e-12)) return false;
  *xy = b.head<2>() / b.z();
  return true;
}

size_t CameraModel::undistortPoints(const std::vector<Eigen::Vector2d>& uv, std::vector<Eigen::Vector2d>* xy,
                                    std::vector<unsigned char>* valid) const {
  xy->assign(uv.size(), Eigen::Vector2d::Zero());
  if (valid) valid->assign(uv.size(), 0);
  size_t n_ok = 0;
  for (size_t i = 0; i < uv.size(); ++i) {
    if (undistortToNormalized(uv[i], &(*xy)[i])) {
      ++n_ok;
      if (valid) (*valid)[i] = 1;
    } else {
      (*xy)[i].setZero();
    }
  }
  return n_ok;
}

size_t CameraModel::undistortPoints(const std::vector<cv::Point2f>& uv, std::vector<cv::Point2f>* xy,
                                    std::vector<unsigned char>* valid) const {
  xy->assign(uv.size(), cv::Point2f(0.f, 0.f));
  if (valid) valid->assign(uv.size(), 0);
  size_t n_ok = 0;
  for (size_t i = 0; i < uv.size(); ++i) {
    Eigen::Vector2d n;
    if (undistortToNormalized(Eigen::Vector2d(uv[i].x, uv[i].y), &n)) {
      (*xy)[i] = cv::Point2f(static_cast<float>(n.x()), static_cast<float>(n.y()));
      ++n_ok;
      if (valid) (*valid)[i] = 1;
    }
  }
  return n_ok;
}

bool CameraModel::isInImage(const Eigen::Vector2d& uv, double border) const {
  return uv.x() >= border && uv.y() >= border && uv.x() <= width_ - 1 - border &&
         uv.y() <= height_ - 1 - border;
}

std::string CameraModel::describe() const {
  std::string s = modelName() + " " + std::to_string(width_) + "x" + std::to_string(height_) + " [";
  const std::vector<double> p = parameters();
  char buf[64];
  for (size_t i = 0; i < p.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%s%.10g", i ? " " : "", p[i]);
    s += buf;
  }
  return s + "]";
}

}  // namespace iraf_vo
