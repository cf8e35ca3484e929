// Reading small text outputs of the tools in tests: a whole file, and a number from flat JSON
// (iraf_vo_run --stats, iraf_vo_eval --json).
#pragma once

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace iraf_vo {
namespace test {

/// The whole file ("" when it cannot be read).
inline std::string readTextFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// The number after "key": in flat JSON, -1 when the key is missing.
inline double jsonNumber(const std::string& json, const std::string& key) {
  const size_t k = json.find("\"" + key + "\":");
  return k == std::string::npos ? -1.0 : std::atof(json.c_str() + k + key.size() + 3);
}

}  // namespace test
}  // namespace iraf_vo
