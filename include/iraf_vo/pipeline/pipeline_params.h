// The parameters of the whole offline pipeline: one struct per stage, read from one YAML file (maps `enhance:`,
// `features:`, `tracker:`; keys = the stages' parameter tables) and `section.key=value` overrides. ROS-free.
#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_model.h"
#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct PipelineParams {
  EnhanceParams enhance;
  FeatureParams features;
  TrackerParams tracker;
  /// "section.key" of every field a config file or a setting gave (applyResolutionRule keeps these).
  std::set<std::string> user_set;
};

/// Calls f(table, stage) for each stage's parameter table and struct, in pipeline order (enhance, features, tracker):
/// the one place that lists the stages (YAML sections, --set, validation, --help, docs/parameters.md).
template <class Pipeline, class F>
void forEachStage(Pipeline& p, F&& f) {
  f(enhanceParamTable(), p.enhance);
  f(featureParamTable(), p.features);
  f(trackerParamTable(), p.tracker);
}
/// The section names in pipeline order, and as "enhance, features, tracker".
std::vector<std::string> pipelineSections();
std::string pipelineSectionList();

/// Resolution rule. The defaults of the size-dependent fields are ORB-SLAM's for EuRoC cam0 (752x480,
/// focal 458.654 px); for another camera they are derived from the image size and the focal length:
///   s = sqrt(width * height / (752 * 480))                       (linear image-size ratio)
///   features.n_features  = clamp(1000 s, 500, 2000), rounded to 50   (keypoint density ~ per image side)
///   features.cell_size   = max(30, round(35 s))  (FAST / adaptive-threshold cell; measured, ATE % of the path:
///                          240x180 sim_slider 16 px 2.3, 30 px 0.22, 35 px 0.31; 512x512 sim_clean_fisheye 30 px
///                          0.24, 35 px 0.57; 1241x376 sim_drive 40 px 0.07, 35 px 0.14)
///   features.n_levels    = 8, fewer so that the coarsest level's short side stays >= 80 px
///                          (min(w, h) / scale_factor^(n_levels - 1) >= 80)
///   tracker.search_radius_px / _wide_px / _refine_px = 15 / 40 / 4 px * focal / 458.654
///                          (prediction errors are angles: pixels scale with the focal length), at least 5 / 15 / 2
///   tracker.init_min_matches / init_min_triangulated / init_min_parallax_points = 100 / 60 / 50 * n_features / 1000
///   tracker.min_triangulation_parallax_deg = fisheye: 1 deg * 458.654 / focal, to 0.01 deg (a new point's depth
///                          error is its bearing noise, pixels / focal, over the parallax); pinhole: 1 deg (docs/decisions.md)
/// Pixel-noise thresholds (init_threshold_px, pnp_threshold_px) and the initialization's parallax test do not depend
/// on the camera (scaling the latter too made the fisheye initialize later, 97.3 % tracked, and was not more accurate).
/// n_features, cell_size, n_levels, search radii, init matches / triangulated / parallax points, triangulation parallax:
/// 752x480 f 458 (EuRoC): 1000, 35, 8, 15 / 40 / 4, 100 / 60 / 50, 1 deg (= the struct defaults)
/// 1241x376 f 719 (KITTI): 1150, 40, 8, 23.5 / 62.7 / 6.3, 115 / 69 / 57, 1 deg
/// 512x512 f 191 (TUM-VI fisheye): 850, 30, 8, 6.2 / 16.7 / 2, 85 / 51 / 43, 2.4 deg
/// 240x180 f 200 (DAVIS240): 500, 30, 5, 6.5 / 17.4 / 2, 50 / 30 / 25, 1 deg
/// The focal length the struct defaults were chosen for (EuRoC cam0 fx, 752x480).
constexpr double kResolutionRefFocal = 458.654;
struct ResolutionDefaults {
  int n_features = 1000, cell_size = 35, n_levels = 8;
  double search_radius_px = 15.0, search_radius_wide_px = 40.0, search_radius_refine_px = 4.0;
  int init_min_matches = 100, init_min_triangulated = 60, init_min_parallax_points = 50;
  double min_triangulation_parallax_deg = 1.0;
};
/// fisheye: the camera is a fisheye (CameraModel::isFisheye), whose triangulation parallax follows its focal length.
ResolutionDefaults resolutionDefaults(int width, int height, double focal, double scale_factor = 1.2,
                                      bool fisheye = false);

/// Sets the fields of the rule that are not in p->user_set to resolutionDefaults(width, height, focal,
/// p->features.scale_factor). Returns a one-line summary of the values used (for logs).
std::string applyResolutionRule(int width, int height, double focal, bool fisheye, PipelineParams* p);
/// The rule for one stage (what the nodelets use): fields named in user_set ("features.n_features", ...) are kept.
std::string applyFeatureResolutionRule(int width, int height, const std::set<std::string>& user_set, FeatureParams* p);
std::string applyTrackerResolutionRule(int width, int height, double focal, bool fisheye,
                                       const std::set<std::string>& user_set, TrackerParams* p);
/// The same rules for a camera: its size, focal length and kind (what the tools and the tracker nodelet use).
std::string applyResolutionRule(const CameraModel& camera, PipelineParams* p);
std::string applyTrackerResolutionRule(const CameraModel& camera, const std::set<std::string>& user_set,
                                       TrackerParams* p);

/// Reads the optional sections of a YAML file (other top-level keys are ignored). false + *error naming the file,
/// the section and the key; *p is unchanged for a section that fails. The keys read go to p->user_set.
bool loadPipelineConfig(const std::string& path, PipelineParams* p, std::string* error);
/// Reads one section's YAML map (validated, all or nothing); the keys read go to p->user_set. false + *error.
bool loadPipelineSection(const std::string& section, const YAML::Node& node, PipelineParams* p, std::string* error);

/// Applies one "section.key=value" (section enhance | features | tracker); the key goes to p->user_set. false + *error.
bool applyPipelineSetting(const std::string& setting, PipelineParams* p, std::string* error);
/// The same with the parts apart (not validated: validate() the result).
bool setPipelineParam(const std::string& section, const std::string& key, const std::string& value, PipelineParams* p,
                      std::string* error);

/// "" when every stage is usable, else "<section>: " + the first failing stage's validation message.
std::string validate(const PipelineParams& p);

}  // namespace iraf_vo
