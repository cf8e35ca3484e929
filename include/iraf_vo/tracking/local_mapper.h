// Local mapping: per new keyframe, cull recent points, update descriptors, create new map points by
// triangulation against the covisible keyframes, fuse them, run the sliding-window BA (local_ba.h) and bound
// the map. ROS-free.
//
//   for each new keyframe: cull recent points (found/visible < min_found_ratio, or <= 2 observations two
//   keyframes after creation), triangulate new points between the keyframe and its num_triangulation_neighbors
//   best covisible keyframes (unmatched keypoints, Hamming <= match_threshold_low, epipolar check on bearings,
//   cheirality, reprojection chi2, min_triangulation_parallax_deg), fuse the keyframe's points with those of its
//   fuse_neighbors most covisible keyframes (projection both ways: a keypoint without a point gets an observation,
//   two points on one keypoint are merged; ORB-SLAM's SearchInNeighbors), then sliding-window BA.
//
// One protocol, two modes (mapping_thread), the tracker calls the same methods in both:
//   addKeyframe / acceptKeyframe  tracking thread, holding Map::lockUpdates: the keyframe enters the map and is
//                                 mapped (cull, descriptors, triangulation, fusion) right there, so the next
//                                 frames match its new points.
//   insertKeyframe                tracking thread, lock released: BA of the window ending at the keyframe.
//   synchronous: BA runs inside insertKeyframe, its result is written back and the map bounded at once.
//   threaded:    BA runs on the mapping thread while tracking goes on; the tracking thread writes its result
//                back (and bounds the map) when it adds the next keyframe, waiting for it there. BA always
//                starts from the map of its keyframe and lands at the next one: a threaded run gives the same
//                trajectory every time, one keyframe's BA later than a synchronous run.
// BA: Huber loss on sigma-normalized pixel residuals, bounded by ba_max_num_iterations (a stereo map:
//   stereo_ba_max_iterations) and by ba_max_solver_time_in_seconds of CPU time of the mapping thread (not wall
//   clock: load-independent); observations failing chi2 afterwards are removed.
#pragma once

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/camera/stereo_rig.h"
#include "iraf_vo/tracking/local_ba.h"
#include "iraf_vo/tracking/map.h"
#include "iraf_vo/tracking/matcher.h"
#include "iraf_vo/tracking/tracker_params.h"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

namespace iraf_vo {

struct LocalMapperStats {
  long ba_runs = 0;
  double ba_ms_total = 0.0;      // wall time of bundleAdjust
  double ba_cpu_ms_total = 0.0;  // thread CPU time of the window's build and bundleAdjust (load-independent)
  double ba_final_rmse_px = 0.0;  // last BA
};

/// Scale consistency of a new point's match: the ratio of its distances d2 / d1 from the two keyframes agrees with the
/// ratio of the keypoints' octave scales (octave_ratio = sigma1 / sigma2) within a factor 1.5 x scale_factor.
bool scaleConsistent(double d1, double d2, double octave_ratio, double scale_factor);

class LocalMapper {
 public:
  /// Starts the mapping thread when params.mapping_thread. camera, params, map must outlive the mapper.
  LocalMapper(const CameraModel& camera, const TrackerParams& params, Map* map);
  ~LocalMapper();
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  /// Tracking thread, holding Map::lockUpdates: adds the frame to the map as a keyframe (after the running BA,
  /// whose window thus never depends on thread timing) and accepts it (acceptKeyframe). Returns its id.
  /// stereo: the frame's left-right points for keypoints without a map point (added before the triangulation).
  long addKeyframe(const Frame& f, const std::vector<StereoMapPoint>& stereo = {});
  /// Tracking thread, holding Map::lockUpdates, for a keyframe in the map (a new one, or the initializer's
  /// second): threaded, writes the last BA result back and bounds the map (waiting for the BA); then culls,
  /// updates descriptors, triangulates and fuses the keyframe's points.
  void acceptKeyframe(long kf_id);
  /// Tracking thread, lock released, after acceptKeyframe: the BA of the window ending at kf_id, synchronous
  /// (written back at once, then the map is bounded) or on the mapping thread (written back by the next
  /// acceptKeyframe).
  void insertKeyframe(long kf_id);
  /// No BA running (always true for synchronous mapping).
  bool idle() const;
  /// Blocks until the running BA is done.
  void waitUntilIdle();
  /// Aborts a running BA, waits for it and drops its result (map reset).
  void clearQueue();
  /// Triangulates the keyframe's new points (once per keyframe) and fuses them.
  void createNewMapPoints(long kf_id);
  LocalMapperStats stats() const;
  /// Stereo: the local BA adds the keyframes' right-image residuals and fixes no scale (call before the first
  /// keyframe; rig must outlive the mapper).
  void setStereo(const StereoRig* rig) { rig_ = rig; }
  /// The largest change of the window's extent (after / before, or its inverse if that is larger, as a factor
  /// >= 1 with the direction kept: < 1 shrank) by a local BA written back since the last call; 1 when none was.
  /// Counted when the result reaches the map (threaded: at the next keyframe), not when the BA ends, so the
  /// frame that sees it does not depend on thread timing.
  double takeScaleChange();

 private:
  struct PendingBA {
    LocalBAProblem problem;
    BASummary summary;
    double extent_before = 0.0;  // the window's extent before the BA (recordScaleChange at write-back)
  };
  void run();
  void mapKeyframe(long kf_id);  // cull, descriptors, triangulation, fusion
  void fuseMapPoints(long kf_id);
  void commitPendingBA();  // threaded: waits for the running BA and writes its result back
  void localBundleAdjustment();
  /// Candidate points of the BA's problem whose rays now span the parallax gate join the poses (Map::promoteCandidates).
  void promoteCandidates(const LocalBAProblem& prob);
  void recordScaleChange(double extent_before, const LocalBAProblem& after);

  const CameraModel& cam_;
  const TrackerParams& p_;
  Map* map_;
  Matcher matcher_;
  const StereoRig* rig_ = nullptr;

  mutable std::mutex queue_mutex_;
  std::condition_variable queue_cv_, idle_cv_;
  std::deque<long> queue_;
  bool busy_ = false, stop_ = false;
  std::atomic<bool> abort_ba_{false};
  std::mutex scale_mutex_;
  double scale_change_ = 1.0;  // guarded by scale_mutex_
  std::unique_ptr<PendingBA> pending_ba_;  // threaded: the last BA result (guarded by queue_mutex_)
  std::thread thread_;

  mutable std::mutex stats_mutex_;
  LocalMapperStats stats_;
};

}  // namespace iraf_vo
