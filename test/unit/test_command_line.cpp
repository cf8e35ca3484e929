// CommandLine (pipeline/command_line.h), the parser of every tool: option values, --config / --set, the deprecated
// forms, and the messages (each names the option, the parameter and the value).
#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "common/tmp_dir.h"
#include "iraf_vo/pipeline/command_line.h"

using namespace iraf_vo;

namespace {

/// A tool with one text, one int option, a flag, a positional and the given stage sections.
struct Tool {
  std::string input, name;
  int count = 3;
  bool quiet = false;
  PipelineParams params;
  CommandLine cli{"tool", ""};
  explicit Tool(const std::vector<std::string>& sections, const std::string& legacy = "") {
    cli.positional("INPUT", &input, "input");
    cli.option("--name", "N", &name, "a name");
    cli.option("--count", "C", &count, 1, 10, "a count");
    cli.flag("--quiet", &quiet, "quiet");
    if (!sections.empty()) cli.stageParams(sections, legacy);
  }
  /// parse(), then applyStageParams() when parsing says run: -1 when usable, else the exit code.
  int run(std::initializer_list<std::string> args) {
    std::vector<const char*> argv{"tool"};
    for (const std::string& a : args) argv.push_back(a.c_str());
    const int code = cli.parse(static_cast<int>(argv.size()), argv.data());
    return code >= 0 ? code : cli.applyStageParams(&params);
  }
};

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = tmpRoot() + "cli_" + name;
  std::ofstream(path) << text;
  return path;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(CommandLine, OptionsFlagsAndPositionals) {
  Tool t({});
  EXPECT_EQ(t.run({"in.png", "--name", "a", "--count=7", "--quiet"}), -1) << t.cli.error();
  EXPECT_EQ(t.input, "in.png");
  EXPECT_EQ(t.name, "a");
  EXPECT_EQ(t.count, 7);
  EXPECT_TRUE(t.quiet);
  EXPECT_TRUE(t.cli.given("--count"));
  EXPECT_FALSE(Tool({}).cli.given("--count"));
}

TEST(CommandLine, BadArgumentsExitTwoNamingTheOption) {
  Tool t({});
  EXPECT_EQ(t.run({"in", "--count", "11"}), 2);
  EXPECT_EQ(t.cli.error(), "--count '11': expected an integer in [1, 10]");
  Tool u({});
  EXPECT_EQ(u.run({"in", "--count", "two"}), 2);
  EXPECT_TRUE(has(u.cli.error(), "'two'")) << u.cli.error();
  Tool v({});
  EXPECT_EQ(v.run({"in", "--bogus"}), 2);
  EXPECT_TRUE(has(v.cli.error(), "--bogus")) << v.cli.error();
  Tool w({});
  EXPECT_EQ(w.run({"in", "--name"}), 2);
  EXPECT_TRUE(has(w.cli.error(), "--name needs a value")) << w.cli.error();
  Tool x({});
  EXPECT_EQ(x.run({"--quiet"}), 2);
  EXPECT_EQ(x.cli.error(), "INPUT is required");
  Tool y({});
  EXPECT_EQ(y.run({"in", "extra"}), 2);
  EXPECT_TRUE(has(y.cli.error(), "'extra'")) << y.cli.error();
  Tool h({});
  EXPECT_EQ(h.run({"--help"}), 0);
}

TEST(CommandLine, SetSectionKeyValue) {
  Tool t({"features", "tracker"});
  EXPECT_EQ(t.run({"in", "--set", "features.n_features=500", "--set", "tracker.ba_window_size=12"}), -1)
      << t.cli.error();
  EXPECT_EQ(t.params.features.n_features, 500);
  EXPECT_EQ(t.params.tracker.ba_window_size, 12);
  EXPECT_EQ(t.params.user_set.count("features.n_features"), 1u);  // the resolution rule keeps it
  EXPECT_EQ(t.params.features.cell_size, FeatureParams().cell_size);
}

TEST(CommandLine, SetErrorsNameSectionKeyAndValue) {
  Tool bad_section({"features", "tracker"});
  EXPECT_EQ(bad_section.run({"in", "--set", "featurez.n_features=500"}), 2);
  EXPECT_EQ(bad_section.cli.error(),
            "--set 'featurez.n_features=500': unknown section 'featurez' (sections: features, tracker)");
  Tool unused_section({"features"});
  EXPECT_EQ(unused_section.run({"in", "--set", "tracker.ba_window_size=12"}), 2);
  EXPECT_TRUE(has(unused_section.cli.error(), "does not use tracker parameters")) << unused_section.cli.error();
  Tool bad_key({"features"});
  EXPECT_EQ(bad_key.run({"in", "--set", "features.n_featurez=500"}), 2);
  EXPECT_TRUE(has(bad_key.cli.error(), "unknown features parameter 'n_featurez'")) << bad_key.cli.error();
  Tool bad_value({"features"});
  EXPECT_EQ(bad_value.run({"in", "--set", "features.n_features=many"}), 2);
  EXPECT_TRUE(has(bad_value.cli.error(), "bad value 'many' for features parameter 'n_features'"))
      << bad_value.cli.error();
  Tool out_of_range({"features"});
  EXPECT_EQ(out_of_range.run({"in", "--set", "features.n_features=20"}), 2);
  EXPECT_EQ(out_of_range.cli.error(), "invalid features parameters: n_features must be in [50, 10000] (got 20)");
  Tool no_equals({"features"});
  EXPECT_EQ(no_equals.run({"in", "--set", "features.n_features"}), 2);
  EXPECT_TRUE(has(no_equals.cli.error(), "expected section.key=value")) << no_equals.cli.error();
}

TEST(CommandLine, ConfigThenSetInOrder) {
  const std::string cfg = writeFile("ok.yaml", "features:\n  n_features: 600\n  cell_size: 40\nother: 1\n");
  Tool t({"features"});
  EXPECT_EQ(t.run({"in", "--config", cfg, "--set", "features.n_features=700"}), -1) << t.cli.error();
  EXPECT_EQ(t.params.features.n_features, 700);  // --set after --config
  EXPECT_EQ(t.params.features.cell_size, 40);
}

TEST(CommandLine, ConfigErrorsNameTheFile) {
  const std::string missing = tmpRoot() + "cli_missing.yaml";
  Tool t({"features"});
  EXPECT_EQ(t.run({"in", "--config", missing}), 2);
  EXPECT_EQ(t.cli.error(), "--config " + missing + ": cannot read the file");
  const std::string bad = writeFile("bad.yaml", "features:\n  n_features: 20\n");
  Tool u({"features"});
  EXPECT_EQ(u.run({"in", "--config", bad}), 2);
  EXPECT_TRUE(has(u.cli.error(), bad) && has(u.cli.error(), "n_features must be in [50, 10000] (got 20)"))
      << u.cli.error();
}

TEST(CommandLine, DeprecatedFormsStillWorkWhereUnambiguous) {
  // --params = --config; a root-level map is the tool's legacy section.
  const std::string root_map = writeFile("root.yaml", "mu_expected: 50\n");
  Tool t({"enhance"}, "enhance");
  EXPECT_EQ(t.run({"in", "--params", root_map}), -1) << t.cli.error();
  EXPECT_EQ(t.params.enhance.mu_expected, 50.0);
  // key=value without section: taken where exactly one of the tool's sections has the key.
  Tool u({"enhance", "features"});
  EXPECT_EQ(u.run({"in", "--set", "eta=2", "--set", "n_features=800"}), -1) << u.cli.error();
  EXPECT_EQ(u.params.enhance.eta, 2.0);
  EXPECT_EQ(u.params.features.n_features, 800);
  Tool v({"features"});
  EXPECT_EQ(v.run({"in", "--set", "eta=2"}), 2);  // not a features parameter
  EXPECT_TRUE(has(v.cli.error(), "no features parameter is named 'eta'")) << v.cli.error();
}

TEST(CommandLine, HelpListsTheSettableParameters) {
  Tool t({"enhance", "features"});
  const std::string help = t.cli.usage();
  for (const char* name : {"--config FILE", "--set SECTION.KEY=VALUE", "enhance: method", "mu_expected", "n_features",
                           "eq23_literal"})
    EXPECT_TRUE(has(help, name)) << name << " missing in:\n" << help;
  EXPECT_FALSE(has(help, "ba_window_size")) << help;  // not a section of this tool
}
