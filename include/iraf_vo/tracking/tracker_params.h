// Parameters of the tracking / mapping back-end: the struct (its initializers are the defaults) and its parameter
// table (common/param_table.h): names = field names = cfg/Tracker.cfg parameters = YAML `tracker:` keys =
// `--set tracker.key=value` = the tracker nodelet's private parameters. ROS-free.
#pragma once

#include <string>

#include "iraf_vo/common/param_table.h"

namespace iraf_vo {

struct TrackerParams {
  // ---- initialization ----
  int init_min_features = 100;          // a reference frame needs at least this many keypoints
  int init_min_matches = 100;           // fewer matches to the reference -> new reference
  int init_max_frames = 30;             // reference older than this -> new reference
  double init_threshold_px = 1.5;       // H / E RANSAC and scoring threshold
  double init_min_parallax_deg = 1.0;   // parallax test (ORB-SLAM CheckRT): the init_min_parallax_points-th
  int init_min_parallax_points = 50;    // largest parallax of the triangulated points >= init_min_parallax_deg
                                        // (0 = the median point: stricter for forward motion, where points
                                        // near the focus of expansion have almost no parallax; 1 m forward on
                                        // sim_drive: median 0.6 deg, 50th best > 1 deg)
  double init_min_median_parallax_deg = 0.5;  // ... and the median point this much. A homography's median point
                                              // needs init_min_parallax_deg (a homography fitted to a non-planar
                                              // scene after 6 cm at 4-10 m showed 0.95 deg, E 0.2: wrong map)
  int init_determined_parallax_points = 10;  // or, for an essential-matrix motion whose translation the ambiguity
                                             // check finds determined: this many points with init_min_parallax_deg
                                             // and no median test (forward driving past far structure: the few
                                             // near points carry the parallax); 0 = off
  double init_determined_min_chi2 = 60.0;  // ... determined: the ambiguity check's profile chi2 >= this (forward
                                           // drives 106-220; hand-held bas-relief starts at 2-3 px noise 10-45)
  int init_min_triangulated = 60;
  double init_homography_ratio = 0.45;  // R_H threshold (ORB-SLAM)
  double init_ambiguity_max_chi2 = 9.21;  // translation-direction check of E inits (two_view_ambiguity.h): refused
  double init_ambiguity_angle_deg = 20.0; // while a direction this far away has a profile chi2 below 9.21 (99 %,
                                          // 2 dof, in units of the estimated noise); 0 = no check
  double init_match_ratio = 0.8;        // Lowe ratio of the initialization matching
  double init_min_map_baseline = 0.05;  // monocular: poses reported once the keyframes span this fraction of the
                                        // median depth (a young map's scale moves with each BA until then); 0 = off
  double init_min_map_baseline_snr = 8.0;  // ... for maps started on an image of estimated SNR below this (noisy,
                                           // high gain: docs/decisions.md); 0 = for every map
  // ---- matching ----
  int match_threshold_high = 100;       // Hamming, projection search (ORB-SLAM TH_HIGH)
  int match_threshold_low = 50;         // Hamming, triangulation / brute force (ORB-SLAM TH_LOW)
  double match_ratio = 0.8;             // best / second-best (same octave) in projection search
  double search_radius_px = 15.0;       // projection search window at octave 0 (times FeatureFrame::scale_factor^octave)
  double search_radius_wide_px = 40.0;  // fallback window
  double search_radius_refine_px = 4.0; // second pass after the pose refinement
  int min_search_matches = 30;          // fewer -> widen the window, then PnP fallback
  bool check_orientation = true;        // rotation-consistency histogram in brute-force matching
  // ---- pose refinement / tracking ----
  double pnp_threshold_px = 3.0;
  int pnp_iterations = 200;
  int pose_rounds = 3;
  int pose_max_iterations = 10;
  bool pose_use_ceres = false;          // pose-only refinement with ceres::Solve instead of the 6x6 LM
  int min_tracking_inliers = 25;
  // ---- keyframes ----
  double keyframe_tracked_ratio = 0.9;
  int keyframe_min_tracked = 80;
  int min_frames_between_keyframes = 0;
  int max_frames_between_keyframes = 20;
  double keyframe_close_steps = 35.0;   // monocular: a point is close when nearer than this many frame steps (the
                                        // camera's motion over the last frame; ORB-SLAM stereo: 35 baselines);
                                        // 0 = off
  double keyframe_close_ratio = 0.5;    // mapping counts as idle while the frame tracks fewer than this share of
                                        // the reference keyframe's close points (a thin near map running out)
  double keyframe_forward_deg = 25.0;   // monocular: while the motion model moves the camera within this angle of
                                        // its optical axis (sustained: keyframe_forward_frames), a keyframe on every
                                        // frame that tracks fewer of the reference keyframe's points than it has,
                                        // no mapping wait; 0 = off (keyframe_policy.h, docs/decisions.md)
  int keyframe_forward_frames = 10;     // ... sustained: forward in 90 % of the last this many tracked frames
  // ---- local mapping ----
  bool mapping_thread = true;           // the mapping mode (local_mapper.h): BA on the mapping thread, written back
                                        // at the next keyframe; false: BA inside track(). Both deterministic.
  int mapping_busy_frames = 3;          // the keyframe policy treats mapping as busy for this many frames after a
                                        // keyframe (both modes: the threaded mapper's real state made the
                                        // keyframes depend on the machine's load)
  int num_triangulation_neighbors = 6;
  double min_triangulation_parallax_deg = 1.0;
  double candidate_parallax_ratio = 0.25;  // new points with a parallax from this x the gate up to the gate are
                                           // candidates: tracked and bundle-adjusted, in no pose until a BA's
                                           // rays span the gate (a gate on the measured parallax keeps the far
                                           // points whose noise shortened their depth; 1 = off)
  double triangulation_match_ratio = 0.6;  // new-point matching along the epipolar line: best < this x the best
                                           // elsewhere on the line (same-corner keypoints within 5 px excepted;
                                           // repeated texture, e.g. facades on a horizontal line; 1 = off)
  double min_found_ratio = 0.25;
  bool predict_scale = false;           // projection searches expect a point at the octave its image scale predicts
                                        // (ORB-SLAM's PredictScale) and skip it beyond 60 deg off its reference view;
                                        // false: at the octave it was created at, from any side (see docs/decisions.md)
  int fuse_neighbors = 0;               // map-point fusion with this many most covisible keyframes (0 = off; see docs/decisions.md)
  double fuse_radius_px = 3.0;          // fusion search window at octave 0 (times scale_factor^octave)
  // ---- stereo (stereo_matcher.h; a monocular tracker ignores them) ----
  double stereo_epipolar_px = 2.0;          // left-right candidates within this distance of the epipolar line
                                            // (x the keypoint's sigma) [px]
  double stereo_min_depth = 0.1;            // stereo points closer than this are dropped [m]
  double stereo_max_depth_baselines = 1000.0;  // ... and farther than this many baselines (stereo_matcher.h)
  double stereo_min_disparity_px = 2.0;      // ... and with less disparity than this (stereo_matcher.h)
  int stereo_init_min_points = 40;          // stereo points the first (metric) map needs from one frame (ORB-SLAM
                                            // has no minimum). A wide baseline on a close scene repeats few
                                            // keypoints in the right image (KITTI rig, 0.54 m, at 0.4-4 m: 33-99
                                            // per frame). The next frame's search needs min_search_matches (30)
                                            // of them: a start with 34 found 28-30 and was lost, 42 tracked
  int stereo_far_fill_points = 200;         // a matched frame with fewer close points than this gets the nearest
                                            // far ones up to it (ORB-SLAM's stereo keyframe rule, with 100; 200:
                                            // a 512-px fisheye road start keeps tracking, docs/decisions.md)
  bool stereo_match_every_frame = false;    // true: left-right matching (and the right front-end) on every frame,
                                            // right residuals in every pose refinement; false: on the
                                            // initialization and keyframes only, whose pose is refined again
                                            // with them (docs/stereo.md)
  int stereo_ba_max_iterations = 5;         // local BA iterations of a stereo map (ba_max_num_iterations: of a
                                            // monocular one): its cost falls < 0.1 % per iteration after ~4
  int stereo_scale_min_close_inliers = 15;  // fewer close pose inliers per frame (mean over the window): the metric
                                            // scale is weakly observed (MetricScaleMonitor; 0 = off)
  int stereo_scale_window_frames = 10;      // tracked frames of that mean
  // ---- sliding-window BA ----
  int ba_window_size = 10;
  int max_map_keyframes = 25;           // keyframes kept (older are dropped); the local BA's fixed anchors are the
                                        // kept ones outside its window that see window points (see docs/decisions.md)
  int ba_max_num_iterations = 10;
  double ba_max_solver_time_in_seconds = 0.1;  // CPU time of the mapping thread (not wall clock: under load
                                               // a wall-clock budget left BA at 0-1 iterations)
  double ba_huber_delta = 2.447;        // sqrt(5.991) on the sigma-normalized residual
  bool ba_use_ceres = false;            // every BA (initialization and local) with ceres::Solve instead of the equivalent Schur-complement
                                        // LM (schur_lm.h; same steps, ~3x less CPU)
  double ba_min_fixed_span = 0.3;       // gauge: fixed keyframe centres must span >= this fraction of the window
  // ---- loss ----
  int lost_frames_before_reset = 2;
  // ---- darkness (signal_check.h): a frame whose image carries no usable signal is LOST, the map is kept ----
  bool dark_check = true;
  double dark_max_mean = 40.0;          // only an image at most this bright (mean grey) can be too dark ...
  double dark_min_snr = 1.0;            // ... it is when its estimated SNR (contrast / noise of its 4x4-pixel
                                        // means, image_signal.h) is below this
  double dark_min_contrast = 0.3;       // ... or the contrast of those means above the noise is below this [grey]
  double washout_min_clipped = 0.85;    // an image with at least this fraction of its 4x4-pixel means clipped
                                        // white (>= 250) is washed out: no usable signal either (1 = never)
  int dark_relocalization_frames = 40;  // for this many frames after dark ones a loss resets the map only after
                                        // this many lost frames (instead of lost_frames_before_reset): the
                                        // tracker relocalizes in the same map meanwhile
  double dark_relocalization_max_depth_ratio = 2.5;  // a relocalization after darkness is refused while its inliers'
                                        // median depth exceeds this multiple of the last tracked frame's: a pose
                                        // on far points only rests on their poorly known depth (0 = no check)
  // ---- health monitor (health_monitor.h): a pose that fails a check is reported LOST, never TRACKING ----
  bool health_monitor = true;
  double health_min_inlier_ratio = 0.5;    // inliers / matches of the final pose refinement
  double health_max_median_chi2 = 3.0;     // median sigma-normalized squared reprojection error of the inliers
  double health_max_accel_ratio = 2.0;     // velocity change limit, x the median speed of the last frames
  double health_min_accel_depth = 0.02;    // motion-model deviation floor, x the median scene depth
  double health_max_rot_accel_deg = 3.0;   // rotation-rate change floor [deg / frame]
  double health_max_ba_scale_change = 1.5; // local BA may change the window's extent by at most this factor
};

/// Every TrackerParams field with its accepted range and doc.
const ParamTable<TrackerParams>& trackerParamTable();

/// Returns a message naming each field out of its table range and each broken cross-field rule, or "" when usable.
std::string validate(const TrackerParams& p);

}  // namespace iraf_vo
