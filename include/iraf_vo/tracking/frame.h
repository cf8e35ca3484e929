// One image as the tracker sees it: keypoints undistorted once into unit bearings, descriptors, and a
// pixel grid for window searches. ROS-free; used by the tracking thread only.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/features/feature_frame.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace iraf_vo {

using Descriptor = std::array<uint8_t, 32>;  // rotated BRIEF, 256 bit

constexpr double kChi2TwoDof = 5.991;  // 2 dof, 95 %

/// Hamming distance of two 32-byte descriptors.
int hammingDistance(const uint8_t* a, const uint8_t* b);
/// Row r of an N x 32 CV_8U descriptor matrix.
Descriptor descriptorRow(const cv::Mat& descriptors, int r);
/// Pixel noise of a keypoint at pyramid level `octave`: scale_factor^octave (level 0: 1 px).
double octaveSigma(double scale_factor, int octave);

class Frame {
 public:
  long index = 0;
  double stamp = 0.0;
  double scale_factor = 1.2;              // pyramid scale of the keypoints' octaves
  std::vector<cv::KeyPoint> keypoints;    // level-0 distorted pixels
  cv::Mat descriptors;                    // N x 32 CV_8U, continuous
  std::vector<Eigen::Vector3d> bearings;  // unit bearing of each keypoint (CameraModel::unproject)
  std::vector<char> valid;                // 0: the keypoint did not unproject
  std::vector<long> point_id;             // matched map point per keypoint, -1 if none
  /// Stereo: per keypoint its left-right match in the right image (u, v, sigma [px]); sigma 0 = none. Empty
  /// for a monocular frame or one without a right image.
  std::vector<Eigen::Vector3f> right_obs;
  Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();

  /// Undistorts the feature stage's keypoints and builds the search grid. false + *error when the
  /// descriptors do not match the keypoints (N x 32 CV_8U).
  static bool fromFeatures(const FeatureFrame& in, const CameraModel& camera, long index, Frame* out,
                           std::string* error);

  size_t size() const { return keypoints.size(); }
  double sigma(int octave) const { return octaveSigma(scale_factor, octave); }
  /// Keypoints within radius r of (u, v) whose octave lies in [min_octave, max_octave].
  void featuresInArea(double u, double v, double r, int min_octave, int max_octave, std::vector<int>* out) const;

 private:
  void buildGrid(int width, int height);

  /// A keypoint as the grid search reads it (position and octave next to the index: one cache line per ~4).
  struct GridEntry {
    float x, y;
    int octave;
    int index;
  };

  double cell_ = 32.0;
  int cols_ = 0, rows_ = 0;
  // Cells in row-major order, each cell's keypoints in keypoint order: cell c holds
  // grid_entries_[grid_start_[c] .. grid_start_[c + 1]); the cells of one grid row are contiguous.
  std::vector<int> grid_start_;
  std::vector<GridEntry> grid_entries_;
};

}  // namespace iraf_vo
