// The images of one topic of a rosbag as a FrameSource, for the offline runner. The reader is ROS code
// (ros/bag_reader.h in libiraf_vo_ros.so); this ROS-free entry point loads that library on first use
// (common/shared_library.h), so a run on an ASL folder never loads the ROS libraries.
#pragma once

#include <memory>
#include <string>

#include "iraf_vo/pipeline/frame_source.h"

namespace iraf_vo {

/// Opens `topic` of the bag at `path`. nullptr + *error when the ROS library cannot be loaded, the bag cannot be
/// read or the topic has no image message (BagImageReader::open). A truncated bag opens with a notice().
std::unique_ptr<FrameSource> openBagFrameSource(const std::string& path, const std::string& topic, std::string* error);

}  // namespace iraf_vo

/// The factory libiraf_vo_ros.so exports (plugin ABI, version 1): a new FrameSource owned by the caller, or nullptr
/// + *error.
extern "C" iraf_vo::FrameSource* iraf_vo_open_bag_frame_source_v1(const std::string* path, const std::string* topic,
                                                                  std::string* error);
