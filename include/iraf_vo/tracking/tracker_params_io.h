// YAML loading of TrackerParams (keys = field names = cfg/Tracker.cfg names). ROS-free.
#pragma once

#include <iraf_vo/tracking/tracker.h>

#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace iraf_vo {

/// Sets one field from its text value ("ba_window_size", "12"). false + *error naming key and value.
bool setTrackerParam(TrackerParams* p, const std::string& key, const std::string& value, std::string* error);
std::vector<std::string> trackerParamNames();
/// Reads every key of a map node (unknown keys are an error), then validates. false + *error.
bool loadTrackerParams(const YAML::Node& node, TrackerParams* p, std::string* error);

}  // namespace iraf_vo
