// How much usable signal an 8-bit image carries, estimated from the image alone (ROS-free): the mean grey, the
// sensor noise, the scene's contrast above that noise and their ratio. The tracker declares a frame "too dark"
// from these numbers (tracking/signal_check.h) instead of tracking on noise.
//
// Features are found at the scale of a few pixels, where weak texture survives noise that dominates single pixels,
// so the estimate is made on the image's 4x4-pixel means (cv::INTER_AREA):
//   noise_sigma  robust noise of those means: the median absolute response of the mask [1 -2 1; -2 4 -2; 1 -2 1]
//                (it cancels planar intensity, so shading does not count, and texture edges are too few to move
//                the median) x 1.4826 / 6 (Gaussian MAD factor / the mask's noise gain sqrt(36)); floored at the
//                8-bit quantization noise of a mean of 16 pixels, 1 / (4 sqrt(12))
//   contrast     their standard deviation with that noise removed: sqrt(max(0, var - noise_sigma^2))
//   snr          contrast / noise_sigma
//   clipped      the fraction of those means at >= 250 grey: white, no texture left (a washed-out image)
// On EuRoC MH01 frames scaled by a factor f plus Gaussian noise of 2 grey levels: f = 1 / 10: SNR 11-13,
// f = 1 / 50: 3.1-3.4, f = 1 / 100 (still tracked by the IRAF front-end): 1.5-1.6, f = 1 / 200 (no longer
// tracked): 0.7-0.8, noise alone 0.1-0.2. Cost: one area resize and a pass over 1 / 16 of the pixels.
#pragma once

#include <opencv2/core.hpp>

namespace iraf_vo {

struct ImageSignal {
  bool measured = false;     // false: no estimate (e.g. a feature message without one): never declared dark
  double mean = 0.0;         // grey level
  double noise_sigma = 0.0;  // of the 4x4 means, grey levels
  double contrast = 0.0;     // of the 4x4 means, grey levels, noise removed
  double snr = 0.0;          // contrast / noise_sigma
  double clipped = 0.0;      // fraction of the 4x4 means >= 250 grey (clipped white)
};

/// The signal estimate of a CV_8UC1 image; measured = false for an empty image, another type or one smaller
/// than 12x12.
ImageSignal measureImageSignal(const cv::Mat& gray);

}  // namespace iraf_vo
