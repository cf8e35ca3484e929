#include "iraf_vo/pipeline/parameter_docs.h"

#include "iraf_vo/pipeline/pipeline_params.h"

namespace iraf_vo {

namespace {

struct StageDoc {
  const char* section;
  const char* struct_name;
  const char* header;
  const char* nodelet;
  const char* cfg;
  const char* example;  // key=value
};

constexpr StageDoc kStages[] = {
    {"enhance", "EnhanceParams", "include/iraf_vo/enhance/enhance_params.h", "iraf_vo/EnhanceNodelet", "Enhance",
     "mu_expected=50"},
    {"features", "FeatureParams", "include/iraf_vo/features/feature_params.h", "iraf_vo/FeatureNodelet", "Features",
     "n_features=500"},
    {"tracker", "TrackerParams", "include/iraf_vo/tracking/tracker_params.h", "iraf_vo/TrackerNodelet", "Tracker",
     "ba_window_size=12"},
};

const StageDoc* stageDoc(const std::string& section) {
  for (const StageDoc& s : kStages)
    if (section == s.section) return &s;
  return nullptr;
}

/// Markdown table cell: '|' escaped.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

const char* typeName(ParamType t) {
  switch (t) {
    case ParamType::kInt: return "int";
    case ParamType::kDouble: return "double";
    case ParamType::kBool: return "bool";
    case ParamType::kText: return "enum";
  }
  return "?";
}

}  // namespace

std::string parameterDocsMarkdown() {
  std::string md =
      "# Parameters\n"
      "\n"
      "<!-- Generated from the parameter tables (src/<stage>/<stage>_params.cpp); do not edit. Regenerate with\n"
      "     " + std::string(kParameterDocsCommand) + "\n"
      "     test_params fails while this file differs from the tables. -->\n"
      "\n"
      "Every parameter of the three stages, one row each. One name everywhere: the struct field, the YAML key, the\n"
      "`--set` key, the ROS private parameter and the dynamic_reconfigure parameter. The default is the struct's\n"
      "initializer; the range is what validation accepts (inclusive) and what the dynamic_reconfigure slider offers.\n"
      "A value out of range is rejected with a message naming the parameter and its range. iraf_vo_run and the\n"
      "nodelets derive the size-dependent fields (n_features, cell_size, n_levels, the search radii, the init counts,\n"
      "the triangulation parallax) from the camera unless they are given (resolution rule, pipeline_params.h); the\n"
      "defaults below are those for 752x480.\n"
      "\n"
      "## How to set a parameter\n"
      "\n"
      "| where | how (e.g. `features.n_features`) |\n"
      "| --- | --- |\n"
      "| YAML file: `--config FILE` of every tool, `params:=FILE` of the launch files | `n_features: 500` in the "
      "`features:` map |\n"
      "| command line of every tool (after `--config`, in order) | `--set features.n_features=500` |\n"
      "| ROS private parameter of the stage's nodelet (read at startup) | `~n_features` of `/features` (the launch "
      "files load the YAML's `features:` map there) |\n"
      "| dynamic_reconfigure (live; cfg/Features.cfg) | `rosrun dynamic_reconfigure dynparam set /features "
      "n_features 500` |\n"
      "\n"
      "`iraf_vo_params [--config FILE] [--set section.key=value ...]` prints the resulting values of every stage.\n";
  const PipelineParams defaults;
  forEachStage(defaults, [&md](const auto& table, const auto& stage) {
    const StageDoc* d = stageDoc(table.section());
    md += "\n## " + table.section() + "\n\n";
    if (d)
      md += std::string("`iraf_vo::") + d->struct_name + "` (" + d->header + "); YAML `" + table.section() +
            ":`; `--set " + table.section() + "." + d->example + "`; nodelet `" + d->nodelet + "` (`/" +
            table.section() + "`), cfg/" + d->cfg + ".cfg.\n";
    if (!table.crossCheckDoc().empty()) md += "\nAlso checked across fields: " + table.crossCheckDoc() + ".\n";
    md += "\n| name | type | default | range | description |\n| --- | --- | --- | --- | --- |\n";
    for (const auto& e : table.entries()) {
      std::string range = table.rangeText(e);
      if (range.rfind("in ", 0) == 0) range = range.substr(3);
      if (range.rfind("odd and in ", 0) == 0) range = range.substr(11) + ", odd";
      md += "| `" + e.name + "` | " + typeName(e.type) + " | `" + cell(table.get(stage, e)) + "` | " +
            (range.empty() ? "see description" : cell(range)) + " | " + cell(e.doc) + " |\n";
    }
  });
  return md;
}

}  // namespace iraf_vo
