// libFuzzer target: bytes -> decodeGray8Png (the 8-bit grayscale PNG fast path). Contract: it never crashes or
// trips ASan/UBSan; when it accepts the bytes, OpenCV's decoder gives exactly the same image. Seeds are small
// grayscale PNGs (test/fuzz/corpus/fuzz_png_gray8/). Built and run by scripts/fuzz.sh.
#include <cstdint>
#include <opencv2/imgcodecs.hpp>

#include "iraf_vo/io/png_gray8.h"

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  cv::Mat ours;
  if (!iraf_vo::decodeGray8Png(data, size, &ours)) return 0;
  FUZZ_CHECK(ours.type() == CV_8UC1 && !ours.empty());
  cv::Mat ref;
  try {
    ref = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8UC1, const_cast<uint8_t*>(data)), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
  }
  FUZZ_CHECK(ref.size() == ours.size() && ref.type() == ours.type());
  FUZZ_CHECK(cv::norm(ref, ours, cv::NORM_INF) == 0.0);
  return 0;
}
