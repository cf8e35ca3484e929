// Left-right matching of one stereo frame for unrectified pairs of any CameraModel (ORB-SLAM3's approach for
// fisheye pairs, on bearings so pinhole-radtan and Kannala-Brandt both work; no rectification). ROS-free.
//
// For every left keypoint: the right keypoints whose bearing lies within stereo_epipolar_px (x its sigma) of the
// left bearing's epipolar plane (E = [t]x R of T_r_l, as an angle times the right focal length), octave within
// +-1 and on the near side of the depth range (the ray crosses [min_depth, max_depth]); the best Hamming distance
// must be <= (match_threshold_high + match_threshold_low) / 2 (ORB-SLAM's stereo threshold) and < match_ratio x
// the second best. Each right keypoint keeps its best left partner only. With the two images, the right pixel is
// refined along the epipolar curve (stereo_refinement.h). The pair is triangulated (DLT on bearings); kept when
// the depth is positive in both cameras and within [stereo_min_depth, stereo_max_depth_baselines x baseline] of
// the left camera and the reprojection error in both images passes the chi2 test (5.991 sigma^2).
//
// Depth range: up to 1000 baselines (110 m for EuRoC, ~0.5 px of disparity at a 458-px focal length): far points
// are uncertain in depth, but the local BA weighs each point by its left and right reprojection errors, so they
// still constrain the rotation and get their depth from later keyframes. Any cap on the measured depth keeps the
// matches whose disparity error was positive near it (depths short, scale short): a simulated street (points at
// 3-65 m) gave a 1.063 scale at 200 baselines with raw disparities. A cap at 40 baselines (ORB-SLAM's "close
// point" ThDepth; 4.4 m at EuRoC) kept half of the EuRoC MH_01 points out of the first map: frames 0-305 then gave
// 61 mm SE(3) ATE and a 0.97 scale instead of 4.5 mm and 1.006.
//
// Close / far (ORB-SLAM's rule, as a disparity): a match with less than stereo_min_disparity_px of disparity
// (focal x baseline / depth; 2 px) gives no depth from one stereo frame, unless the frame has fewer close matches
// than stereo_far_fill_points (200): then the nearest far ones fill it up. Far points enter the map
// from the triangulation between keyframes. Below ~2 px the kept matches' depths are biased short (the cap
// selects positive disparity errors): simulated highway, pinhole, 80-150 m -37 %, fisheye beyond 150 m -90 %.
#pragma once

#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/tracker_params.h"

#include <Eigen/Core>
#include <vector>

namespace iraf_vo {

struct StereoMatch {
  int left = -1;                                 // keypoint index in the left frame
  int right = -1;                                // keypoint index in the right frame
  Eigen::Vector3d p_l = Eigen::Vector3d::Zero();  // the triangulated point in the left camera frame [m]
  Eigen::Vector2d uv_r = Eigen::Vector2d::Zero();  // the right pixel (refined along the epipolar curve when the
                                                   // images were given, else the right keypoint's)
  double depth() const { return p_l.norm(); }    // distance from the left camera centre
};

class StereoMatcher {
 public:
  /// rig and params must outlive the matcher.
  StereoMatcher(const StereoRig& rig, const TrackerParams& params);

  /// The checked matches of one stereo frame (left and right: the same exposure, undistorted by Frame). With both
  /// images (8-bit, the keypoints' level 0), each right pixel is refined along the epipolar curve first
  /// (stereo_refinement.h; a match whose refinement fails is dropped), then triangulated and checked.
  std::vector<StereoMatch> match(const Frame& left, const Frame& right, const cv::Mat& left_image = cv::Mat(),
                                 const cv::Mat& right_image = cv::Mat()) const;
  /// The same from the right image's features (and right.image when left_image is given too); fills
  /// left->right_obs (the match's right pixel and sigma per left keypoint). false (no matches, right_obs empty) when
  /// the right features are unusable.
  bool matchRight(Frame* left, const FeatureFrame& right, std::vector<StereoMatch>* matches,
                  const cv::Mat& left_image = cv::Mat()) const;

  double maxDepth() const { return max_depth_; }
  /// Points farther than this (less disparity than stereo_min_disparity_px) are kept only to fill a frame up to
  /// stereo_far_fill_points, nearest first.
  double closeDepth() const { return close_depth_; }

 private:
  /// Left keypoint i's right pixel and bearing refined along the epipolar curve (step: the finer octave's pixel).
  bool refineRight(const Frame& left, size_t i, int right_octave, const cv::Mat& left_image, const cv::Mat& right_image,
                   Eigen::Vector2d* uv_r, Eigen::Vector3d* b_r) const;
  /// Drops the far matches (depth > close_depth_) but the nearest ones up to stereo_far_fill_points; the order is kept.
  void keepClosePoints(std::vector<StereoMatch>* matches) const;
  const StereoRig& rig_;
  const TrackerParams& p_;
  Eigen::Matrix3d E_;  // b_r^T E b_l = 0
  Eigen::Vector3d c_r_in_l_;  // right camera centre in the left frame
  double max_depth_;
  double close_depth_;
};

/// The matches as map points in the world (left.T_c_w), for the left keypoints without a map point
/// (left.point_id < 0) when only_new, else for all.
std::vector<StereoMapPoint> stereoMapPoints(const std::vector<StereoMatch>& matches, const Frame& left, bool only_new);
/// The matches within close_depth whose left keypoint has no map point (left.point_id < 0), per keypoint of left
/// (0 without keypoints).
double closeShareWithoutPoint(const std::vector<StereoMatch>& matches, const Frame& left, double close_depth);

}  // namespace iraf_vo
