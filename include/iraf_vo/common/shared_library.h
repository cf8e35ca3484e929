// Optional parts of iraf_vo loaded on first use (dlopen), so a program that never needs them does not pay for
// loading them: OpenCV's image codecs pull in ~120 more shared libraries on Debian (GDAL and its tree, ~0.14 s of
// CPU per process start), the ROS bag reader ~160 (with the codecs, through cv_bridge). ROS-free.
#pragma once

#include <string>

namespace iraf_vo {

/// dlopen()s `file_name` (e.g. "libiraf_vo_codecs.so") from the folder libiraf_vo_core.so was loaded from (devel
/// space or install space: the libraries are built and installed side by side; the dynamic loader's search only if
/// that folder cannot be told). Returns the handle (never closed), or nullptr + *error naming the file, the folder and
/// why.
void* openSiblingLibrary(const std::string& file_name, std::string* error);

/// The address of `symbol` in a handle of openSiblingLibrary, or nullptr + *error naming the symbol and library.
void* findLibrarySymbol(void* handle, const std::string& symbol, const std::string& file_name, std::string* error);

}  // namespace iraf_vo
