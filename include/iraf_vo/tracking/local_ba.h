// The sliding-window bundle-adjustment problem: which keyframes are free, which are held fixed (gauge).
// ROS-free.
//
// Window: the newest window_size keyframes and the points they observe (points with >= 2 observations) are
// free; every other keyframe still in the map that observes those points is held fixed. Monocular gauge =
// 6 dof pose + 1 dof scale: if fewer than two keyframes end up fixed (start of a map), or the fixed centres
// span less than min_fixed_span of the window's extent (oldest to newest centre; scale only weakly held: it
// drifted towards 0 in fast-motion runs), the oldest window keyframes are fixed until both hold, keeping at
// least one keyframe free.
//
// Write-back (Map::applyLocalBA) while the tracking thread kept going: keyframes added after the problem was
// built were posed against the pre-BA map and points triangulated meanwhile used pre-BA poses; both are moved
// with the correction of their anchor keyframe (points: the keyframe that created them if it was free in the
// BA; keyframes and points of new keyframes: the newest window keyframe), so the map stays consistent (without
// this, a starving tracker's points disagreed with the optimized poses by > 10 px and the next BAs shrank the
// scale).
#pragma once

#include <iraf_vo/tracking/geometry.h>

#include <utility>
#include <vector>

namespace iraf_vo {

struct LocalBAProblem {
  std::vector<long> keyframe_ids;                     // index -> keyframe id; window first (newest first)
  int window_size = 0;                                // keyframes [0, window_size) form the window
  std::vector<long> point_ids;                        // index -> map point id
  std::vector<BAKeyframe> keyframes;
  std::vector<BAPoint> points;
  std::vector<BAObservation> observations;
  std::vector<std::pair<long, int>> observation_keypoint;  // (keyframe id, keypoint index) per observation
  // Map state when the problem was built: keyframes / points with ids >= these were added while BA ran (the
  // tracking thread keeps going) and are moved with the correction of their anchor keyframe on write-back.
  long next_keyframe_id = 0, next_point_id = 0;
};

/// Fixes the oldest window keyframes (indices window_size-1 down to 1) until at least two keyframes are fixed
/// and the fixed centres span >= min_fixed_span * the window's extent. Returns the number of fixed keyframes.
int fixMonocularGauge(std::vector<BAKeyframe>* keyframes, int window_size, double min_fixed_span);

/// Largest distance of a window keyframe's centre from the newest one (the window's extent; 0 if empty).
double windowExtent(const LocalBAProblem& problem);

}  // namespace iraf_vo
