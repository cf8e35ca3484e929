// Path checks and line trimming shared by the file readers (io/). ROS-free.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>
#include <system_error>

namespace iraf_vo {

/// True when `path` names an existing directory (links followed); never throws.
inline bool isDir(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec);
}

/// True when `path` names an existing regular file (links followed); never throws.
inline bool isFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

/// `s` without its leading and trailing whitespace.
inline std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

}  // namespace iraf_vo
