// iraf_vo_params: the stage parameters. `--markdown` prints docs/parameters.md (generated from the parameter
// tables); otherwise prints the values of every stage after --config / --set as one YAML file (usable as --config).
//
//   iraf_vo_params --markdown > docs/parameters.md
//   iraf_vo_params [--config FILE] [--set section.key=value ...]
#include <cstdio>
#include <string>

#include "iraf_vo/pipeline/command_line.h"
#include "iraf_vo/pipeline/parameter_docs.h"

int main(int argc, char** argv) {
  bool markdown = false;
  iraf_vo::CommandLine cli("iraf_vo_params",
                           "Prints every stage parameter after --config / --set as YAML, or the parameter reference.");
  cli.flag("--markdown", &markdown, "print docs/parameters.md (generated from the parameter tables)");
  cli.stageParams(iraf_vo::pipelineSections());
  if (const int code = cli.parse(argc, argv); code >= 0) return code;
  if (markdown) return std::fputs(iraf_vo::parameterDocsMarkdown().c_str(), stdout), 0;
  iraf_vo::PipelineParams params;
  if (const int code = cli.applyStageParams(&params); code >= 0) return code;
  iraf_vo::forEachStage(params, [](const auto& table, const auto& stage) {
    std::printf("%s:\n", table.section().c_str());
    for (const auto& e : table.entries()) std::printf("  %s: %s\n", e.name.c_str(), table.get(stage, e).c_str());
  });
  return 0;
}
