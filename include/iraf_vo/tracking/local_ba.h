// The sliding-window bundle-adjustment problem: which keyframes are free, which are held fixed (gauge).
// ROS-free.
//
// Window: the newest window_size keyframes and the points they observe (points with >= 2 observations) are
// free; every other keyframe still in the map that observes those points is held fixed. Monocular gauge =
// 6 dof pose + 1 dof scale. Start of a map (no keyframe outside the window observes its points): only the
// oldest keyframe is fixed and the solution is rescaled about its centre so that the distance to the second
// oldest stays as it was (scale_anchor: the same unit of scale as before, the baseline's direction and the
// second keyframe's rotation free; fixing the oldest two froze the low-parallax initialization's error in the
// map: EuRoC MH01 frames 0-30 ~13 mm vs ~3 mm, self-aligned 8.0 vs 2.6 mm). Otherwise, if fewer than two
// keyframes are fixed, or the fixed centres span less than min_fixed_span of the window's extent (oldest to
// newest centre; scale only weakly held: it drifted towards 0 in fast-motion runs), the oldest window
// keyframes are fixed until both hold, keeping at least one keyframe free.
//
// Write-back (applyLocalBA) while the tracking thread kept going: keyframes added after the problem was
// built were posed against the pre-BA map and points triangulated meanwhile used pre-BA poses; both are moved
// with the correction of their anchor keyframe (points: the keyframe that created them if it was free in the
// BA; keyframes and points of new keyframes: the newest window keyframe), so the map stays consistent (without
// this, a starving tracker's points disagreed with the optimized poses by > 10 px and the next BAs shrank the
// scale).
#pragma once

#include "iraf_vo/tracking/bundle_adjustment.h"
#include "iraf_vo/tracking/map.h"

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
  // >= 0: the window is the whole map (start of a map, nothing outside observes its points) and only this
  // keyframe (the oldest) is fixed; the scale is then held by rescaling the solution about its centre
  // (holdScaleAboutAnchor) instead of fixing a second keyframe, whose error from the low-parallax
  // initialization would otherwise stay frozen in the map.
  int scale_anchor = -1;
};

/// The sliding-window BA problem of the map's newest window_size keyframes, copied under the map lock.
/// stereo: the keyframes' right-image observations (Keyframe::right_obs) become residuals too (BAObservation::right),
/// a point seen by one stereo keyframe is optimized, and the gauge is 6 dof only (the scale is observed): the
/// keyframes outside the window that see its points are fixed, or else the oldest window keyframe.
LocalBAProblem buildLocalBAProblem(const Map& map, int window_size, double min_fixed_span, bool stereo = false);

/// Writes the optimized poses / points back into the map, moves keyframes / points added since the problem was
/// built with their anchor's correction and removes observations flagged as outliers. The caller holds
/// Map::lockUpdates() (the mapping thread) or is the tracking thread.
void applyLocalBA(const LocalBAProblem& problem, const BASummary& summary, Map* map);

/// Fixes the oldest window keyframes (indices window_size-1 down to 1) until at least two keyframes are fixed
/// and the fixed centres span >= min_fixed_span * the window's extent. Returns the number of fixed keyframes.
int fixMonocularGauge(std::vector<BAKeyframe>* keyframes, int window_size, double min_fixed_span);

/// Distance of the second-oldest window keyframe's centre from the scale anchor's (the oldest) centre: the
/// young map's unit of scale (0 without an anchor).
double anchorBaseline(const LocalBAProblem& problem);

/// Rescales the problem's free keyframes and points about the scale anchor's centre so that anchorBaseline()
/// becomes `baseline` (a gauge change of the monocular problem: reprojection errors are unchanged).
void holdScaleAboutAnchor(LocalBAProblem* problem, double baseline);

/// Largest distance of a window keyframe's centre from the newest one (the window's extent; 0 if empty).
double windowExtent(const LocalBAProblem& problem);

}  // namespace iraf_vo
