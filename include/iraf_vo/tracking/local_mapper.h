// Local mapping: per new keyframe, cull recent points, update descriptors, create new map points by
// triangulation against the covisible keyframes, run the sliding-window BA (local_ba.h) and bound the map.
// Runs on its own thread (mapping_thread = true) or synchronously inside insertKeyframe. ROS-free.
//
//   for each new keyframe: cull recent points (found/visible < min_found_ratio, or <= 2 observations two
//   keyframes after creation), triangulate new points between the keyframe and its num_triangulation_neighbors
//   best covisible keyframes (unmatched keypoints, Hamming <= match_threshold_low, epipolar check on bearings,
//   cheirality, reprojection chi2, min_triangulation_parallax_deg), fuse the keyframe's points with those of its
//   fuse_neighbors most covisible keyframes (projection both ways: a keypoint without a point gets an observation,
//   two points on one keypoint are merged; ORB-SLAM's SearchInNeighbors), then sliding-window BA when no other
//   keyframe is waiting or ba_every_keyframes keyframes were processed since the last BA.
// Threaded: the tracking thread usually triangulated the keyframe already (triangulate_in_tracking; claimed
//   once per keyframe), the mapping thread then culls, updates descriptors and runs BA.
// BA: Huber loss on sigma-normalized pixel residuals, bounded by ba_max_num_iterations and by
//   ba_max_solver_time_in_seconds of CPU time of the mapping thread (not wall clock: load-independent), aborted when a new keyframe arrives if ba_abort_on_keyframe; results are
//   merged under the map mutex; observations failing chi2 afterwards are removed.
#pragma once

#include "iraf_vo/camera/camera_model.h"
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

class LocalMapper {
 public:
  /// Starts the mapping thread when params.mapping_thread. camera, params, map must outlive the mapper.
  LocalMapper(const CameraModel& camera, const TrackerParams& params, Map* map);
  ~LocalMapper();
  LocalMapper(const LocalMapper&) = delete;
  LocalMapper& operator=(const LocalMapper&) = delete;

  /// Queues a keyframe (threaded; waits while max_pending_keyframes are pending = back-pressure under overload)
  /// or processes it right here (synchronous mapping).
  void insertKeyframe(long kf_id);
  /// No keyframe queued or being processed (always true for synchronous mapping).
  bool idle() const;
  /// Blocks until every queued keyframe is processed.
  void waitUntilIdle();
  /// Drops queued keyframes, aborts a running BA and waits until the thread is idle (map reset).
  void clearQueue();
  /// Triangulates the keyframe's new points (once per keyframe; the tracker calls it when the map starves).
  void createNewMapPoints(long kf_id);
  /// Deferred commit (mapping_thread && ba_deferred_commit), called by the tracking thread for a new keyframe
  /// (holding Map::lockUpdates): waits for the running BA, writes its result back, bounds the map, then culls,
  /// updates descriptors and triangulates for kf_id. The thread then only runs BA (insertKeyframe). Every
  /// frame thus sees a map that does not depend on thread timing.
  void mapKeyframeInTracking(long kf_id);
  /// Deferred commit: waits for the running BA and writes its result back (tracking thread, holding
  /// Map::lockUpdates); nothing when no result is pending. True when a result was written back.
  bool commitPendingBA();
  LocalMapperStats stats() const;
  /// The largest change of the window's extent (after / before, or its inverse if that is larger, as a factor
  /// >= 1 with the direction kept: < 1 shrank) by a local BA since the last call; 1 when none ran.
  double takeScaleChange();

 private:
  struct PendingBA {
    LocalBAProblem problem;
    BASummary summary;
  };
  void run();
  bool deferred() const;
  void mapKeyframe(long kf_id);  // cull, descriptors, triangulation, fusion
  void fuseMapPoints(long kf_id);
  void processKeyframe(long kf_id, bool run_ba);
  void localBundleAdjustment();
  void recordScaleChange(double extent_before, const LocalBAProblem& after);

  const CameraModel& cam_;
  const TrackerParams& p_;
  Map* map_;
  Matcher matcher_;

  mutable std::mutex queue_mutex_;
  std::condition_variable queue_cv_, idle_cv_;
  std::deque<long> queue_;
  bool busy_ = false, stop_ = false;
  int keyframes_since_ba_ = 0;  // mapping thread only
  std::atomic<bool> abort_ba_{false};
  std::mutex scale_mutex_;
  double scale_change_ = 1.0;  // guarded by scale_mutex_
  std::unique_ptr<PendingBA> pending_ba_;  // deferred commit: the last BA result (guarded by queue_mutex_)
  std::thread thread_;

  mutable std::mutex stats_mutex_;
  LocalMapperStats stats_;
};

}  // namespace iraf_vo
