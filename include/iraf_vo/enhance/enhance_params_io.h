// Setting EnhanceParams by name: from YAML files (ov_core style) and from `--set key=value` on the
// command line. The names are the field names, which are also the cfg/Enhance.cfg parameter names.
#pragma once

#include <string>
#include <vector>

#include "iraf_vo/enhance/enhancer.h"

namespace YAML {
class Node;
}

namespace iraf_vo {

/// Sets one field by name from its text value. Returns false (error names key and value) when the
/// key is unknown or the value does not parse.
bool setEnhanceParam(EnhanceParams* p, const std::string& key, const std::string& value, std::string* error);

/// Names of all settable fields.
std::vector<std::string> enhanceParamNames();

/// Reads every key of a YAML map into `p` (unknown keys are errors), then validates.
bool loadEnhanceParams(const YAML::Node& node, EnhanceParams* p, std::string* error);

}  // namespace iraf_vo
