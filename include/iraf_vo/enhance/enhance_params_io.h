// The parameter table of EnhanceParams (common/param_table.h): names = field names = cfg/Enhance.cfg parameters =
// YAML `enhance:` keys = `--set enhance.key=value`. ROS-free.
#pragma once

#include <string>
#include <vector>

#include "iraf_vo/common/param_table.h"
#include "iraf_vo/enhance/enhancer.h"

namespace iraf_vo {

/// Every EnhanceParams field with its cfg range and doc (cfg/Enhance.cfg also has the nodelet's `enabled`).
const ParamTable<EnhanceParams>& enhanceParamTable();

/// Sets one field by name from its text value. Returns false (error names key and value) when the
/// key is unknown or the value does not parse.
bool setEnhanceParam(EnhanceParams* p, const std::string& key, const std::string& value, std::string* error);

/// Names of all settable fields.
std::vector<std::string> enhanceParamNames();

/// Reads every key of a YAML map into `p` (unknown keys are errors), then validates.
bool loadEnhanceParams(const YAML::Node& node, EnhanceParams* p, std::string* error);

}  // namespace iraf_vo
