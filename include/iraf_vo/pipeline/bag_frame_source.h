// The images of one topic of a rosbag (two for a stereo camera) as a FrameSource, for the offline runner. The reader
// is ROS code (ros/bag_reader.h in libiraf_vo_ros.so); this ROS-free entry point loads that library on first use
// (common/shared_library.h), so a run on an ASL folder never loads the ROS libraries.
#pragma once

#include <memory>
#include <string>

#include "iraf_vo/pipeline/frame_source.h"
#include "iraf_vo/pipeline/stereo_pairing.h"

namespace iraf_vo {

struct BagSourceOptions {
  std::string topic;        // the image topic (the left camera of a stereo pair)
  std::string right_topic;  // the right camera's image topic ("" = monocular): fills SourceImage::right
  /// Which right image goes with which left one (StereoPairing; its clock is the bag's stamps). A left image without
  /// a right partner within the tolerance keeps an empty SourceImage::right.
  StereoPairingParams pairing;
};

/// Opens the bag at `path`. nullptr + *error when the ROS library cannot be loaded, the bag cannot be read or a topic
/// has no image message (BagImageReader::open). A truncated bag opens with a notice(). With a right topic,
/// skippedSummary() also says how many left images had no right partner and how many right images were dropped.
std::unique_ptr<FrameSource> openBagFrameSource(const std::string& path, const BagSourceOptions& options,
                                                std::string* error);
inline std::unique_ptr<FrameSource> openBagFrameSource(const std::string& path, const std::string& topic,
                                                       std::string* error) {
  BagSourceOptions o;
  o.topic = topic;
  return openBagFrameSource(path, o, error);
}

}  // namespace iraf_vo

/// The factory libiraf_vo_ros.so exports (plugin ABI, version 2): a new FrameSource owned by the caller, or nullptr
/// + *error.
extern "C" iraf_vo::FrameSource* iraf_vo_open_bag_frame_source_v2(const std::string* path,
                                                                  const iraf_vo::BagSourceOptions* options,
                                                                  std::string* error);
