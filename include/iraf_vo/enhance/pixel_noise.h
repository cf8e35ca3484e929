// Sensor noise of an 8-bit image at the pixel scale, from the image alone (ROS-free): the mask noise estimate of
// common/mask_noise.h on the pixels. This is the noise the unsharp mask of eq. (12) amplifies. Unlike the SNR of
// 4x4-pixel means (features/image_signal.h), fine texture barely raises it: EuRoC MH01 1.2-2.0, the rostest's 376x240
// render 1.0-2.5, the same EuRoC frames through a camera at gain 48 (`iraf_vo_degrade --profile night`) 21-24.
// Every second row and column is sampled (a quarter of the pixels).
#pragma once

#include <opencv2/core.hpp>

namespace iraf_vo {

/// Robust noise sigma [grey levels] of a CV_8UC1 image; 0 for an empty image, another type or one smaller than 3x3.
double estimatePixelNoise(const cv::Mat& gray);

}  // namespace iraf_vo
