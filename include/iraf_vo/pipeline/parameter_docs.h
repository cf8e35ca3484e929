// docs/parameters.md, generated from the stages' parameter tables (`iraf_vo_params --markdown`; test_params
// fails when the committed file differs). ROS-free.
#pragma once

#include <string>

namespace iraf_vo {

/// The Markdown reference of every stage parameter: per stage name, type, default, range and doc, and how to set
/// it (YAML key, --set, ROS private parameter, dynamic_reconfigure).
std::string parameterDocsMarkdown();

/// The command that regenerates docs/parameters.md from the source tree's root.
constexpr const char* kParameterDocsCommand = "build/devel/lib/iraf_vo/iraf_vo_params --markdown > docs/parameters.md";

}  // namespace iraf_vo
