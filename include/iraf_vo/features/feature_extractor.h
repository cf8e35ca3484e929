// The feature stage of IRAF-SLAM: ORB on an image pyramid with ORB-SLAM's per-cell FAST, quad-tree
// distribution and per-level quota, the adaptive FAST threshold (paper II-B, eqs. 13-20) and feature
// culling (paper II-C, eqs. 21-23). ROS-free.
//
// With adaptive_threshold = false and culling = false this is the ORB-SLAM3 front-end (thresholds 20 / 7),
// so the baseline and every ablation run through the same code.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <vector>

#include "iraf_vo/features/adaptive_threshold.h"
#include "iraf_vo/features/cell_fast_detector.h"
#include "iraf_vo/features/feature_culling.h"
#include "iraf_vo/features/feature_frame.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/features/orb_describer.h"

namespace iraf_vo {

/// Per-level quota of ORB-SLAM: N (1 - 1/s) / (1 - (1/s)^L) * (1/s)^l, the last level takes the remainder.
std::vector<int> featuresPerLevel(int n_features, double scale_factor, int n_levels);

/// ORB-SLAM's quad-tree distribution: splits [x0,x1) x [y0,y1) until there are >= n_desired nodes (or
/// no node holds more than one keypoint) and keeps the strongest keypoint (response) of each node.
std::vector<cv::KeyPoint> distributeQuadTree(const std::vector<cv::KeyPoint>& candidates, float x0, float y0, float x1,
                                             float y1, int n_desired);

/// Reorders [first, last) exactly as libstdc++'s std::partition with the predicate pass[*it] != 0 does
/// (same permutation, not only the same split), without data-dependent branches; returns the split point.
int* partitionLikeStd(int* first, int* last, const uint8_t* pass, std::vector<int>* scratch);

/// Orientation by intensity centroid (ORB): angle in degrees [0, 360) of the moment vector over a disc of
/// radius 15 around (x, y); (x, y) must be >= 15 px from the border.
float intensityCentroidAngle(const cv::Mat& level, cv::Point2f pt);
/// The same angle by the plain scalar sums (reference for tests; intensityCentroidAngle uses SIMD).
float intensityCentroidAngleScalar(const cv::Mat& level, cv::Point2f pt);

class FeatureExtractor {
 public:
  FeatureExtractor();

  /// `gray8` must be a non-empty CV_8UC1 image and `params` must validate; throws std::invalid_argument
  /// naming the problem otherwise. `culled` (optional) receives the keypoints removed by culling.
  FeatureFrame extract(const cv::Mat& gray8, double stamp, const FeatureParams& params,
                       CulledFeatures* culled = nullptr);

  /// Pyramid of the last extract() (level l has size round(size / scale_factor^l)).
  const std::vector<cv::Mat>& pyramid() const { return pyramid_; }

  /// Builds the ORB-SLAM pyramid of `gray8` into *pyramid (level l from level l-1, INTER_LINEAR).
  static void buildPyramid(const cv::Mat& gray8, double scale_factor, int n_levels, std::vector<cv::Mat>* pyramid);

 private:
  // The steps of extract(), in order.
  static void checkInput(const cv::Mat& gray8, const FeatureParams& p);
  /// Cell thresholds (eqs. 13-20), per-cell FAST and the quad-tree distribution of level l into
  /// level_kps_[l] (level coordinates, octave = l).
  void detectLevel(int l, int quota, const FeatureParams& p, FeatureStats* st);
  /// Scores every detected keypoint (eqs. 21-23) and decides which are kept.
  CullResult cull(const cv::Size& image_size, const FeatureParams& p, FeatureStats* st);
  /// Orientation (intensity centroid) and rotated-BRIEF descriptors of the kept keypoints only, level by
  /// level, into frame; the culled ones (oriented) go to *culled when given.
  void describeKept(const CullResult& cr, const FeatureParams& p, FeatureFrame* frame, CulledFeatures* culled);
  /// Min / median / max of the thresholds of all scanned cells.
  void summarizeCellThresholds(FeatureStats* st);

  std::vector<cv::Mat> pyramid_;
  cv::Mat level0_;
  CellThresholdEstimator threshold_estimator_;
  CellFastDetector fast_detector_;
  std::vector<double> thresholds_, cell_thresholds_;
  std::vector<std::vector<cv::KeyPoint>> level_kps_;  // distributed keypoints per level (level coordinates)
  std::vector<cv::KeyPoint> all_kps_;                 // the same, concatenated, level-0 coordinates
  std::vector<cv::KeyPoint> candidates_, level_batch_;
  std::vector<size_t> batch_index_;
  OrbDescriber describer_;  // rotated BRIEF, one level at a time (= cv::ORB's bytes)
};

}  // namespace iraf_vo
