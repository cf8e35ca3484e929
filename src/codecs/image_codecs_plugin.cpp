// libiraf_vo_codecs.so: OpenCV's imgcodecs behind the plugin ABI of io/image_codecs.h, for libiraf_vo_core.so
// (which does not link imgcodecs) and so for iraf_vo_run; the core loads it on first use.
#include <opencv2/imgcodecs.hpp>

#include <climits>

#include "iraf_vo/io/image_codecs.h"

namespace {

cv::Mat readImage(const std::string& path, int flags) { return cv::imread(path, flags); }

cv::Mat decodeImage(const uint8_t* data, size_t size, int flags) {
  if (!data || size == 0 || size > static_cast<size_t>(INT_MAX)) return cv::Mat();
  const cv::Mat buf(1, static_cast<int>(size), CV_8UC1, const_cast<uint8_t*>(data));
  return cv::imdecode(buf, flags);
}

bool writeImage(const std::string& path, const cv::Mat& image, const std::vector<int>& params) {
  return cv::imwrite(path, image, params);
}

bool encodeImage(const std::string& ext, const cv::Mat& image, std::vector<uint8_t>* buf,
                 const std::vector<int>& params) {
  return cv::imencode(ext, image, *buf, params);
}

const iraf_vo::codecs::Api kApi{readImage, decodeImage, writeImage, encodeImage};

}  // namespace

extern "C" __attribute__((visibility("default"))) const iraf_vo::codecs::Api* iraf_vo_image_codecs_api_v1() {
  return &kApi;
}
