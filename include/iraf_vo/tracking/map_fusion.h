// Map-point fusion on the map's side (ORB-SLAM's LocalMapping::SearchInNeighbors / Fuse): what to project where,
// copied under the map lock, and the observations / merges the projection search (Matcher::searchForFusion) found.
// ROS-free.
//
// Without it a point gains observations only from the frame that becomes a keyframe; a point that frame
// missed is triangulated again from other keyframes, as a duplicate with two observations. Fusion links such
// keypoints to the existing point, so the local BA sees one point with many views instead of several weakly
// constrained ones.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/tracking/map.h"

#include <Eigen/Geometry>

#include <utility>
#include <vector>

namespace iraf_vo {

/// Map-point fusion (ORB-SLAM's SearchInNeighbors / Fuse): a keyframe to project points into, with a copy of
/// its pose and observations taken under the lock, and the points to project (not observed by it).
struct FusionTarget {
  KeyframePtr keyframe;
  Eigen::Isometry3d T_c_w;
  std::vector<long> point_id;
  std::vector<LocalPoint> candidates;
};

/// Keypoint kp of keyframe kf_id shows map point point_id (found by projection).
struct FusionLink {
  long kf_id;
  int kp;
  long point_id;
};

/// Fusion targets of keyframe kf_id: the keyframe itself with the points of its num_neighbors most covisible
/// keyframes, and each of those neighbors with the keyframe's points (points a target observes already are left
/// out). With a camera, each candidate's scale-prediction reference too (Map::localPoints). Empty when the
/// keyframe is gone.
std::vector<FusionTarget> fusionTargets(const Map& map, long kf_id, int num_neighbors,
                                        const CameraModel* camera = nullptr);

/// Applies links in order: a keypoint without a point gets the observation; a keypoint showing another point
/// merges the two (the point with more observations keeps its id and position, takes the other's observations
/// where it has none in that keyframe). Links to vanished keyframes / points, or to a point the keyframe
/// observes already, are skipped. Returns {observations added, points merged}.
std::pair<int, int> applyFusion(const std::vector<FusionLink>& links, Map* map);

}  // namespace iraf_vo
