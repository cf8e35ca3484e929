#include <iraf_vo/tracking/tracker_params.h>

#include <cmath>
#include <utility>

namespace iraf_vo {

std::string validate(const TrackerParams& p) {
  auto bad = [](const std::string& k, const std::string& why) { return "TrackerParams." + k + ": " + why; };
  // Fields bounded below only: +inf passed and reached int casts (e.g. search radius / cell -> grid index).
  for (const auto& kv : {std::make_pair("init_threshold_px", p.init_threshold_px),
                         std::make_pair("init_min_parallax_deg", p.init_min_parallax_deg),
                         std::make_pair("init_min_median_parallax_deg", p.init_min_median_parallax_deg),
                         std::make_pair("search_radius_px", p.search_radius_px),
                         std::make_pair("search_radius_wide_px", p.search_radius_wide_px),
                         std::make_pair("search_radius_refine_px", p.search_radius_refine_px),
                         std::make_pair("pnp_threshold_px", p.pnp_threshold_px),
                         std::make_pair("min_triangulation_parallax_deg", p.min_triangulation_parallax_deg),
                         std::make_pair("fuse_radius_px", p.fuse_radius_px),
                         std::make_pair("ba_max_solver_time_in_seconds", p.ba_max_solver_time_in_seconds),
                         std::make_pair("ba_huber_delta", p.ba_huber_delta)})
    if (!std::isfinite(kv.second)) return bad(kv.first, "must be finite");
  if (p.init_min_features < 8) return bad("init_min_features", "must be >= 8");
  if (p.init_min_matches < 8) return bad("init_min_matches", "must be >= 8");
  if (p.init_max_frames < 1) return bad("init_max_frames", "must be >= 1");
  if (!(p.init_threshold_px > 0)) return bad("init_threshold_px", "must be > 0");
  if (!(p.init_min_parallax_deg >= 0)) return bad("init_min_parallax_deg", "must be >= 0");
  if (!(p.init_min_median_parallax_deg >= 0)) return bad("init_min_median_parallax_deg", "must be >= 0");
  if (p.init_min_parallax_points < 0) return bad("init_min_parallax_points", "must be >= 0");
  if (p.init_min_triangulated < 8) return bad("init_min_triangulated", "must be >= 8");
  if (!(p.init_homography_ratio >= 0 && p.init_homography_ratio <= 1)) return bad("init_homography_ratio", "must be in [0, 1]");
  if (!(p.init_ambiguity_max_chi2 >= 0)) return bad("init_ambiguity_max_chi2", "must be >= 0");
  if (!(p.init_ambiguity_angle_deg > 0 && p.init_ambiguity_angle_deg <= 90)) return bad("init_ambiguity_angle_deg", "must be in (0, 90]");
  if (!(p.init_match_ratio > 0 && p.init_match_ratio <= 1)) return bad("init_match_ratio", "must be in (0, 1]");
  if (p.match_threshold_high < 1 || p.match_threshold_high > 256) return bad("match_threshold_high", "must be in [1, 256]");
  if (p.match_threshold_low < 1 || p.match_threshold_low > 256) return bad("match_threshold_low", "must be in [1, 256]");
  if (!(p.match_ratio > 0 && p.match_ratio <= 1)) return bad("match_ratio", "must be in (0, 1]");
  if (!(p.search_radius_px > 0)) return bad("search_radius_px", "must be > 0");
  if (!(p.search_radius_wide_px >= p.search_radius_px)) return bad("search_radius_wide_px", "must be >= search_radius_px");
  if (!(p.search_radius_refine_px > 0)) return bad("search_radius_refine_px", "must be > 0");
  if (p.min_search_matches < 4) return bad("min_search_matches", "must be >= 4");
  if (!(p.pnp_threshold_px > 0)) return bad("pnp_threshold_px", "must be > 0");
  if (p.pnp_iterations < 10) return bad("pnp_iterations", "must be >= 10");
  if (p.pose_rounds < 1) return bad("pose_rounds", "must be >= 1");
  if (p.pose_max_iterations < 1) return bad("pose_max_iterations", "must be >= 1");
  if (p.min_tracking_inliers < 6) return bad("min_tracking_inliers", "must be >= 6");
  if (!(p.keyframe_tracked_ratio > 0 && p.keyframe_tracked_ratio <= 1)) return bad("keyframe_tracked_ratio", "must be in (0, 1]");
  if (p.keyframe_min_tracked < 0) return bad("keyframe_min_tracked", "must be >= 0");
  if (p.min_frames_between_keyframes < 0) return bad("min_frames_between_keyframes", "must be >= 0");
  if (p.max_frames_between_keyframes < 1) return bad("max_frames_between_keyframes", "must be >= 1");
  if (p.num_triangulation_neighbors < 1) return bad("num_triangulation_neighbors", "must be >= 1");
  if (p.fuse_neighbors < 0) return bad("fuse_neighbors", "must be >= 0");
  if (!(p.fuse_radius_px > 0)) return bad("fuse_radius_px", "must be > 0");
  if (!(p.min_triangulation_parallax_deg >= 0)) return bad("min_triangulation_parallax_deg", "must be >= 0");
  if (!(p.min_found_ratio >= 0 && p.min_found_ratio <= 1)) return bad("min_found_ratio", "must be in [0, 1]");
  if (p.ba_window_size < 2) return bad("ba_window_size", "must be >= 2");
  if (p.max_map_keyframes < p.ba_window_size) return bad("max_map_keyframes", "must be >= ba_window_size");
  if (p.ba_max_num_iterations < 0) return bad("ba_max_num_iterations", "must be >= 0");
  if (!(p.ba_max_solver_time_in_seconds > 0)) return bad("ba_max_solver_time_in_seconds", "must be > 0");
  if (!(p.ba_huber_delta > 0)) return bad("ba_huber_delta", "must be > 0");
  if (p.starving_inliers < 0) return bad("starving_inliers", "must be >= 0");
  if (p.ba_commit_frames < 0) return bad("ba_commit_frames", "must be >= 0");
  if (p.sync_mapping_busy_frames < 0) return bad("sync_mapping_busy_frames", "must be >= 0");
  if (p.lost_frames_before_reset < 0) return bad("lost_frames_before_reset", "must be >= 0");
  if (!(p.dark_max_mean >= 0 && p.dark_max_mean <= 255)) return bad("dark_max_mean", "must be in [0, 255]");
  if (!(p.dark_min_snr >= 0 && std::isfinite(p.dark_min_snr))) return bad("dark_min_snr", "must be >= 0 and finite");
  if (!(p.dark_min_contrast >= 0 && std::isfinite(p.dark_min_contrast))) return bad("dark_min_contrast", "must be >= 0 and finite");
  if (p.dark_relocalization_frames < 0) return bad("dark_relocalization_frames", "must be >= 0");
  if (!(p.health_min_inlier_ratio >= 0 && p.health_min_inlier_ratio <= 1)) return bad("health_min_inlier_ratio", "must be in [0, 1]");
  if (!(p.health_max_median_chi2 > 0 && std::isfinite(p.health_max_median_chi2))) return bad("health_max_median_chi2", "must be > 0 and finite");
  if (!(p.health_max_accel_ratio > 0 && std::isfinite(p.health_max_accel_ratio))) return bad("health_max_accel_ratio", "must be > 0 and finite");
  if (!(p.health_min_accel_depth >= 0 && std::isfinite(p.health_min_accel_depth))) return bad("health_min_accel_depth", "must be >= 0 and finite");
  if (!(p.health_max_rot_accel_deg > 0 && std::isfinite(p.health_max_rot_accel_deg))) return bad("health_max_rot_accel_deg", "must be > 0 and finite");
  if (!(p.health_max_ba_scale_change > 1 && std::isfinite(p.health_max_ba_scale_change))) return bad("health_max_ba_scale_change", "must be > 1 and finite");
  return "";
}

}  // namespace iraf_vo
