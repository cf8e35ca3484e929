// Fast decoding of the PNG files VO datasets are made of (EuRoC, TUM-VI, our simulator: 8-bit grayscale,
// not interlaced). OpenCV's PNG reader (libpng + zlib) spends ~4 ms on a 752x480 frame, most of it in libpng's
// per-pixel Paeth unfiltering; libdeflate's inflate and a branch-free unfilter give the same pixels in about
// half the time. Everything else (colour, 16 bit, interlaced, palette, transparency, unknown chunks, any
// damage) is left to OpenCV: decodeImage() falls back to cv::imdecode, so errors keep OpenCV's behaviour.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace iraf_vo {

/// Decodes an in-memory PNG when it is 8-bit grayscale, not interlaced, with only IHDR / IDAT / IEND and
/// metadata chunks (text, time, pHYs) and valid CRCs / zlib checksum: *out = CV_8UC1, the same pixels as
/// cv::imdecode(..., IMREAD_UNCHANGED). false (out untouched) for any other input, never throws.
bool decodeGray8Png(const uint8_t* data, size_t size, cv::Mat* out);

/// decodeGray8Png when it applies, else cv::imdecode(IMREAD_UNCHANGED). Empty Mat when neither decodes;
/// *error (optional) gets OpenCV's exception text when it throws.
cv::Mat decodeImage(const uint8_t* data, size_t size, std::string* error = nullptr);

/// Reads a whole file into *bytes. false when it cannot be opened or read.
bool readFileBytes(const std::string& path, std::vector<uint8_t>* bytes);

}  // namespace iraf_vo
