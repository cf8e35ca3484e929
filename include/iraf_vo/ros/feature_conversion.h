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
/// arrays are inconsistent (lengths differ, descriptors not N x 32, non-finite coordinates).
bool fromMsg(const Features& msg, FeatureFrame* frame, std::string* error);

}  // namespace iraf_vo
