// Feature culling of IRAF-SLAM (paper II-C, eqs. 21-23). ROS-free.
//
//   D       = N_keypoint / A_region of the keypoint's quad-tree leaf          eq. (21)
//   C_light = 1 / (1 + exp(-rho (H_c - H_th)))                                 eq. (22)
//   S       = w1 sigmoid(k (D - D_opt)) + w2 * C_light                         eq. (23), see below
//
// Definitions the paper leaves open (chosen here):
//  * Quad-tree: the level-0 image is split recursively into 4 while a node holds more than one keypoint
//    and its children would not be smaller than min_node_size. Leaves are the "sub-regions" of eq. (21).
//  * D is divided by the frame's mean density (N_total / image area), so D = 1 means "as dense as the
//    frame on average" and D_opt does not depend on the resolution or n_features.
//  * H_c = standard deviation of the contrast_patch_size^2 patch around the keypoint on its pyramid level.
//  * eq. (23) prints w2 * (1 - C_light): that REWARDS low contrast, contradicting the text ("lower C_light
//    values indicate regions prone to lighting instability"). Default: the stated intent, w2 * C_light;
//    FeatureParams::eq23_literal = true reproduces the printed formula.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "iraf_vo/features/feature_params.h"

namespace iraf_vo {

/// Keypoints removed by culling (optional output of FeatureExtractor::extract, used for debug images).
struct CulledFeatures {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<float> stability;
};

struct CullResult {
  std::vector<float> stability;  // S per input keypoint (1 for every keypoint when culling is off)
  std::vector<float> density;    // D per input keypoint (relative to the mean density)
  std::vector<float> contrast;   // H_c per input keypoint
  std::vector<uint8_t> keep;     // 1 = kept
  int culled = 0;
};

inline double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

/// eq. (22).
inline double lightingStability(double h_c, double h_th, double rho) { return sigmoid(rho * (h_c - h_th)); }

/// eq. (23) (with the sign choice of p.eq23_literal).
double stabilityScore(double density, double c_light, const FeatureParams& p);

/// H_c: std-dev of the `patch` x `patch` window centred at (x, y) of `level` (clipped to the image).
double localContrast(const cv::Mat& level, float x, float y, int patch);
/// The same; simd = false forces the plain sums (the test reference; windows wider than 16 px always use them).
double localContrastImpl(const cv::Mat& level, float x, float y, int patch, bool simd);

/// eq. (21): relative density D of each keypoint's quad-tree leaf (keypoints in level-0 pixels).
std::vector<float> quadTreeDensity(const std::vector<cv::KeyPoint>& kps, cv::Size image_size, int min_node_size);

/// Scores and culls `kps` (level-0 coordinates, octave = pyramid level). `pyramid[l]` is level l, whose
/// coordinates are level-0 coordinates / scale_factor^l. With p.culling false every keypoint is kept
/// with stability 1. Never keeps fewer than min(p.min_features, kps.size()): when S < s_min would remove
/// too many, the highest-S keypoints are kept.
CullResult cullKeypoints(const std::vector<cv::KeyPoint>& kps, const std::vector<cv::Mat>& pyramid,
                         cv::Size image_size, const FeatureParams& p);

}  // namespace iraf_vo
