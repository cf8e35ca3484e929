// Translation-direction check of the two-view relative pose (never start tracking on a wrong motion).
// At ~1 deg of parallax with noisy keypoints a sideways translation and a rotation explain nearly the same image
// motion (the bas-relief ambiguity): the epipolar cost is a long curved valley, sometimes with a second minimum,
// and RANSAC's motion can be 30-100 deg off in translation. A covariance (the local curvature) underestimates
// such a valley; instead the profile chi2 of the translation direction (rotation re-optimized for each direction)
// is followed along the valley's weakest direction. When a direction >= min_angle_deg away explains the matches
// about as well (profile chi2 below max_delta_chi2 in units of the estimated noise, or even better), the
// translation is not determined yet and the initializer waits for more motion. ROS-free.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace iraf_vo {

struct MotionAmbiguityParams {
  double sigma_px = 1.0;         // keypoint noise (pixels at level 0): the robust loss's scale
  double min_angle_deg = 20.0;   // directions this far from the chosen translation count as "another motion"
  double max_delta_chi2 = 9.21;  // ambiguous below this profile chi2 (99 % of chi2 with 2 dof); <= 0: never
};

struct MotionAmbiguity {
  bool ambiguous = false;
  double profile_chi2 = 0.0;  // lowest profile chi2 at >= min_angle_deg along the valley (< 0: a better minimum)
  double angle_deg = 0.0;     // where it was found
  double sigma_est_px = 0.0;  // noise estimated from the refined motion's residuals
  double refined_shift_deg = 0.0;  // angle between the chosen translation and the refined one; >= min_angle_deg:
                                   // ambiguous (the chosen motion is no minimum of the robust cost), the refined
                                   // motion is the other one (profile chi2 0) and nothing else is searched
  Eigen::Matrix3d R_other = Eigen::Matrix3d::Identity();  // the motion there
  Eigen::Vector3d t_other = Eigen::Vector3d::Zero();
};

/// p1, p2: normalized image coordinates (x/z, y/z) of the matches (a robust loss handles outliers); (R, t): the
/// chosen motion, x2 = R x1 + t; focal converts to pixels. Refines (R, t) on the Sampson errors, estimates the
/// profile's weakest direction from 4 small tilts, follows it both ways (min_angle_deg, 45, 90 deg), and
/// refines (R, t) freely from 8 restarts (4 directions tilted 45 and 90 deg) for a second minimum. If the refinement
/// of (R, t) itself moves the translation by >= min_angle_deg, that alone makes it ambiguous.
MotionAmbiguity findTranslationAmbiguity(const std::vector<Eigen::Vector2d>& p1, const std::vector<Eigen::Vector2d>& p2,
                                         const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double focal,
                                         const MotionAmbiguityParams& params);

/// How many of the model's inliers (b1[i] <-> b2[i], inliers[i]) a pure rotation explains: the rotation fitted to
/// them by Kabsch, refitted twice to its own inliers (angle between R b1 and b2, in pixels via focal, below
/// 2 threshold_px). A camera that only turns or stands still: all of them; a translation with parallax: not the
/// near points.
int inliersOfPureRotation(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                          const std::vector<char>& inliers, double focal, double threshold_px);

}  // namespace iraf_vo
