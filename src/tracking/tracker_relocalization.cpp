// Relocalization after darkness (tracking thread): the seeds a frame with signal is tracked from once the light
// returns (the keyframe-wise Relocalizer's PnP poses and the last pose moved on at the velocity before the dark),
// ranked by the map inliers tracking from each ends with. The state machine is in tracker.cpp.
#include "tracker_impl.h"

#include <algorithm>
#include <utility>

namespace iraf_vo {

// After dark frames, when tracking from the last pose failed (or ended with fewer map inliers than a search from the
// moved-on seed): the local map tracked from the poses the keyframe-wise relocalization proposes and, until the
// first pose after the dark, from the last pose moved on at the velocity before it (on a road the camera is metres
// further on, and a search around the last pose can settle on a repeated texture there), the one whose tracking
// ends with the most map inliers first (PnP seeds of 10-20 inliers on a frame still recovering its exposure can be
// the wrong keyframe's: the search around such a seed settles on a pose with fewer inliers than around the right
// one); the same inlier and health checks decide. A pose from the moved-on seed keeps that velocity.
bool Tracker::Impl::relocalizeAfterDarkness(Frame& cur, TrackResult* res) {
  if (!signal.recovering()) return false;
  const auto t0 = SteadyClock::now();
  const Eigen::Isometry3d T_last = lastPose();
  std::vector<RelocalizationCandidate> candidates = relocalizer.candidates(cur, map, 3);
  const std::optional<Eigen::Isometry3d> moved_on =
      signal.awaitingRelocalization() ? movedOnSeed(cur, T_last) : std::nullopt;
  if (moved_on) {
    RelocalizationCandidate moved;
    moved.T_c_w = *moved_on;
    moved.moved_on = true;
    candidates.push_back(moved);
  }
  rankByTrackedInliers(cur, &candidates);
  res->timing.ms_match += msSince(t0);
  for (const RelocalizationCandidate& c : candidates) {
    std::fill(cur.point_id.begin(), cur.point_id.end(), -1);  // of a rejected attempt
    res->rejected.clear();
    if (!trackFrom(cur, T_last, c.T_c_w, res, 0, roughSeed(c), c.moved_on)) continue;
    moved_on_after_dark = c.moved_on;
    res->used_pnp = !c.moved_on;
    return true;
  }
  return false;
}

std::optional<Eigen::Isometry3d> Tracker::Impl::movedOnSeed(const Frame& cur, const Eigen::Isometry3d& T_last) const {
  const long frames = cur.index - last.index;
  if (!have_velocity_before_dark || frames < 1) return std::nullopt;
  Eigen::Isometry3d T = T_last;
  for (long k = 0; k < frames; ++k) T = velocity_before_dark * T;
  return T;
}

void Tracker::Impl::rankByTrackedInliers(const Frame& cur, std::vector<RelocalizationCandidate>* candidates) const {
  if (candidates->size() < 2) return;
  std::vector<std::pair<int, size_t>> order;  // (-inliers, rank from the relocalizer)
  for (size_t k = 0; k < candidates->size(); ++k)
    order.emplace_back(
        -pose_tracker.inliersFrom(cur, (*candidates)[k].T_c_w, map, predictionUnknown() && !(*candidates)[k].moved_on,
                                  roughSeed((*candidates)[k])),
        k);
  std::sort(order.begin(), order.end());
  std::vector<RelocalizationCandidate> ranked;
  for (const auto& o : order) ranked.push_back((*candidates)[o.second]);
  *candidates = std::move(ranked);
}

}  // namespace iraf_vo
