// E and H of a monocular start by RANSAC and their ORB-SLAM scores (two_view_models.h). ROS-free.
#include "iraf_vo/tracking/two_view_models.h"

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace iraf_vo {

namespace {

Eigen::Vector2d normalized(const Eigen::Vector3d& b) { return Eigen::Vector2d(b.x() / b.z(), b.y() / b.z()); }

}  // namespace

double scoreHomography(const Eigen::Matrix3d& H, const std::vector<Eigen::Vector2d>& p1,
                       const std::vector<Eigen::Vector2d>& p2, double focal, double sigma, std::vector<char>* inl) {
  const Eigen::Matrix3d Hinv = H.inverse();
  const double th = 5.991, inv_s2 = 1.0 / (sigma * sigma), f2 = focal * focal;
  double score = 0.0;
  inl->assign(p1.size(), 0);
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector3d a = H * p1[i].homogeneous(), b = Hinv * p2[i].homogeneous();
    const double e21 = (a.hnormalized() - p2[i]).squaredNorm() * f2 * inv_s2;
    const double e12 = (b.hnormalized() - p1[i]).squaredNorm() * f2 * inv_s2;
    if (e21 > th || e12 > th) continue;
    (*inl)[i] = 1;
    score += (th - e21) + (th - e12);
  }
  return score;
}

double scoreEssential(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& p1,
                      const std::vector<Eigen::Vector2d>& p2, double focal, double sigma, std::vector<char>* inl) {
  const double th = 3.841, th_score = 5.991, inv_s2 = 1.0 / (sigma * sigma), f2 = focal * focal;
  double score = 0.0;
  inl->assign(p1.size(), 0);
  for (size_t i = 0; i < p1.size(); ++i) {
    const Eigen::Vector3d x1 = p1[i].homogeneous(), x2 = p2[i].homogeneous();
    const Eigen::Vector3d l2 = E * x1, l1 = E.transpose() * x2;
    const double num = x2.dot(l2);
    const double e2 = num * num / (l2.head<2>().squaredNorm() + 1e-18) * f2 * inv_s2;  // distance in image 2
    const double e1 = num * num / (l1.head<2>().squaredNorm() + 1e-18) * f2 * inv_s2;
    if (e1 > th || e2 > th) continue;
    (*inl)[i] = 1;
    score += (th_score - e1) + (th_score - e2);
  }
  return score;
}

ForwardMatches collectForwardMatches(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2) {
  ForwardMatches m;
  for (size_t i = 0; i < b1.size(); ++i) {
    if (b1[i].z() < 0.1 || b2[i].z() < 0.1) continue;
    m.index.push_back(static_cast<int>(i));
    m.b1.push_back(b1[i]);
    m.b2.push_back(b2[i]);
    m.p1.push_back(normalized(b1[i]));
    m.p2.push_back(normalized(b2[i]));
    m.c1.emplace_back(m.p1.back().x(), m.p1.back().y());
    m.c2.emplace_back(m.p2.back().x(), m.p2.back().y());
  }
  return m;
}

TwoViewModels fitEssentialAndHomography(const ForwardMatches& m, double focal, const TwoViewParams& params,
                                        TwoViewResult* res) {
  TwoViewModels models;
  const double th_norm = params.threshold_px / focal;
  cv::Mat mask_e, mask_h;
  models.E = cv::findEssentialMat(m.c1, m.c2, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, 0.999, th_norm, mask_e);
  models.H = cv::findHomography(m.c1, m.c2, cv::RANSAC, th_norm, mask_h, 2000, 0.999);
  models.have_e = models.E.rows == 3 && models.E.cols == 3;
  models.have_h = models.H.rows == 3 && models.H.cols == 3;
  if (models.have_e) {
    Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
    cv::cv2eigen(models.E, E);
    res->score_f = scoreEssential(E, m.p1, m.p2, focal, params.threshold_px, &models.inliers_e);
  }
  if (models.have_h) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    cv::cv2eigen(models.H, H);
    res->score_h = scoreHomography(H, m.p1, m.p2, focal, params.threshold_px, &models.inliers_h);
  }
  return models;
}

}  // namespace iraf_vo
