// The parameters of the whole offline pipeline: one struct per stage, read from one YAML file (maps `enhance:`,
// `features:`, `tracker:`; keys = the stages' parameter tables) and `section.key=value` overrides. ROS-free.
#pragma once

#include <string>

#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/tracking/tracker_params.h"

namespace iraf_vo {

struct PipelineParams {
  EnhanceParams enhance;
  FeatureParams features;
  TrackerParams tracker;
};

/// Reads the optional sections of a YAML file (other top-level keys are ignored). false + *error naming the file,
/// the section and the key; *p is unchanged for a section that fails.
bool loadPipelineConfig(const std::string& path, PipelineParams* p, std::string* error);

/// Applies one "section.key=value" (section enhance | features | tracker). false + *error.
bool applyPipelineSetting(const std::string& setting, PipelineParams* p, std::string* error);

/// "" when every stage is usable, else the first stage's validation message.
std::string validate(const PipelineParams& p);

}  // namespace iraf_vo
