#include "iraf_vo/common/shared_library.h"

#include <dlfcn.h>

namespace iraf_vo {

namespace {

std::string thisLibraryFolder() {
  Dl_info info;
  if (dladdr(reinterpret_cast<void*>(&openSiblingLibrary), &info) == 0 || !info.dli_fname) return "";
  const std::string path = info.dli_fname;
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

}  // namespace

void* openSiblingLibrary(const std::string& file_name, std::string* error) {
  const std::string folder = thisLibraryFolder();
  std::string why;
  if (!folder.empty()) {
    if (void* h = dlopen((folder + file_name).c_str(), RTLD_NOW | RTLD_LOCAL)) return h;
    const char* e = dlerror();
    why = e ? e : (folder + file_name + ": dlopen failed");
  }
  if (void* h = dlopen(file_name.c_str(), RTLD_NOW | RTLD_LOCAL)) return h;
  const char* e = dlerror();
  if (error)
    *error = "cannot load " + file_name + " (looked beside libiraf_vo_core.so" +
             (folder.empty() ? std::string() : " in " + folder) + " and on the loader's path): " +
             (why.empty() ? std::string(e ? e : "dlopen failed") : why);
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
