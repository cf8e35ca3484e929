// libFuzzer target: bytes -> YAML -> the enhance / features / tracker ParamTable::load (the params
// files of iraf_vo_enhance / iraf_vo_run). A load that succeeds must give params that validate(); a load that
// fails must say why. Never throw (apart from YAML::Load's own parse errors, which callers catch) or crash.
// Built and run by scripts/fuzz.sh.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/tracking/tracker_params.h"

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int which = data[0] % 3;
  YAML::Node node;
  try {
    node = YAML::Load(std::string(reinterpret_cast<const char*>(data + 1), size - 1));
  } catch (const YAML::Exception&) {
    return 0;  // not YAML: the callers report the parse error
  }
  std::string err;
  if (which == 0) {
    iraf_vo::EnhanceParams p;
    if (iraf_vo::enhanceParamTable().load(node, &p, &err)) FUZZ_CHECK(iraf_vo::validate(p).empty());
    else FUZZ_CHECK(!err.empty());
  } else if (which == 1) {
    iraf_vo::FeatureParams p;
    if (iraf_vo::featureParamTable().load(node, &p, &err)) FUZZ_CHECK(iraf_vo::validate(p).empty());
    else FUZZ_CHECK(!err.empty());
  } else {
    iraf_vo::TrackerParams p;
    if (iraf_vo::trackerParamTable().load(node, &p, &err)) FUZZ_CHECK(iraf_vo::validate(p).empty());
    else FUZZ_CHECK(!err.empty());
  }
  return 0;
}
