#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

namespace {

/// The rules between TrackerParams fields (each field's own range is its table row).
std::string crossFieldRule(const TrackerParams& p) {
  std::string out;
  if (!(p.search_radius_wide_px >= p.search_radius_px))
    out += "search_radius_wide_px must be >= search_radius_px (got " + formatDouble(p.search_radius_wide_px) + " < " +
           formatDouble(p.search_radius_px) + ")";
  if (p.max_map_keyframes < p.ba_window_size)
    out += std::string(out.empty() ? "" : "; ") + "max_map_keyframes must be >= ba_window_size (got " +
           std::to_string(p.max_map_keyframes) + " < " + std::to_string(p.ba_window_size) + ")";
  return out;
}

}  // namespace

const ParamTable<TrackerParams>& trackerParamTable() {
  using P = TrackerParams;
  static const ParamTable<P> table(
      "tracker",
      {
          intParam("init_min_features", &P::init_min_features, 8, 10000, "Keypoints a reference frame needs"),
          intParam("init_min_matches", &P::init_min_matches, 8, 10000,
                   "Fewer matches to the reference -> new reference"),
          intParam("init_max_frames", &P::init_max_frames, 1, 1000, "Reference older than this -> new reference"),
          doubleParam("init_threshold_px", &P::init_threshold_px, 0.1, 10.0, "H / E RANSAC and scoring threshold [px]"),
          doubleParam("init_min_parallax_deg", &P::init_min_parallax_deg, 0.0, 20.0,
                      "Parallax the init_min_parallax_points-th most parallax-rich triangulated point needs [deg]"),
          intParam("init_min_parallax_points", &P::init_min_parallax_points, 0, 10000,
                   "Parallax test: this many triangulated points (all if fewer) need init_min_parallax_deg "
                   "(ORB-SLAM 50); 0 = the median point"),
          doubleParam("init_min_median_parallax_deg", &P::init_min_median_parallax_deg, 0.0, 20.0,
                      "Parallax test: the median triangulated point also needs this parallax [deg]"),
          intParam("init_determined_parallax_points", &P::init_determined_parallax_points, 0, 10000,
                   "Or, for an essential-matrix motion whose translation is determined (init_ambiguity_max_chi2 > 0): "
                   "this many points need init_min_parallax_deg, no median test; 0 = off"),
          doubleParam("init_determined_min_chi2", &P::init_determined_min_chi2, 0.0, 1e6,
                      "The translation counts as determined for init_determined_parallax_points when the ambiguity "
                      "check's profile chi2 is at least this"),
          intParam("init_min_triangulated", &P::init_min_triangulated, 8, 10000, "Points the initial map needs"),
          doubleParam("init_homography_ratio", &P::init_homography_ratio, 0.0, 1.0,
                      "R_H = S_H / (S_H + S_F) above this -> homography (ORB-SLAM 0.45)"),
          doubleParam("init_ambiguity_max_chi2", &P::init_ambiguity_max_chi2, 0.0, 1000.0,
                      "Essential-matrix init refused while a translation >= init_ambiguity_angle_deg away has a "
                      "profile chi2 below this (noise units; 0 = no check)"),
          doubleParam("init_ambiguity_angle_deg", &P::init_ambiguity_angle_deg, 1.0, 90.0,
                      "Translation directions this far from the chosen one count as another motion [deg]"),
          doubleParam("init_match_ratio", &P::init_match_ratio, 0.1, 1.0, "Lowe ratio of the initialization matching"),
          doubleParam("init_min_map_baseline", &P::init_min_map_baseline, 0.0, 1.0,
                      "Monocular: frames are reported TRACKING only once the map's keyframes span this fraction of the median scene depth; before, the young map is tracked and mapped and its frames are reported INITIALIZING (0 = from the initialization on)"),
          doubleParam("init_min_map_baseline_snr", &P::init_min_map_baseline_snr, 0.0, 1000.0,
                      "init_min_map_baseline applies to maps started on an image whose estimated SNR (before enhancement) is below this (0 = to every map)"),
          intParam("match_threshold_high", &P::match_threshold_high, 1, 256,
                   "Hamming threshold of the projection search (ORB-SLAM TH_HIGH)"),
          intParam("match_threshold_low", &P::match_threshold_low, 1, 256,
                   "Hamming threshold of triangulation matching (ORB-SLAM TH_LOW)"),
          doubleParam("match_ratio", &P::match_ratio, 0.1, 1.0,
                      "Best / second best in the projection search (same octave)"),
          doubleParam("search_radius_px", &P::search_radius_px, 1.0, 400.0,
                      "Projection search window at octave 0 [px] (x scale_factor^octave of the features)"),
          doubleParam("search_radius_wide_px", &P::search_radius_wide_px, 1.0, 1000.0,
                      "Fallback window when too few matches [px]"),
          doubleParam("search_radius_refine_px", &P::search_radius_refine_px, 0.5, 100.0,
                      "Second pass after the pose refinement [px]"),
          intParam("min_search_matches", &P::min_search_matches, 4, 10000,
                   "Fewer -> wider window, then brute force + PnP"),
          boolParam("check_orientation", &P::check_orientation,
                    "Rotation-consistency histogram in brute-force matching"),
          boolParam("predict_scale", &P::predict_scale,
                    "Projection searches at the octave the point's image scale predicts, skipping views > 60 deg off"),
          doubleParam("pnp_threshold_px", &P::pnp_threshold_px, 0.1, 50.0, "PnP RANSAC threshold [px]"),
          intParam("pnp_iterations", &P::pnp_iterations, 10, 10000, "PnP RANSAC iterations"),
          intParam("pose_rounds", &P::pose_rounds, 1, 10, "Pose refinement rounds (solve, chi2 outlier test)"),
          intParam("pose_max_iterations", &P::pose_max_iterations, 1, 100, "LM iterations per round"),
          boolParam("pose_use_ceres", &P::pose_use_ceres,
                    "Pose-only refinement with ceres::Solve instead of the 6x6 LM"),
          intParam("min_tracking_inliers", &P::min_tracking_inliers, 6, 10000, "Fewer inliers -> frame lost"),
          doubleParam("keyframe_tracked_ratio", &P::keyframe_tracked_ratio, 0.01, 1.0,
                      "New keyframe when inliers < ratio x reference keyframe's points (ORB-SLAM mono 0.9)"),
          intParam("keyframe_min_tracked", &P::keyframe_min_tracked, 0, 10000,
                   "New keyframe when inliers drop below this"),
          intParam("min_frames_between_keyframes", &P::min_frames_between_keyframes, 0, 1000,
                   "Minimum frames between keyframes"),
          intParam("max_frames_between_keyframes", &P::max_frames_between_keyframes, 1, 1000,
                   "Keyframe timeout [frames]"),
          doubleParam("keyframe_close_steps", &P::keyframe_close_steps, 0.0, 1000.0,
                      "Monocular keyframe rule: close points are nearer than this many frame steps (0 = off)"),
          doubleParam("keyframe_close_ratio", &P::keyframe_close_ratio, 0.0, 1.0,
                      "Monocular keyframe rule: no mapping wait while < this share of the reference's close points is tracked"),
          doubleParam("keyframe_forward_deg", &P::keyframe_forward_deg, 0.0, 90.0,
                      "Monocular keyframe rule: moving within this angle of the optical axis (sustained), a keyframe whenever a reference point is no longer tracked, no mapping wait [deg] (0 = off)"),
          intParam("keyframe_forward_frames", &P::keyframe_forward_frames, 1, 1000,
                   "Monocular keyframe rule: the forward motion counts as sustained when in 90 % of the last this many tracked frames (1: every forward frame)"),
          boolParam("mapping_thread", &P::mapping_thread,
                    "Mapping mode: BA on its own thread, written back at the next keyframe (false: inside track()); both deterministic"),
          intParam("mapping_busy_frames", &P::mapping_busy_frames, 0, 100,
                   "Keyframe rule: mapping counts as busy this many frames after a keyframe (both mapping modes)"),
          intParam("num_triangulation_neighbors", &P::num_triangulation_neighbors, 1, 50,
                   "Covisible keyframes used for new points"),
          doubleParam("min_triangulation_parallax_deg", &P::min_triangulation_parallax_deg, 0.0, 30.0,
                      "Minimum parallax of a new point [deg]"),
          doubleParam("candidate_parallax_ratio", &P::candidate_parallax_ratio, 0.0, 1.0,
                      "New points from this x min_triangulation_parallax_deg up to it are candidates: tracked and "
                      "bundle-adjusted, used for poses once their rays span the gate (1 = off)"),
          doubleParam("triangulation_match_ratio", &P::triangulation_match_ratio, 0.1, 1.0,
                      "New points: best match on the epipolar line < this x the best elsewhere on it (1 = off)"),
          doubleParam("min_found_ratio", &P::min_found_ratio, 0.0, 1.0,
                      "Cull recent points found in fewer than this fraction of the frames that saw them"),
          intParam("fuse_neighbors", &P::fuse_neighbors, 0, 50,
                   "Map-point fusion with this many most covisible keyframes per new keyframe (0 = off)"),
          doubleParam("fuse_radius_px", &P::fuse_radius_px, 0.5, 50.0,
                      "Fusion search window at octave 0 [px] (times scale_factor^octave)"),
          doubleParam("stereo_epipolar_px", &P::stereo_epipolar_px, 0.1, 50.0,
                      "Stereo: right candidates within this distance of the epipolar line (x the keypoint's sigma) [px]"),
          doubleParam("stereo_min_depth", &P::stereo_min_depth, 0.0, 100.0,
                      "Stereo: points from one stereo frame closer than this are dropped [m]"),
          doubleParam("stereo_max_depth_baselines", &P::stereo_max_depth_baselines, 1.0, 10000.0,
                      "Stereo: ... and farther than this many baselines (1000: ~0.5 px of disparity)"),
          doubleParam("stereo_min_disparity_px", &P::stereo_min_disparity_px, 0.0, 100.0,
                      "Stereo: ... and with less disparity than this (focal x baseline / depth; 0 = off) [px]"),
          intParam("stereo_init_min_points", &P::stereo_init_min_points, 8, 10000,
                   "Stereo: points the first (metric) map needs from one frame"),
          intParam("stereo_far_fill_points", &P::stereo_far_fill_points, 0, 10000,
                   "Stereo: a matched frame with fewer close points gets the nearest far ones up to this many"),
          boolParam("stereo_match_every_frame", &P::stereo_match_every_frame,
                    "Stereo: match left-right on every frame (right residuals in every pose refinement); false: on keyframes only"),
          intParam("stereo_ba_max_iterations", &P::stereo_ba_max_iterations, 0, 200,
                   "Stereo: Levenberg-Marquardt iterations per local BA of a stereo map (ba_max_num_iterations: monocular)"),
          intParam("stereo_scale_min_close_inliers", &P::stereo_scale_min_close_inliers, 0, 10000,
                   "Stereo: fewer pose inliers nearer than the close depth per frame (mean over stereo_scale_window_frames) -> "
                   "metric scale weakly observed, reported (0 = off)"),
          intParam("stereo_scale_window_frames", &P::stereo_scale_window_frames, 1, 1000,
                   "Stereo: tracked frames of that mean"),
          intParam("ba_window_size", &P::ba_window_size, 2, 100, "Keyframes optimized by the sliding-window BA"),
          intParam("max_map_keyframes", &P::max_map_keyframes, 2, 1000,
                   "Keyframes kept in the map (older are dropped; >= ba_window_size)"),
          intParam("ba_max_num_iterations", &P::ba_max_num_iterations, 0, 200, "Levenberg-Marquardt iterations per BA"),
          doubleParam("ba_max_solver_time_in_seconds", &P::ba_max_solver_time_in_seconds, 0.001, 10.0,
                      "BA budget per run [s of the mapping thread's CPU time]"),
          doubleParam("ba_min_fixed_span", &P::ba_min_fixed_span, 0.0, 1.0,
                      "Gauge: fixed keyframe centres must span this fraction of the window extent"),
          doubleParam("ba_huber_delta", &P::ba_huber_delta, 0.1, 100.0,
                      "Huber threshold on the sigma-normalized residual (sqrt(5.991))"),
          boolParam("ba_use_ceres", &P::ba_use_ceres,
                    "Every BA (initialization, local) with ceres::Solve instead of the equivalent Schur-complement LM"),
          intParam("lost_frames_before_reset", &P::lost_frames_before_reset, 0, 1000,
                   "Consecutive lost frames (relocalization attempts) before the map is reset"),
          boolParam("dark_check", &P::dark_check,
                    "Report a frame whose image carries no usable signal as lost (too dark), keeping the map"),
          doubleParam("dark_max_mean", &P::dark_max_mean, 0.0, 255.0,
                      "Only an image at most this bright (mean grey) can be too dark"),
          doubleParam("dark_min_snr", &P::dark_min_snr, 0.0, 100.0,
                      "A dark image is too dark below this estimated SNR (contrast / noise of its 4x4-pixel means)"),
          doubleParam("dark_min_contrast", &P::dark_min_contrast, 0.0, 255.0,
                      "A dark image is too dark below this contrast of its 4x4-pixel means above the noise [grey levels]"),
          doubleParam("washout_min_clipped", &P::washout_min_clipped, 0.0, 1.0,
                      "An image with at least this fraction of its 4x4-pixel means clipped white (>= 250) is washed out: no usable signal, like a dark one (1 = never)"),
          intParam("dark_relocalization_frames", &P::dark_relocalization_frames, 0, 100000,
                   "After dark frames: for this many frames a loss resets the map only after this many lost frames (relocalization in the same map), and the keyframe rule's reference is the keyframe sharing the most points with the frame"),
          doubleParam("dark_relocalization_max_depth_ratio", &P::dark_relocalization_max_depth_ratio, 0.0, 1000.0,
                      "A relocalization after darkness is refused while its inliers' median depth exceeds this multiple of the last tracked frame's (a pose on far points only; 0 = no check)"),
          boolParam("health_monitor", &P::health_monitor,
                    "Reject untrustworthy poses (reported lost, never tracking)"),
          doubleParam("health_min_inlier_ratio", &P::health_min_inlier_ratio, 0.0, 1.0,
                      "Inliers / matches of the final pose refinement"),
          doubleParam("health_max_median_chi2", &P::health_max_median_chi2, 0.1, 100.0,
                      "Median sigma-normalized squared reprojection error of the inliers"),
          doubleParam("health_max_accel_ratio", &P::health_max_accel_ratio, 0.1, 100.0,
                      "Velocity / rotation-rate change limit, x the median of the last frames"),
          doubleParam("health_min_accel_depth", &P::health_min_accel_depth, 0.0, 10.0,
                      "Motion-model deviation floor, x the median scene depth"),
          doubleParam("health_max_rot_accel_deg", &P::health_max_rot_accel_deg, 0.1, 180.0,
                      "Rotation-rate change floor [deg / frame]"),
          doubleParam("health_max_ba_scale_change", &P::health_max_ba_scale_change, 1.01, 100.0,
                      "Local BA may change the window extent by at most this factor"),
      },
      crossFieldRule, "search_radius_wide_px >= search_radius_px; max_map_keyframes >= ba_window_size");
  return table;
}

std::string validate(const TrackerParams& p) { return trackerParamTable().validate(p); }

}  // namespace iraf_vo
