// FAST-9 corner detection (16-pixel Bresenham circle of radius 3) with a threshold per image COLUMN, so one
// pass over a row of cells applies every cell's own threshold (paper eq. 20) instead of one cv::FAST call per
// threshold. Same test, score and 3x3 non-max suppression as cv::FAST. ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <cstdint>
#include <vector>

namespace iraf_vo {

constexpr uint8_t kWallLeft = 1, kWallRight = 2;

/// Scratch rows reused between calls (no per-call allocation once grown).
struct Fast9Buffers {
  std::vector<uint8_t> score[4];  // FAST scores of the last 4 rows (0 = no corner)
  std::vector<int> corners[4];    // their corner columns
};

/// Replaces *keypoints by the FAST-9 corners of `img` (CV_8UC1, may be an ROI): pixel (x, y), 3 <= x < cols - 3,
/// 3 <= y < rows - 3, is a corner iff >= 9 contiguous circle pixels are all > I + col_threshold[x] or all
/// < I - col_threshold[x]. response = score = the largest threshold at which the pixel is still a corner
/// (cv::FAST's score); a corner is kept iff its score is > the score of every 8-neighbour that is a corner
/// (at that neighbour's own column threshold). Row-major order, like cv::FAST. col_threshold has img.cols
/// entries >= 1. With one threshold for every column the result equals cv::FAST(img, kps, t, true).
/// walls (optional, img.cols entries): a column with kWallLeft (kWallRight) ignores the column on its left
/// (right) in non-max suppression, as if the image ended there: cv::FAST on an ROI starting (ending) there.
void detectFast9(const cv::Mat& img, const uint8_t* col_threshold, std::vector<cv::KeyPoint>* keypoints,
                 Fast9Buffers* buffers, const uint8_t* walls = nullptr);

/// detectFast9's row kernel: AVX2 (32 lanes, where the CPU has it; the default) or the baseline SIMD build
/// (16 lanes). Both give the same corners and scores; for tests. Returns whether AVX2 is now in use.
bool fast9UseAvx2(bool allowed);

/// Lets detectFast9 use the AVX-512BW corner kernel (when fast9UseAvx2 allows AVX2 and the CPU has AVX-512BW;
/// the default) or not (AVX2 / baseline as fast9UseAvx2 says; also selects AVX2 again when it is allowed).
/// Returns whether the AVX-512BW kernel is now in use. For tests and benchmarks: the output is the same.
bool fast9UseAvx512(bool allowed);

}  // namespace iraf_vo
