#include <iraf_vo/tracking/tracker_params_io.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>

namespace iraf_vo {

namespace {

using Setter = std::function<bool(TrackerParams*, const std::string&)>;

bool parseInt(const std::string& s, int* v) {
  char* end = nullptr;
  const long x = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || !end || *end != '\0') return false;
  *v = static_cast<int>(x);
  return true;
}
bool parseDouble(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0' && std::isfinite(*v);
}
bool parseBool(const std::string& s, bool* v) {
  if (s == "true" || s == "1" || s == "True" || s == "TRUE") return (*v = true), true;
  if (s == "false" || s == "0" || s == "False" || s == "FALSE") return (*v = false), true;
  return false;
}

const std::map<std::string, Setter>& setters() {
  static const std::map<std::string, Setter> m = [] {
    std::map<std::string, Setter> s;
#define IRAF_INT(name) s[#name] = [](TrackerParams* p, const std::string& v) { return parseInt(v, &p->name); };
#define IRAF_DBL(name) s[#name] = [](TrackerParams* p, const std::string& v) { return parseDouble(v, &p->name); };
#define IRAF_BOOL(name) s[#name] = [](TrackerParams* p, const std::string& v) { return parseBool(v, &p->name); };
    IRAF_DBL(scale_factor)
    IRAF_INT(init_min_features)
    IRAF_INT(init_min_matches)
    IRAF_INT(init_max_frames)
    IRAF_DBL(init_threshold_px)
    IRAF_DBL(init_min_parallax_deg)
    IRAF_INT(init_min_triangulated)
    IRAF_DBL(init_homography_ratio)
    IRAF_DBL(init_match_ratio)
    IRAF_INT(match_threshold_high)
    IRAF_INT(match_threshold_low)
    IRAF_DBL(match_ratio)
    IRAF_DBL(search_radius_px)
    IRAF_DBL(search_radius_wide_px)
    IRAF_DBL(search_radius_refine_px)
    IRAF_INT(min_search_matches)
    IRAF_BOOL(check_orientation)
    IRAF_DBL(pnp_threshold_px)
    IRAF_INT(pnp_iterations)
    IRAF_INT(pose_rounds)
    IRAF_INT(pose_max_iterations)
    IRAF_BOOL(pose_use_ceres)
    IRAF_INT(min_tracking_inliers)
    IRAF_DBL(keyframe_tracked_ratio)
    IRAF_INT(keyframe_min_tracked)
    IRAF_INT(min_frames_between_keyframes)
    IRAF_INT(max_frames_between_keyframes)
    IRAF_BOOL(mapping_thread)
    IRAF_INT(starving_inliers)
    IRAF_INT(sync_mapping_busy_frames)
    IRAF_INT(num_triangulation_neighbors)
    IRAF_DBL(min_triangulation_parallax_deg)
    IRAF_DBL(min_found_ratio)
    IRAF_INT(ba_window_size)
    IRAF_INT(max_map_keyframes)
    IRAF_INT(ba_max_num_iterations)
    IRAF_DBL(ba_max_solver_time_in_seconds)
    IRAF_DBL(ba_huber_delta)
    IRAF_BOOL(ba_abort_on_keyframe)
    IRAF_DBL(ba_min_fixed_span)
    IRAF_INT(ba_every_keyframes)
    IRAF_INT(max_pending_keyframes)
    IRAF_INT(lost_frames_before_reset)
    IRAF_BOOL(health_monitor)
    IRAF_DBL(health_min_inlier_ratio)
    IRAF_DBL(health_max_median_chi2)
    IRAF_DBL(health_max_accel_ratio)
    IRAF_DBL(health_min_accel_depth)
    IRAF_DBL(health_max_rot_accel_deg)
    IRAF_DBL(health_max_ba_scale_change)
#undef IRAF_INT
#undef IRAF_DBL
#undef IRAF_BOOL
    return s;
  }();
  return m;
}

}  // namespace

bool setTrackerParam(TrackerParams* p, const std::string& key, const std::string& value, std::string* error) {
  const auto it = setters().find(key);
  if (it == setters().end()) {
    if (error) *error = "unknown tracker parameter '" + key + "'";
    return false;
  }
  if (!it->second(p, value)) {
    if (error) *error = "tracker parameter '" + key + "': cannot parse value '" + value + "'";
    return false;
  }
  return true;
}

std::vector<std::string> trackerParamNames() {
  std::vector<std::string> out;
  for (const auto& kv : setters()) out.push_back(kv.first);
  return out;
}

bool loadTrackerParams(const YAML::Node& node, TrackerParams* p, std::string* error) {
  if (!node || node.IsNull()) return true;
  if (!node.IsMap()) {
    if (error) *error = "tracker parameters: expected a map of key: value";
    return false;
  }
  TrackerParams tmp = *p;
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>("");  // fallback: a non-scalar key (e.g. "? ? 4") threw
    if (!kv.second.IsScalar()) {
      if (error) *error = "tracker parameter '" + key + "': expected a scalar value";
      return false;
    }
    if (!setTrackerParam(&tmp, key, kv.second.as<std::string>(), error)) return false;
  }
  const std::string v = validate(tmp);
  if (!v.empty()) {
    if (error) *error = v;
    return false;
  }
  *p = tmp;
  return true;
}

}  // namespace iraf_vo
