// The output of the feature stage for one image: what the tracker consumes and what the
// FeatureFrame message carries. ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <cstdint>
#include <vector>

#include "iraf_vo/features/image_signal.h"

namespace iraf_vo {

struct FeatureStats {
  double global_threshold = 0.0;     // F_t^g of level 0 (eq. 15)
  double cell_threshold_min = 0.0;   // over all cells of all levels (eq. 20)
  double cell_threshold_median = 0.0;
  double cell_threshold_max = 0.0;
  int detected = 0;                  // keypoints after distribution, before culling
  int culled = 0;                    // removed by the stability score (eqs. 21-23)
  // Stage times [ms] are CPU time of the extracting thread (= wall time when it is not preempted).
  double ms_threshold = 0.0;         // adaptive threshold computation
  double ms_detect = 0.0;            // pyramid + FAST + distribution + orientation + descriptors
  double ms_cull = 0.0;
  // Added by the feature stage (not needed by the tracker):
  double entropy = 0.0;              // F_h of level 0 (eq. 13), bits
  double gradient = 0.0;             // F_g of level 0 (eq. 14)
  int cells = 0;                     // FAST cells over all levels
  int cells_retried = 0;             // cells where F_t found nothing and the retry threshold ran
  int candidates = 0;                // FAST corners before the quad-tree distribution
  int brightness = 0;                // enhancement class of the input (BrightnessClass) if known, else 0
  double ms_describe = 0.0;          // part of ms_detect: orientation + descriptors of the kept keypoints
  double ms_pyramid = 0.0;           // part of ms_detect: level-0 copy + pyramid
  double ms_fast = 0.0;              // part of ms_detect: FAST with the cell thresholds (+ retries)
};

struct FeatureFrame {
  double stamp = 0.0;                  // seconds
  int width = 0, height = 0;
  std::vector<cv::KeyPoint> keypoints; // pt in level-0 pixels; octave, angle, response set;
                                       // class_id holds the FAST threshold used (rounded)
  cv::Mat descriptors;                 // N x 32 CV_8U, row i <-> keypoints[i]
  std::vector<float> stability;        // S of eq. 23 per kept keypoint (1 when culling is off)
  double scale_factor = 1.2;           // pyramid scale: keypoint sigma at octave o = scale_factor^o px
  FeatureStats stats;
  ImageSignal signal;                  // of the camera's image before enhancement (measured = false if unknown)
  cv::Mat image;                       // the 8-bit image the keypoints were detected on (the stereo matcher's
                                       // sub-pixel refinement); empty when not carried (ROS messages)
};

}  // namespace iraf_vo
