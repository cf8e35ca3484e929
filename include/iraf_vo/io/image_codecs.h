// Image files through OpenCV's imgcodecs, loaded on first use from libiraf_vo_codecs.so (common/shared_library.h):
// libiraf_vo_core.so does not link imgcodecs, so a run whose images are all 8-bit gray PNG (png_gray8.h decodes
// those) never loads it and the ~120 more libraries it needs on Debian. Same behaviour as the cv:: functions of the same names
// (empty Mat / false on failure, cv::Exception from OpenCV); cv::Exception too when the codec library cannot be
// loaded, naming it and why. ROS-free; thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace iraf_vo {
namespace codecs {

cv::Mat imread(const std::string& path, int flags);
cv::Mat imdecode(const uint8_t* data, size_t size, int flags);
bool imwrite(const std::string& path, const cv::Mat& image, const std::vector<int>& params = {});
bool imencode(const std::string& ext, const cv::Mat& image, std::vector<uint8_t>* buf,
              const std::vector<int>& params = {});

/// The functions libiraf_vo_codecs.so exports through iraf_vo_image_codecs_api_v1() (plugin ABI, version 1).
struct Api {
  cv::Mat (*imread)(const std::string& path, int flags);
  cv::Mat (*imdecode)(const uint8_t* data, size_t size, int flags);
  bool (*imwrite)(const std::string& path, const cv::Mat& image, const std::vector<int>& params);
  bool (*imencode)(const std::string& ext, const cv::Mat& image, std::vector<uint8_t>* buf,
                   const std::vector<int>& params);
};

}  // namespace codecs
}  // namespace iraf_vo
