// Descriptor matching for the tracker (ORB-SLAM flavour): projection search of map points into a frame,
// brute-force matching with ratio test and rotation consistency, and the epipolar search used for
// triangulation. ROS-free; stateless apart from the parameters.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/map_fusion.h"
#include "iraf_vo/tracking/tracker_params.h"

#include <utility>
#include <vector>

namespace iraf_vo {

/// One-to-one matches between a frame's keypoints and a list of (local) map points.
class MatchSet {
 public:
  MatchSet(size_t num_keypoints, size_t num_points) : point_of_(num_keypoints, -1), keypoint_of_(num_points, -1) {}
  int pointOf(int keypoint) const { return point_of_[keypoint]; }
  int keypointOf(int point) const { return keypoint_of_[point]; }
  /// Links keypoint <-> point; a point the keypoint had before is released.
  void link(int keypoint, int point);
  void unlinkKeypoint(int keypoint);
  void clear();
  int size() const;
  size_t numKeypoints() const { return point_of_.size(); }
  const std::vector<int>& keypointOfPoint() const { return keypoint_of_; }

 private:
  std::vector<int> point_of_;     // keypoint -> point, -1 if none
  std::vector<int> keypoint_of_;  // point -> keypoint, -1 if none
};

/// Rotation consistency (ORB-SLAM): keep matches whose keypoint-angle difference falls into the 3 most
/// populated of 30 bins (2nd / 3rd only if >= 10 % of the 1st). Angles < -1000 mean "unknown": kept.
std::vector<char> rotationConsistent(const std::vector<float>& angle_differences);

class Matcher {
 public:
  Matcher(const CameraModel& camera, const TrackerParams& params) : cam_(camera), p_(params) {}

  /// Projects the unmatched local points with T_c_w and matches each to the best keypoint within
  /// radius * sigma(octave) pixels and octave +- octave_margin, octave = the point's predicted octave
  /// (predictOctave, which also drops points seen > 60 deg off their reference view) with predict_scale, else the
  /// octave it was created at (Hamming <= match_threshold_high, ratio test
  /// against the second best of the same octave). Keeps matches already in *matches. Marks the points that
  /// project into the image in *visible (optional). Returns the number of matches added.
  int searchByProjection(const Frame& f, const Eigen::Isometry3d& T_c_w, const std::vector<LocalPoint>& local,
                         double radius, int octave_margin, MatchSet* matches, std::vector<char>* visible) const;

  /// Brute force: query descriptors (valid ones) against train descriptors, ratio test, Hamming <= threshold,
  /// one query per train (the closest), rotation consistency if check_orientation. (query, train) pairs.
  std::vector<std::pair<int, int>> matchBruteForce(const cv::Mat& query, const std::vector<cv::KeyPoint>& query_kps,
                                                   const std::vector<char>& query_valid, const cv::Mat& train,
                                                   const std::vector<float>& train_angles, int threshold,
                                                   double ratio) const;

  /// Epipolar search for triangulation: for each unused keypoint of keyframe 1, the closest (Hamming <=
  /// match_threshold_low) unmatched keypoint of keyframe 2 within 1.96 sigma of its epipolar plane, if it is
  /// distinct on that line (Hamming <= triangulation_match_ratio x any candidate more than 5 px away from it).
  /// Returns, per keypoint of keyframe 2, the matched keypoint of keyframe 1 (-1 if none).
  std::vector<int> searchForTriangulation(const Keyframe& kf1, const std::vector<char>& used1, const Keyframe& kf2,
                                          const std::vector<long>& point_id2, const Eigen::Isometry3d& T_21) const;

  /// Map-point fusion: projects the target's candidate points into its keyframe and links each keypoint to the
  /// candidate with the least Hamming distance (<= match_threshold_low) among those projecting within
  /// radius * sigma(point octave) pixels and the chi2 gate (5.991 sigma(keypoint octave)^2), octave +- 1 (the point
  /// octave predicted as in searchByProjection).
  std::vector<FusionLink> searchForFusion(const FusionTarget& target, double radius) const;

 private:
  /// The point's pixel in the image seen with T_c_w (camera centre `center`) and the octave to search it at
  /// (predictOctave with predict_scale, else its own); false when it is behind the camera, outside the image or,
  /// with predict_scale, out of the predicted scale / viewing-angle range.
  bool projectInView(const LocalPoint& lp, const Eigen::Isometry3d& T_c_w, const Eigen::Vector3d& center,
                     double scale_factor, Eigen::Vector2d* uv, int* octave) const;

  const CameraModel& cam_;
  const TrackerParams& p_;
};

}  // namespace iraf_vo
