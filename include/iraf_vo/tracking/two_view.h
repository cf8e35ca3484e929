// Two-view initialization of a monocular map: relative pose and structure from matched bearings
// (geometry.h conventions). ROS-free.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace iraf_vo {

struct TwoViewParams {
  double threshold_px = 1.5;       // RANSAC / scoring inlier threshold (pixels at level 0; converted with focal)
  double min_parallax_deg = 1.0;   // parallax test: at least min_parallax_points triangulated points (all if
  int min_parallax_points = 50;    // fewer) have this parallax (ORB-SLAM); min_parallax_points 0 = the median
  double min_median_parallax_deg = 0.5;  // and the median point has this parallax. A homography's median point
                                         // needs min_parallax_deg.
  int determined_parallax_points = 10;  // or (essential matrix, ambiguity check on): this many points have
                                        // min_parallax_deg, no median test, and the translation must be
                                        // determined: profile chi2 >= determined_min_chi2; 0 = off
  double determined_min_chi2 = 60.0;
  int min_triangulated = 50;
  // Refused when a pure rotation explains this share of the chosen model's inliers (within 2 threshold_px): a
  // camera that only turns or stands still (a homography then decomposes into a spurious motion); 1 = no check.
  double max_rotation_inlier_ratio = 0.95;
  double homography_ratio = 0.45;  // R_H = S_H / (S_H + S_F) above this -> homography (ORB-SLAM)
  double model_fallback_margin = 0.1;  // |R_H - homography_ratio| below this and the chosen model fails its
                                       // checks -> the other model is tried (0 = never); a homography tried so
                                       // must explain most of the essential matrix's off-plane inliers
  // Essential-matrix motions: refused while a translation direction >= ambiguity_angle_deg away explains the
  // matches about as well (profile chi2 < ambiguity_max_chi2, two_view_ambiguity.h); 0 = no check.
  double ambiguity_max_chi2 = 9.21;
  double ambiguity_angle_deg = 20.0;
  // The same check for a homography tried after the essential matrix (which scored higher: the scene has depth
  // off any plane, so the matches do determine a true translation) failed: with noisy keypoints and little
  // parallax its decomposition trades rotation for a spurious translation that passes the parallax test.
  bool check_fallback_homography = true;
  bool ba_use_ceres = false;  // the motion refinement's BAOptions::use_ceres (TrackerParams::ba_use_ceres)
};

struct TwoViewResult {
  bool ok = false;
  std::string model;               // "homography" or "essential"
  std::string reason;              // why it failed ("" when ok)
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();  // x2 = R_21 x1 + t_21
  Eigen::Vector3d t_21 = Eigen::Vector3d::Zero();      // unit norm
  std::vector<Eigen::Vector3d> points;  // per match, in frame-1 coordinates (valid where triangulated)
  std::vector<char> triangulated;       // per match
  int num_triangulated = 0;
  double median_parallax_deg = 0.0;
  double parallax_deg = 0.0;       // the tested parallax (min_parallax_points-th largest, or the median;
                                   // few_parallax_points: the determined_parallax_points-th largest)
  bool few_parallax_points = false;  // accepted by the determined_parallax_points test (the strict one failed)
  double score_h = 0.0, score_f = 0.0;
  double translation_profile_chi2 = -1.0;  // the ambiguity check's value (-1: not run)
};

/// Relative pose + structure from matched bearings (b1[i] <-> b2[i]). Uses cv::findEssentialMat and
/// cv::findHomography on normalized coordinates, ORB-SLAM symmetric-transfer scores for model selection,
/// then triangulation with cheirality, reprojection (threshold_px, via `focal`) and parallax checks.
TwoViewResult initializeTwoView(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                double focal, const TwoViewParams& params);

}  // namespace iraf_vo
