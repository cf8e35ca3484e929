#include "iraf_vo/common/param_table.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace iraf_vo {

const char* toString(ParamType t) {
  switch (t) {
    case ParamType::kInt: return "an integer";
    case ParamType::kDouble: return "a finite number";
    case ParamType::kBool: return "true or false";
    case ParamType::kText: return "one of the listed names";
  }
  return "?";
}

bool parseDoubleText(const std::string& s, double* v) {
  char* end = nullptr;
  errno = 0;
  const double d = std::strtod(s.c_str(), &end);
  if (s.empty() || end == s.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(d)) return false;
  *v = d;
  return true;
}

bool parseIntText(const std::string& s, int* v) {
  double d;
  if (!parseDoubleText(s, &d) || d != std::floor(d) || d < std::numeric_limits<int>::min() ||
      d > std::numeric_limits<int>::max())
    return false;
  *v = static_cast<int>(d);
  return true;
}

bool parseBoolText(const std::string& s, bool* v) {
  for (const char* t : {"true", "True", "TRUE", "1", "yes", "Yes", "YES", "on", "On", "ON"})
    if (s == t) return (*v = true), true;
  for (const char* f : {"false", "False", "FALSE", "0", "no", "No", "NO", "off", "Off", "OFF"})
    if (s == f) return (*v = false), true;
  return false;
}

std::string formatDouble(double v) {
  char buf[64];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

}  // namespace iraf_vo
