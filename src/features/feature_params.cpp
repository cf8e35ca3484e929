#include "iraf_vo/features/feature_params.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <map>
#include <sstream>

namespace iraf_vo {

std::string validate(const FeatureParams& p) {
  std::ostringstream e;
  // Upper bound: extract() reserves 4 * n_features candidates (int overflow / std::length_error for huge values,
  // found by test_bad_inputs FeatureExtractorExtremeValidParams); 100000 is 10x cfg/Features.cfg's maximum.
  if (p.n_features < 1 || p.n_features > 100000) e << "n_features must be in [1, 100000] (got " << p.n_features << "); ";
  if (!(p.scale_factor > 1.0 && p.scale_factor <= 4.0)) e << "scale_factor must be in (1, 4] (got " << p.scale_factor << "); ";
  if (p.n_levels < 1 || p.n_levels > 32) e << "n_levels must be in [1, 32] (got " << p.n_levels << "); ";
  if (p.cell_size < 8) e << "cell_size must be >= 8 (got " << p.cell_size << "); ";
  if (p.ini_th_fast < 1 || p.ini_th_fast > 254) e << "ini_th_fast must be in [1, 254] (got " << p.ini_th_fast << "); ";
  if (p.min_th_fast < 1 || p.min_th_fast > 254) e << "min_th_fast must be in [1, 254] (got " << p.min_th_fast << "); ";
  if (!std::isfinite(p.alpha) || p.alpha < 0) e << "alpha must be finite and >= 0 (got " << p.alpha << "); ";
  if (!std::isfinite(p.beta) || p.beta < 0) e << "beta must be finite and >= 0 (got " << p.beta << "); ";
  if (!std::isfinite(p.delta) || p.delta < 0) e << "delta must be finite and >= 0 (got " << p.delta << "); ";
  if (!(p.ft_min >= 1.0 && p.ft_min <= 254.0)) e << "ft_min must be in [1, 254] (got " << p.ft_min << "); ";
  if (p.center_window < 1 || p.center_window % 2 == 0) e << "center_window must be odd and >= 1 (got " << p.center_window << "); ";
  if (p.min_node_size < 1) e << "min_node_size must be >= 1 (got " << p.min_node_size << "); ";
  if (p.contrast_patch_size < 3 || p.contrast_patch_size % 2 == 0)
    e << "contrast_patch_size must be odd and >= 3 (got " << p.contrast_patch_size << "); ";
  for (auto kv : {std::make_pair("rho", p.rho), std::make_pair("h_th", p.h_th), std::make_pair("k", p.k),
                  std::make_pair("d_opt", p.d_opt), std::make_pair("w1", p.w1), std::make_pair("w2", p.w2),
                  std::make_pair("s_min", p.s_min)})
    if (!std::isfinite(kv.second)) e << kv.first << " must be finite (got " << kv.second << "); ";
  if (p.min_features < 0) e << "min_features must be >= 0 (got " << p.min_features << "); ";
  return e.str();
}

namespace {

template <typename T>
std::function<bool(const YAML::Node&)> bind(T* field) {
  return [field](const YAML::Node& n) {
    try {
      *field = n.as<T>();
      return true;
    } catch (const YAML::Exception&) {
      return false;
    }
  };
}

}  // namespace

bool loadFeatureParams(const YAML::Node& node, FeatureParams* p, std::string* err) {
  auto fail = [err](const std::string& m) {
    if (err) *err = m;
    return false;
  };
  if (!node.IsDefined() || node.IsNull()) return true;  // nothing to override
  if (!node.IsMap()) return fail("feature params: expected a YAML map of key: value");
  FeatureParams q = *p;
  const std::map<std::string, std::function<bool(const YAML::Node&)>> setters = {
      {"n_features", bind(&q.n_features)},
      {"scale_factor", bind(&q.scale_factor)},
      {"n_levels", bind(&q.n_levels)},
      {"cell_size", bind(&q.cell_size)},
      {"adaptive_threshold", bind(&q.adaptive_threshold)},
      {"ini_th_fast", bind(&q.ini_th_fast)},
      {"min_th_fast", bind(&q.min_th_fast)},
      {"alpha", bind(&q.alpha)},
      {"beta", bind(&q.beta)},
      {"delta", bind(&q.delta)},
      {"ft_min", bind(&q.ft_min)},
      {"center_window", bind(&q.center_window)},
      {"culling", bind(&q.culling)},
      {"min_node_size", bind(&q.min_node_size)},
      {"contrast_patch_size", bind(&q.contrast_patch_size)},
      {"rho", bind(&q.rho)},
      {"h_th", bind(&q.h_th)},
      {"k", bind(&q.k)},
      {"d_opt", bind(&q.d_opt)},
      {"w1", bind(&q.w1)},
      {"w2", bind(&q.w2)},
      {"s_min", bind(&q.s_min)},
      {"min_features", bind(&q.min_features)},
      {"eq23_literal", bind(&q.eq23_literal)},
      {"fast_path", bind(&q.fast_path)},
  };
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>("");
    auto it = setters.find(key);
    if (it == setters.end()) return fail("feature params: unknown key '" + key + "'");
    if (!kv.second.IsScalar() || !it->second(kv.second))
      return fail("feature params: key '" + key + "' has a value of the wrong type");
  }
  const std::string v = validate(q);
  if (!v.empty()) return fail("feature params: " + v);
  *p = q;
  return true;
}

}  // namespace iraf_vo
