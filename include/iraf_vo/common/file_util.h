// Path checks, image-file names and line trimming shared by the file readers (io/) and the tools. ROS-free.
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

/// True when the file name ends in an image extension the readers take (png, jpg, jpeg, bmp, pgm, ppm, tif, tiff;
/// any case).
inline bool hasImageExtension(const std::filesystem::path& path) {
  std::string e = path.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".bmp" || e == ".pgm" || e == ".ppm" || e == ".tif" ||
         e == ".tiff";
}

/// `s` without its leading and trailing whitespace.
inline std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

}  // namespace iraf_vo
