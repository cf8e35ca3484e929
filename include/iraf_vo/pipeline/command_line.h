// The command-line parser of every tool in src/tools/: options with a checked value, flags, positional arguments,
// `--help` built from the declarations, and the stage-parameter options shared by every tool that runs a stage:
//   --config FILE             YAML with maps enhance: / features: / tracker: (--params FILE: deprecated alias)
//   --set section.key=value   one parameter (repeatable, applied in order after --config)
// whose --help lists the settable parameters from the stages' tables. Errors name the option and the value;
// parse() and applyStageParams() return the exit code (0 after --help, 2 for bad arguments). ROS-free.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "iraf_vo/pipeline/pipeline_params.h"

namespace iraf_vo {

class CommandLine {
 public:
  /// `tool`: the program name in messages; `summary`: the text under the usage line (may be empty).
  CommandLine(std::string tool, std::string summary);

  /// An option with a value ("--dataset DIR"); `metavar` names the value in --help. Also accepted as --name=value.
  void option(const std::string& name, const std::string& metavar, std::string* value, const std::string& help);
  /// A whole number / a finite number in [min, max].
  void option(const std::string& name, const std::string& metavar, int* value, int min, int max,
              const std::string& help);
  void option(const std::string& name, const std::string& metavar, double* value, double min, double max,
              const std::string& help);
  /// An option whose value is optional: "--name" alone gives `bare`, "--name=VALUE" gives VALUE.
  void optionalValue(const std::string& name, const std::string& metavar, std::string* value, const std::string& bare,
                     const std::string& help);
  /// A flag without a value: sets *value to `to`.
  void flag(const std::string& name, bool* value, const std::string& help, bool to = true);
  /// The next positional argument (in declaration order); optional ones must come last.
  void positional(const std::string& metavar, std::string* value, const std::string& help, bool required = true);
  /// Options that must be given ("--dataset").
  void require(const std::string& name);

  /// Adds --config / --params / --set for the given sections (enhance | features | tracker; their tables' order).
  /// `legacy_section`: where an old `--set key=value` without section, or a deprecated `--params` file that is one
  /// root-level map, belongs ("" = nowhere: then a key without section must be unique among `sections`).
  void stageParams(const std::vector<std::string>& sections, const std::string& legacy_section = "");

  /// Parses argv[1..]: -1 when the tool should run, else the exit code (0 after --help: usage on stdout; 2 after an
  /// error: message and usage on stderr).
  int parse(int argc, const char* const* argv);
  /// Loads --config, then applies each --set in order and validates the tool's sections (after the tool has set
  /// its own defaults, e.g. a mode, in *p). -1 when usable, else 2 with a message on stderr.
  int applyStageParams(PipelineParams* p);

  /// Whether an option was given on the command line.
  bool given(const std::string& name) const;
  /// The last error (also printed), "" if none.
  const std::string& error() const { return error_; }
  std::string usage() const;

 private:
  struct Spec {
    Spec(std::string n, std::string m, std::string h, std::string b = "")
        : name(std::move(n)), metavar(std::move(m)), help(std::move(h)), bare(std::move(b)) {}
    std::string name, metavar, help, bare;
    bool takes_value = true, optional_value = false, required = false, given = false;
    std::function<bool(const std::string&)> set;  // false: bad value
    std::string expected;                         // "an integer in [1, 100]" for messages
  };
  struct Positional {
    std::string metavar, help;
    std::string* value;
    bool required;
  };
  Spec* find(const std::string& name);
  void add(Spec s);
  int fail(const std::string& message, bool show_usage = false);
  void warn(const std::string& message) const;
  bool applySetting(const std::string& setting, PipelineParams* p);
  bool loadConfig(const std::string& path, bool deprecated_alias, PipelineParams* p);
  std::string parameterHelp() const;

  std::string tool_, summary_, error_;
  std::vector<Spec> specs_;
  std::vector<Positional> positionals_;
  // Stage parameters (stageParams()).
  std::vector<std::string> sections_;
  std::string legacy_section_, config_path_;
  bool config_is_deprecated_alias_ = false;
  std::vector<std::string> settings_;
};

}  // namespace iraf_vo
