#include "iraf_vo/common/shared_library.h"

#include <dlfcn.h>

namespace iraf_vo {

namespace {

// An address inside libiraf_vo_core.so itself (a file-local object: an exported function's address taken in a
// non-PIE executable could resolve to the executable's PLT entry).
const char kAnchor = 0;

std::string thisLibraryFolder() {
  Dl_info info;
  if (dladdr(static_cast<const void*>(&kAnchor), &info) == 0 || !info.dli_fname) return "";
  const std::string path = info.dli_fname;
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

}  // namespace

void* openSiblingLibrary(const std::string& file_name, std::string* error) {
  // Beside the core when its folder is known (devel and install space keep the libraries together); the loader's
  // search path only when it is not.
  const std::string folder = thisLibraryFolder();
  const std::string path = folder.empty() ? file_name : folder + file_name;
  if (void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) return h;
  const char* e = dlerror();
  if (error)
    *error = "cannot load " + file_name + (folder.empty() ? std::string(" (on the loader's path)") : " from " + folder) +
             ": " + (e ? e : "dlopen failed");
  return nullptr;
}

void* findLibrarySymbol(void* handle, const std::string& symbol, const std::string& file_name, std::string* error) {
  dlerror();
  void* p = dlsym(handle, symbol.c_str());
  if (!p && error) {
    const char* e = dlerror();
    *error = file_name + " has no symbol " + symbol + (e ? std::string(": ") + e : std::string());
  }
  return p;
}

}  // namespace iraf_vo
