// Monocular map initialization: two-view geometry between a reference frame and the current frame
// (initializeTwoView: H vs E with ORB-SLAM scores, cheirality / reprojection / parallax checks), a two-keyframe
// BA, then the map's first two keyframes and points. ROS-free; tracking thread only.
//
// The reference is replaced when it is older than init_max_frames or has fewer than init_min_matches matches; the
// one replaced for too few matches is tried as well while it keeps init_min_triangulated matches.
// Scale: the triangulated points' median depth in the reference frame becomes `anchor.median_depth`; the
// reference frame sits at `anchor.T_w_ref` (the origin for the first map, the last good pose after a loss).
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/tracking/frame.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/matcher.h"
#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct MapAnchor {
  Eigen::Isometry3d T_w_ref = Eigen::Isometry3d::Identity();
  double median_depth = 1.0;
};

class MapInitializer {
 public:
  MapInitializer(const CameraModel& camera, const TrackerParams& params)
      : cam_(camera), p_(params), matcher_(camera, params) {}

  bool hasReference() const { return have_reference_; }
  /// The frame becomes the reference if it has at least init_min_features keypoints (else: no reference).
  void setReference(const Frame& f);
  void clearReference() { have_reference_ = have_previous_ = false; }
  /// Tries to initialize the map from the reference and `cur`. On success the map holds the two keyframes
  /// (*kf0 = reference, *kf1 = cur), cur.T_c_w and cur.point_id are set and *num_points = points created.
  bool initialize(Frame& cur, const MapAnchor& anchor, Map* map, KeyframePtr* kf0, KeyframePtr* kf1,
                  int* num_points);
  /// Why the last initialize() call failed ("" after a success), e.g. "too few matches (42 < 100)" or
  /// "essential: parallax too low (0.4 deg)"; for logs (TrackResult::init_status, the frame log).
  const std::string& lastFailure() const { return last_failure_; }

 private:
  /// Matches (cur, reference) of cur against a reference frame.
  std::vector<std::pair<int, int>> matchToReference(const Frame& ref, const Frame& cur) const;
  /// The two-view test, BA and initial map from `ref` and cur (last_failure_ says why not).
  bool initializeFrom(const Frame& ref, const std::vector<std::pair<int, int>>& matches, Frame& cur,
                      const MapAnchor& anchor, Map* map, KeyframePtr* kf0, KeyframePtr* kf1, int* num_points);
  /// The same from the reference replaced for too few matches, while it keeps init_min_triangulated matches.
  bool initializeFromPrevious(Frame& cur, const MapAnchor& anchor, Map* map, KeyframePtr* kf0, KeyframePtr* kf1,
                              int* num_points);

  const CameraModel& cam_;
  const TrackerParams& p_;
  Matcher matcher_;
  bool have_reference_ = false;
  Frame reference_;
  bool have_previous_ = false;
  Frame previous_;
  std::string last_failure_;
};

}  // namespace iraf_vo
