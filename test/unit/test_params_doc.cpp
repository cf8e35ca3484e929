// docs/parameters.md is generated from the parameter tables (pipeline/parameter_docs.h) and must not go stale: this
// test regenerates it and compares it with the committed file.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "iraf_vo/pipeline/parameter_docs.h"
#include "iraf_vo/pipeline/pipeline_params.h"

TEST(ParameterDocs, CommittedFileEqualsTheTables) {
  const std::string path = std::string(IRAF_VO_SOURCE_DIR) + "/docs/parameters.md";
  std::ifstream f(path);
  ASSERT_TRUE(f.good()) << path << " is missing: generate it with `" << iraf_vo::kParameterDocsCommand << "`";
  std::stringstream committed;
  committed << f.rdbuf();
  EXPECT_TRUE(committed.str() == iraf_vo::parameterDocsMarkdown())
      << "docs/parameters.md differs from the parameter tables: regenerate it from the source root with\n  "
      << iraf_vo::kParameterDocsCommand;
}

TEST(ParameterDocs, EveryParameterHasARowWithItsDefaultAndRange) {
  const std::string md = iraf_vo::parameterDocsMarkdown();
  const iraf_vo::PipelineParams defaults;
  iraf_vo::forEachStage(defaults, [&md](const auto& table, const auto& stage) {
    EXPECT_NE(md.find("\n## " + table.section() + "\n"), std::string::npos) << table.section();
    for (const auto& e : table.entries()) {
      const std::string row = "| `" + e.name + "` | ";
      const size_t at = md.find(row);
      ASSERT_NE(at, std::string::npos) << e.name;
      const std::string line = md.substr(at, md.find('\n', at) - at);
      EXPECT_NE(line.find("`" + table.get(stage, e) + "`"), std::string::npos) << line;
      if (e.type == iraf_vo::ParamType::kInt || e.type == iraf_vo::ParamType::kDouble) {
        const std::string range = "[" + iraf_vo::formatDouble(e.min) + ", " + iraf_vo::formatDouble(e.max) + "]";
        EXPECT_NE(line.find(range), std::string::npos) << line;
      }
    }
  });
}
