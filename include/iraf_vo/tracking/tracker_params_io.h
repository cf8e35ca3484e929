// The parameter table of TrackerParams (common/param_table.h): names = field names = cfg/Tracker.cfg parameters =
// YAML `tracker:` keys = `--set tracker.key=value` = the tracker nodelet's private parameters. ROS-free.
#pragma once

#include "iraf_vo/common/param_table.h"
#include "iraf_vo/tracking/tracker_params.h"

#include <string>
#include <vector>

namespace iraf_vo {

/// Every TrackerParams field with its cfg/Tracker.cfg range and doc.
const ParamTable<TrackerParams>& trackerParamTable();

/// Sets one field from its text value ("ba_window_size", "12"). false + *error naming key and value.
bool setTrackerParam(TrackerParams* p, const std::string& key, const std::string& value, std::string* error);
std::vector<std::string> trackerParamNames();
/// Reads every key of a map node (unknown keys are an error), then validates. false + *error.
bool loadTrackerParams(const YAML::Node& node, TrackerParams* p, std::string* error);

}  // namespace iraf_vo
