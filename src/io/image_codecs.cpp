#include "iraf_vo/io/image_codecs.h"

#include <mutex>

#include "iraf_vo/common/shared_library.h"

namespace iraf_vo {
namespace codecs {

namespace {

const char* const kLibrary = "libiraf_vo_codecs.so";

const Api& api() {
  static std::once_flag once;
  static const Api* loaded = nullptr;
  static std::string error;
  std::call_once(once, [] {
    void* h = openSiblingLibrary(kLibrary, &error);
    if (!h) return;
    using Entry = const Api* (*)();
    auto entry = reinterpret_cast<Entry>(findLibrarySymbol(h, "iraf_vo_image_codecs_api_v1", kLibrary, &error));
    if (entry) loaded = entry();
  });
  if (!loaded)
    CV_Error(cv::Error::StsError, "iraf_vo: image files other than 8-bit gray PNG need the codec library: " + error);
  return *loaded;
}

}  // namespace

cv::Mat imread(const std::string& path, int flags) { return api().imread(path, flags); }

cv::Mat imdecode(const uint8_t* data, size_t size, int flags) { return api().imdecode(data, size, flags); }

bool imwrite(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return api().imwrite(path, image, params);
}

bool imencode(const std::string& ext, const cv::Mat& image, std::vector<uint8_t>* buf, const std::vector<int>& params) {
  return api().imencode(ext, image, buf, params);
}

}  // namespace codecs
}  // namespace iraf_vo
