#include "iraf_vo/pipeline/pipeline_params.h"

#include <yaml-cpp/yaml.h>

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
  if (section == enhanceParamTable().section()) return enhanceParamTable().set(&p->enhance, key, value, error);
  if (section == featureParamTable().section()) return featureParamTable().set(&p->features, key, value, error);
  if (section == trackerParamTable().section()) return trackerParamTable().set(&p->tracker, key, value, error);
  *error = "unknown section '" + section + "' (tracker, enhance, features)";
  return false;
}

std::string validate(const PipelineParams& p) {
  for (const std::string& e : {validate(p.enhance), validate(p.features), validate(p.tracker)})
    if (!e.empty()) return e;
  return "";
}

}  // namespace iraf_vo
