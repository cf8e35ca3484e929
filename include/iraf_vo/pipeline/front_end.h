// The front-end of the offline pipeline: enhancement + feature extraction in one of the paper's configurations
// (Tables I / II: IRAF, the ORB-SLAM3 baseline, each module alone, HE / CLAHE). ROS-free.
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/features/feature_params.h"

namespace iraf_vo {

/// iraf = enhancement + adaptive threshold + culling; baseline = all off (ORB-SLAM3); enhance / adaptive / culling =
/// that module alone; he / clahe = global histogram equalization / CLAHE + the baseline features.
enum class FrontEndMode { kIraf, kBaseline, kEnhance, kAdaptive, kCulling, kHe, kClahe };
const char* toString(FrontEndMode m);
/// Parses a toString() name; false for anything else.
bool parseFrontEndMode(const std::string& s, FrontEndMode* m);
/// "iraf, baseline, enhance, adaptive, culling, he or clahe", for messages.
const char* frontEndModeList();
/// Sets the switches of `mode` (enhancement method, adaptive threshold, culling); every other field is kept.
void applyFrontEndMode(FrontEndMode mode, EnhanceParams* enhance, FeatureParams* features);

struct FrontEndTiming {
  double ms_enhance = 0.0;   // wall time
  double ms_features = 0.0;  // wall time
};

/// Owns an Enhancer and a FeatureExtractor (their buffers are reused): image -> FeatureFrame. One thread at a time.
class FrontEnd {
 public:
  /// keep_image: each FeatureFrame carries its enhanced image (FeatureFrame::image, for the stereo matcher's sub-pixel
  /// refinement); false: the image is released after the extraction (monocular: nothing reads it).
  FrontEnd(const EnhanceParams& enhance, const FeatureParams& features, bool keep_image = false);

  /// Enhances a CV_8UC1 image and extracts its features; stats.brightness = the enhancement class.
  /// Throws std::invalid_argument for an unusable image or invalid parameters.
  FeatureFrame process(const cv::Mat& gray, double stamp, FrontEndTiming* timing = nullptr);

 private:
  EnhanceParams enhance_params_;
  FeatureParams feature_params_;
  Enhancer enhancer_;
  FeatureExtractor extractor_;
  bool keep_image_;
};

}  // namespace iraf_vo
