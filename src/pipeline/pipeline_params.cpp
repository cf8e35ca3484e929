#include "iraf_vo/pipeline/pipeline_params.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace iraf_vo {

namespace {

bool fail(std::string* error, const std::string& m) {
  if (error) *error = m;
  return false;
}

}  // namespace

bool loadPipelineSection(const std::string& section, const YAML::Node& node, PipelineParams* p, std::string* error) {
  bool known = false, ok = true;
  forEachStage(*p, [&](const auto& table, auto& stage) {
    if (table.section() != section) return;
    known = true;
    ok = table.load(node, &stage, error);
  });
  if (!known) return fail(error, "unknown section '" + section + "' (" + pipelineSectionList() + ")");
  if (ok && node.IsMap())
    for (const auto& kv : node) p->user_set.insert(section + "." + kv.first.as<std::string>(""));
  return ok;
}

bool loadPipelineConfig(const std::string& path, PipelineParams* p, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const std::exception& e) {
    return fail(error, path + ": " + e.what());
  }
  if (!root.IsMap())
    return root.IsNull() || fail(error, path + ": expected a YAML map (sections " + pipelineSectionList() + ")");
  for (const std::string& section : pipelineSections()) {
    std::string err;
    if (root[section] && !loadPipelineSection(section, root[section], p, &err)) return fail(error, path + ": " + err);
  }
  return true;
}

bool applyPipelineSetting(const std::string& setting, PipelineParams* p, std::string* error) {
  const size_t dot = setting.find('.'), eq = setting.find('=');
  if (dot == std::string::npos || eq == std::string::npos || eq < dot)
    return fail(error, "expected section.key=value");
  return setPipelineParam(setting.substr(0, dot), setting.substr(dot + 1, eq - dot - 1), setting.substr(eq + 1), p,
                          error);
}

bool setPipelineParam(const std::string& section, const std::string& key, const std::string& value, PipelineParams* p,
                      std::string* error) {
  bool known = false, ok = false;
  forEachStage(*p, [&](const auto& table, auto& stage) {
    if (table.section() != section) return;
    known = true;
    ok = table.set(&stage, key, value, error);
  });
  if (!known) return fail(error, "unknown section '" + section + "' (" + pipelineSectionList() + ")");
  if (ok) p->user_set.insert(section + "." + key);
  return ok;
}

std::vector<std::string> pipelineSections() {
  std::vector<std::string> s;
  const PipelineParams defaults;
  forEachStage(defaults, [&s](const auto& table, const auto&) { s.push_back(table.section()); });
  return s;
}

std::string pipelineSectionList() {
  std::string out;
  for (const std::string& s : pipelineSections()) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string validate(const PipelineParams& p) {
  std::string out;
  forEachStage(p, [&out](const auto& table, const auto& stage) {
    const std::string e = table.validate(stage);
    if (out.empty() && !e.empty()) out = table.section() + ": " + e;
  });
  return out;
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
