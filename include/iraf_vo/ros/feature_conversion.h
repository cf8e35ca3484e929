// ROS glue (not part of the ROS-free core): iraf_vo::FeatureFrame <-> iraf_vo/Features message.
#pragma once

#include <std_msgs/Header.h>

#include <string>

#include "iraf_vo/Features.h"
#include "iraf_vo/features/feature_frame.h"

namespace iraf_vo {

/// Fills *msg from `frame`; `header` is copied as is (frame.stamp is not used for it).
void toMsg(const FeatureFrame& frame, const std_msgs::Header& header, Features* msg);

/// Rebuilds a core FeatureFrame (stamp = header.stamp in seconds). Returns false and fills *error when the
/// arrays are inconsistent (lengths differ, descriptors not N x 32, non-finite coordinates) or scale_factor is not in
/// (1, 4]. scale_factor 0 (a sender that does not fill it): estimated from the keypoint sizes (31 scale^octave), else
/// 1.2, with a note in *warning.
bool fromMsg(const Features& msg, FeatureFrame* frame, std::string* error, std::string* warning = nullptr);

/// The pyramid scale implied by the keypoint sizes (size = 31 * scale^octave, the first keypoint with octave > 0);
/// 0 when no keypoint tells.
double scaleFactorFromSizes(const Features& msg);

}  // namespace iraf_vo
