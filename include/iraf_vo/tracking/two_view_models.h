// The two models of a monocular start (two_view.h): the matches whose rays point forward in both views, the
// essential matrix and the homography fitted to them by RANSAC (OpenCV), and their ORB-SLAM scores (sum over both
// directions of (gate - e^2 / sigma^2), pixel units through `focal`). ROS-free.
#pragma once

#include "iraf_vo/tracking/two_view.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <vector>

namespace iraf_vo {

/// The matches whose rays point forward in both views, as bearings, normalized and OpenCV coordinates.
struct ForwardMatches {
  std::vector<int> index;  // into the caller's match list
  std::vector<Eigen::Vector3d> b1, b2;
  std::vector<Eigen::Vector2d> p1, p2;
  std::vector<cv::Point2f> c1, c2;
};

/// Only rays in front of both cameras have normalized coordinates (fisheye rays beyond 90 deg are dropped).
ForwardMatches collectForwardMatches(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2);

/// Both models by RANSAC (OpenCV) and their inliers by the ORB-SLAM scores.
struct TwoViewModels {
  cv::Mat E, H;
  bool have_e = false, have_h = false;
  std::vector<char> inliers_e, inliers_h;
};

/// Fits both models to the forward matches; their scores go to res->score_f / res->score_h.
TwoViewModels fitEssentialAndHomography(const ForwardMatches& m, double focal, const TwoViewParams& params,
                                        TwoViewResult* res);

/// ORB-SLAM's score of a homography x2 ~ H x1 on normalized coordinates; *inl: the matches within the gate both ways.
double scoreHomography(const Eigen::Matrix3d& H, const std::vector<Eigen::Vector2d>& p1,
                       const std::vector<Eigen::Vector2d>& p2, double focal, double sigma, std::vector<char>* inl);
/// ORB-SLAM's score of an essential matrix (x2^T E x1 = 0) by the point-to-epipolar-line distances in both images.
double scoreEssential(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& p1,
                      const std::vector<Eigen::Vector2d>& p2, double focal, double sigma, std::vector<char>* inl);

}  // namespace iraf_vo
