#include "iraf_vo/enhance/enhance_params_io.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>

namespace iraf_vo {

namespace {

bool parseDouble(const std::string& s, double* v) {
  char* end = nullptr;
  const double d = std::strtod(s.c_str(), &end);
  if (s.empty() || end == s.c_str() || *end != '\0' || !std::isfinite(d)) return false;
  *v = d;
  return true;
}

using Setter = std::function<bool(EnhanceParams*, const std::string&)>;

Setter doubleField(double EnhanceParams::*f) {
  return [f](EnhanceParams* p, const std::string& s) { return parseDouble(s, &(p->*f)); };
}
Setter intField(int EnhanceParams::*f) {
  return [f](EnhanceParams* p, const std::string& s) {
    double d;
    if (!parseDouble(s, &d) || d != std::floor(d)) return false;
    p->*f = static_cast<int>(d);
    return true;
  };
}

const std::map<std::string, Setter>& setters() {
  static const std::map<std::string, Setter> m = {
      {"method", [](EnhanceParams* p, const std::string& s) { return parseEnhanceMethod(s, &p->method); }},
      {"gaussian_kernel_size", intField(&EnhanceParams::gaussian_kernel_size)},
      {"gaussian_sigma", doubleField(&EnhanceParams::gaussian_sigma)},
      {"mu_expected", doubleField(&EnhanceParams::mu_expected)},
      {"brightness_threshold", doubleField(&EnhanceParams::brightness_threshold)},
      {"dim_lambda", doubleField(&EnhanceParams::dim_lambda)},
      {"dim_tau", doubleField(&EnhanceParams::dim_tau)},
      {"bright_lambda", doubleField(&EnhanceParams::bright_lambda)},
      {"bright_tau", doubleField(&EnhanceParams::bright_tau)},
      {"epsilon", doubleField(&EnhanceParams::epsilon)},
      {"eta", doubleField(&EnhanceParams::eta)},
      {"clahe_clip_limit", doubleField(&EnhanceParams::clahe_clip_limit)},
      {"clahe_tiles", intField(&EnhanceParams::clahe_tiles)},
  };
  return m;
}

}  // namespace

bool setEnhanceParam(EnhanceParams* p, const std::string& key, const std::string& value, std::string* error) {
  const auto it = setters().find(key);
  if (it == setters().end()) {
    *error = "unknown enhance parameter '" + key + "'";
    return false;
  }
  if (!it->second(p, value)) {
    *error = "bad value '" + value + "' for enhance parameter '" + key + "'";
    return false;
  }
  return true;
}

std::vector<std::string> enhanceParamNames() {
  std::vector<std::string> names;
  for (const auto& kv : setters()) names.push_back(kv.first);
  return names;
}

bool loadEnhanceParams(const YAML::Node& node, EnhanceParams* p, std::string* error) {
  if (!node.IsMap()) {
    *error = "enhance parameters must be a YAML map";
    return false;
  }
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>("");  // fallback: a non-scalar key (e.g. "? ? 4") threw
    if (!kv.second.IsScalar()) {
      *error = "enhance parameter '" + key + "' must be a scalar";
      return false;
    }
    if (!setEnhanceParam(p, key, kv.second.as<std::string>(), error)) return false;
  }
  const std::string v = validate(*p);
  if (!v.empty()) {
    *error = "invalid enhance parameters: " + v;
    return false;
  }
  return true;
}

}  // namespace iraf_vo
