#include "iraf_vo/pipeline/pipeline_params.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "iraf_vo/enhance/enhance_params_io.h"
#include "iraf_vo/tracking/tracker_params_io.h"

namespace iraf_vo {

bool loadPipelineConfig(const std::string& path, PipelineParams* p, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  std::string err;
  bool ok = true;
  if (root["enhance"] && !enhanceParamTable().load(root["enhance"], &p->enhance, &err))
    ok = false;
  else if (root["features"] && !featureParamTable().load(root["features"], &p->features, &err))
    ok = false;
  else if (root["tracker"] && !trackerParamTable().load(root["tracker"], &p->tracker, &err))
    ok = false;
  if (!ok) *error = path + ": " + err;
  for (const char* section : {"enhance", "features", "tracker"})
    if (ok && root[section] && root[section].IsMap())
      for (const auto& kv : root[section]) p->user_set.insert(std::string(section) + "." + kv.first.as<std::string>());
  return ok;
}

bool applyPipelineSetting(const std::string& setting, PipelineParams* p, std::string* error) {
  const size_t dot = setting.find('.'), eq = setting.find('=');
  if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
    *error = "expected section.key=value";
    return false;
  }
  const std::string section = setting.substr(0, dot), key = setting.substr(dot + 1, eq - dot - 1);
  const std::string value = setting.substr(eq + 1);
  bool ok = false;
  if (section == enhanceParamTable().section())
    ok = enhanceParamTable().set(&p->enhance, key, value, error);
  else if (section == featureParamTable().section())
    ok = featureParamTable().set(&p->features, key, value, error);
  else if (section == trackerParamTable().section())
    ok = trackerParamTable().set(&p->tracker, key, value, error);
  else
    *error = "unknown section '" + section + "' (tracker, enhance, features)";
  if (ok) p->user_set.insert(section + "." + key);
  return ok;
}

std::string validate(const PipelineParams& p) {
  for (const std::string& e : {validate(p.enhance), validate(p.features), validate(p.tracker)})
    if (!e.empty()) return e;
  return "";
}

ResolutionDefaults resolutionDefaults(int width, int height, double focal, double scale_factor, bool fisheye) {
  constexpr double kRefWidth = 752, kRefHeight = 480, kMinLevelSide = 80.0;
  const ResolutionDefaults ref;
  ResolutionDefaults d;
  if (width <= 0 || height <= 0 || !(focal > 0)) return d;
  const double s = std::sqrt(static_cast<double>(width) * height / (kRefWidth * kRefHeight));
  d.n_features = static_cast<int>(std::lround(std::clamp(ref.n_features * s, 500.0, 2000.0) / 50.0)) * 50;
  d.cell_size = std::max(30, static_cast<int>(std::lround(ref.cell_size * s)));
  d.n_levels = 1;
  if (scale_factor > 1.0)
    while (d.n_levels < ref.n_levels && std::min(width, height) / std::pow(scale_factor, d.n_levels) >= kMinLevelSide)
      ++d.n_levels;
  const double f = focal / kResolutionRefFocal;
  d.search_radius_px = std::max(5.0, ref.search_radius_px * f);
  d.search_radius_wide_px = std::max(15.0, ref.search_radius_wide_px * f);
  d.search_radius_refine_px = std::max(2.0, ref.search_radius_refine_px * f);
  // Fisheye: a new point's depth error ~ (pixel noise / focal) / parallax, so the same margin in pixels needs a
  // parallax ~ 1 / focal (f 191: 2.4 deg); its scale had drifted 10-35 % over 300 frames at 1 deg. Narrow pinhole
  // cameras keep 1 deg: points leave their view sooner, and 1 / focal starved the map of dark low-resolution
  // sequences (240x180 slider, dark: 5.8 -> 13.4 mm; 376x240, dark: 635 -> 167 points, lost twice). docs/decisions.md.
  if (fisheye) d.min_triangulation_parallax_deg = std::round(100.0 * ref.min_triangulation_parallax_deg / f) / 100.0;
  const double n = d.n_features / static_cast<double>(ref.n_features);
  d.init_min_matches = static_cast<int>(std::lround(ref.init_min_matches * n));
  d.init_min_triangulated = static_cast<int>(std::lround(ref.init_min_triangulated * n));
  d.init_min_parallax_points = static_cast<int>(std::lround(ref.init_min_parallax_points * n));
  return d;
}

std::string applyFeatureResolutionRule(int width, int height, const std::set<std::string>& user_set, FeatureParams* p) {
  // The feature fields depend on the image size only (any positive focal gives the same ones).
  const ResolutionDefaults d = resolutionDefaults(width, height, kResolutionRefFocal, p->scale_factor);
  const auto unset = [&user_set](const char* key) { return user_set.count(key) == 0; };
  if (unset("features.n_features")) p->n_features = d.n_features;
  if (unset("features.cell_size")) p->cell_size = d.cell_size;
  if (unset("features.n_levels")) p->n_levels = d.n_levels;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%dx%d: n_features %d, cell_size %d, n_levels %d", width, height, p->n_features,
                p->cell_size, p->n_levels);
  return buf;
}

std::string applyTrackerResolutionRule(int width, int height, double focal, bool fisheye,
                                       const std::set<std::string>& user_set, TrackerParams* p) {
  // The tracker fields depend on the size and the focal length only (scale_factor only sets n_levels).
  const ResolutionDefaults d = resolutionDefaults(width, height, focal, FeatureParams().scale_factor, fisheye);
  const auto unset = [&user_set](const char* key) { return user_set.count(key) == 0; };
  if (unset("tracker.search_radius_px")) p->search_radius_px = d.search_radius_px;
  if (unset("tracker.search_radius_wide_px")) p->search_radius_wide_px = d.search_radius_wide_px;
  if (unset("tracker.search_radius_refine_px")) p->search_radius_refine_px = d.search_radius_refine_px;
  if (unset("tracker.init_min_matches")) p->init_min_matches = d.init_min_matches;
  if (unset("tracker.init_min_triangulated")) p->init_min_triangulated = d.init_min_triangulated;
  if (unset("tracker.init_min_parallax_points")) p->init_min_parallax_points = d.init_min_parallax_points;
  if (unset("tracker.min_triangulation_parallax_deg")) p->min_triangulation_parallax_deg = d.min_triangulation_parallax_deg;
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "f %.0f: search radii %.1f / %.1f / %.1f px, init min matches %d, triangulated %d, parallax points %d, "
                "triangulation parallax %.2f deg",
                focal, p->search_radius_px, p->search_radius_wide_px, p->search_radius_refine_px, p->init_min_matches,
                p->init_min_triangulated, p->init_min_parallax_points, p->min_triangulation_parallax_deg);
  return buf;
}

std::string applyResolutionRule(int width, int height, double focal, bool fisheye, PipelineParams* p) {
  const std::string f = applyFeatureResolutionRule(width, height, p->user_set, &p->features);
  return f + ", " + applyTrackerResolutionRule(width, height, focal, fisheye, p->user_set, &p->tracker);
}

std::string applyResolutionRule(const CameraModel& camera, PipelineParams* p) {
  return applyResolutionRule(camera.width(), camera.height(), camera.focal(), camera.isFisheye(), p);
}

std::string applyTrackerResolutionRule(const CameraModel& camera, const std::set<std::string>& user_set,
                                       TrackerParams* p) {
  return applyTrackerResolutionRule(camera.width(), camera.height(), camera.focal(), camera.isFisheye(), user_set, p);
}

}  // namespace iraf_vo
