// Sub-pixel refinement of a left-right match along the epipolar curve (ORB-SLAM's SAD patch search along the row,
// for unrectified pairs of any camera model). ROS-free.
//
// ORB keypoints sit on the integer grid of their pyramid level (1.2^octave px at level 0), so a raw disparity is
// quantized to about a level pixel. For far points that is most of the disparity; and as a match must triangulate
// in front of both cameras and within the depth range, the kept matches are those whose error made the disparity
// larger: their depths come out short, and the metric scale with them (a simulated street at 10-65 m:
// triangulated depths 5-50 % short beyond 15 m before the refinement, within noise after).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace iraf_vo {

struct EpipolarPatchSearch {
  int half_window = 5;   // the patch is (2 w + 1)^2 samples
  int half_range = 5;    // positions -L..L along the epipolar direction
  int gauss_newton_steps = 3;  // after the parabola: steps on the squared differences (0: the parabola's fit)
  bool slanted = true;   // the steps also fit how the shift changes over the patch (false: one shift for the patch)
};

/// The right pixel where the left pixel's patch fits best along `direction` (a unit vector in the right image, the
/// epipolar curve's tangent at uv_r) within +-half_range x step of uv_r. Patches are sampled bilinearly every `step`
/// pixels (the keypoint's level pixel), compared by the sum of absolute differences after removing each patch's
/// mean (the two images' offsets), and the minimum is interpolated by a parabola, then moved by Gauss-Newton steps
/// on the sum of squared differences (each at most half a step). With `slanted` the steps fit the shift at the patch
/// centre together with its rate of change along and across the direction: on a surface seen at a slant (a road, a
/// floor, a wall along the view) the disparity changes over the patch, and one shift for the whole patch is pulled
/// towards wherever the texture is strongest. false when a patch leaves an image, the best fit is at the end of the
/// range, or the images are not 8-bit gray.
bool refineAlongEpipolar(const cv::Mat& left, const cv::Mat& right, const Eigen::Vector2d& uv_l,
                         const Eigen::Vector2d& uv_r, const Eigen::Vector2d& direction, double step,
                         Eigen::Vector2d* refined, const EpipolarPatchSearch& search = EpipolarPatchSearch());

}  // namespace iraf_vo
