// Multi-view basics (multiview.h): triangulation of bearings, parallax, reprojection error, PnP on bearings.
// ROS-free.
#include "iraf_vo/tracking/multiview.h"

#include "iraf_vo/tracking/geometry.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <algorithm>
#include <cmath>

namespace iraf_vo {

bool triangulateBearings(const Eigen::Isometry3d& T1, const Eigen::Vector3d& b1, const Eigen::Isometry3d& T2,
                         const Eigen::Vector3d& b2, Eigen::Vector3d* p_w) {
  Eigen::Matrix4d A;
  const Eigen::Matrix<double, 3, 4> P1 = T1.matrix().topRows<3>(), P2 = T2.matrix().topRows<3>();
  const Eigen::Vector3d u1 = b1.normalized(), u2 = b2.normalized();
  // Two independent rows of [u]x P X = 0 per view: choose the rows with the largest |u| component excluded.
  auto rows = [](const Eigen::Vector3d& u, const Eigen::Matrix<double, 3, 4>& P, Eigen::Matrix<double, 2, 4>* out) {
    Eigen::Matrix<double, 3, 4> C = skew(u) * P;
    int k;
    u.cwiseAbs().maxCoeff(&k);
    int r = 0;
    for (int i = 0; i < 3; ++i)
      if (i != k) out->row(r++) = C.row(i);
  };
  Eigen::Matrix<double, 2, 4> r1, r2;
  rows(u1, P1, &r1);
  rows(u2, P2, &r2);
  A << r1, r2;
  Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d X = svd.matrixV().col(3);
  if (std::abs(X(3)) < 1e-12) return false;
  *p_w = X.head<3>() / X(3);
  return p_w->allFinite();
}

double parallaxAngle(const Eigen::Isometry3d& T1, const Eigen::Isometry3d& T2, const Eigen::Vector3d& p) {
  const Eigen::Vector3d c1 = T1.inverse().translation(), c2 = T2.inverse().translation();
  const double c = (p - c1).normalized().dot((p - c2).normalized());
  return std::acos(std::clamp(c, -1.0, 1.0));
}

double reprojectionError2(const CameraModel& cam, const Eigen::Isometry3d& T_c_w, const Eigen::Vector3d& p_w,
                          const Eigen::Vector2d& uv) {
  const Eigen::Vector3d p_c = T_c_w * p_w;
  Eigen::Vector2d pr;
  if (p_c.z() <= 1e-6 || !cam.project(p_c, &pr)) return -1.0;
  return (pr - uv).squaredNorm();
}

int solvePnPBearings(const std::vector<Eigen::Vector3d>& p_w, const std::vector<Eigen::Vector3d>& bearings,
                     double focal, double threshold_px, int iterations, Eigen::Isometry3d* T_c_w,
                     std::vector<char>* inliers) {
  if (inliers) inliers->assign(p_w.size(), 0);
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  std::vector<int> idx;
  for (size_t i = 0; i < p_w.size() && i < bearings.size(); ++i) {
    if (bearings[i].z() < 0.1 || !p_w[i].allFinite()) continue;
    obj.emplace_back(p_w[i].x(), p_w[i].y(), p_w[i].z());
    img.emplace_back(bearings[i].x() / bearings[i].z(), bearings[i].y() / bearings[i].z());
    idx.push_back(static_cast<int>(i));
  }
  if (obj.size() < 6) return 0;
  cv::Mat rvec, tvec, inl;
  bool ok = false;
  try {
    ok = cv::solvePnPRansac(obj, img, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec, false, iterations,
                            static_cast<float>(threshold_px / focal), 0.99, inl, cv::SOLVEPNP_AP3P);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok || inl.rows < 6) return 0;
  // Refine on the inliers (Levenberg-Marquardt in OpenCV).
  std::vector<cv::Point3f> obj_in;
  std::vector<cv::Point2f> img_in;
  for (int r = 0; r < inl.rows; ++r) {
    obj_in.push_back(obj[inl.at<int>(r)]);
    img_in.push_back(img[inl.at<int>(r)]);
  }
  cv::solvePnPRefineLM(obj_in, img_in, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), rvec, tvec);
  cv::Mat Rcv;
  cv::Rodrigues(rvec, Rcv);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(Rcv, R);
  cv::cv2eigen(tvec, t);
  if (!R.allFinite() || !t.allFinite()) return 0;
  T_c_w->setIdentity();
  T_c_w->linear() = R;
  T_c_w->translation() = t;
  if (inliers)
    for (int r = 0; r < inl.rows; ++r) (*inliers)[idx[inl.at<int>(r)]] = 1;
  return inl.rows;
}

}  // namespace iraf_vo
