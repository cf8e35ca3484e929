#include "iraf_vo/pipeline/command_line.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <utility>

namespace iraf_vo {

namespace {

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const std::string& s : v) out += (out.empty() ? "" : ", ") + s;
  return out;
}

/// Whether the stage table `section` has a row `key`.
bool hasParam(const std::string& section, const std::string& key) {
  bool found = false;
  const PipelineParams defaults;
  forEachStage(defaults, [&](const auto& table, const auto&) {
    if (table.section() == section && table.find(key)) found = true;
  });
  return found;
}

}  // namespace

CommandLine::CommandLine(std::string tool, std::string summary)
    : tool_(std::move(tool)), summary_(std::move(summary)) {}

void CommandLine::add(Spec s) { specs_.push_back(std::move(s)); }

CommandLine::Spec* CommandLine::find(const std::string& name) {
  for (Spec& s : specs_)
    if (s.name == name) return &s;
  return nullptr;
}

void CommandLine::option(const std::string& name, const std::string& metavar, std::string* value,
                         const std::string& help) {
  Spec s{name, metavar, help};
  s.set = [value](const std::string& v) { return *value = v, true; };
  add(std::move(s));
}

void CommandLine::option(const std::string& name, const std::string& metavar, int* value, int min, int max,
                         const std::string& help) {
  Spec s{name, metavar, help};
  s.expected = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  s.set = [value, min, max](const std::string& v) {
    int x;
    return parseIntText(v, &x) && x >= min && x <= max && (*value = x, true);
  };
  add(std::move(s));
}

void CommandLine::option(const std::string& name, const std::string& metavar, double* value, double min, double max,
                         const std::string& help) {
  Spec s{name, metavar, help};
  s.expected = "a number in [" + formatDouble(min) + ", " + formatDouble(max) + "]";
  s.set = [value, min, max](const std::string& v) {
    double x;
    return parseDoubleText(v, &x) && x >= min && x <= max && (*value = x, true);
  };
  add(std::move(s));
}

void CommandLine::optionalValue(const std::string& name, const std::string& metavar, std::string* value,
                                const std::string& bare, const std::string& help) {
  Spec s{name, metavar, help, bare};
  s.optional_value = true;
  s.set = [value](const std::string& v) { return *value = v, true; };
  add(std::move(s));
}

void CommandLine::flag(const std::string& name, bool* value, const std::string& help, bool to) {
  Spec s{name, "", help};
  s.takes_value = false;
  s.set = [value, to](const std::string&) { return *value = to, true; };
  add(std::move(s));
}

void CommandLine::positional(const std::string& metavar, std::string* value, const std::string& help, bool required) {
  positionals_.push_back({metavar, help, value, required});
}

void CommandLine::require(const std::string& name) {
  if (Spec* s = find(name)) s->required = true;
}

void CommandLine::stageParams(const std::vector<std::string>& sections, const std::string& legacy_section) {
  for (const std::string& s : pipelineSections())  // pipeline order
    if (contains(sections, s)) sections_.push_back(s);
  legacy_section_ = legacy_section;
  std::string maps;
  for (const std::string& s : sections_) maps += (maps.empty() ? "" : ", ") + s + ":";
  Spec config{"--config", "FILE", "YAML with the maps " + maps + " (keys = parameter names; other keys are ignored)"};
  config.set = [this](const std::string& v) { return config_path_ = v, config_is_deprecated_alias_ = false, true; };
  add(std::move(config));
  Spec params{"--params", "FILE", "deprecated alias of --config"};
  params.set = [this](const std::string& v) {
    warn("--params is deprecated: use --config " + v);
    return config_path_ = v, config_is_deprecated_alias_ = true, true;
  };
  add(std::move(params));
  std::string example;  // the first row of the first section at its default
  const PipelineParams defaults;
  forEachStage(defaults, [&](const auto& table, const auto& stage) {
    if (example.empty() && table.section() == sections_.front())
      example = table.section() + "." + table.entries().front().name + "=" + table.get(stage, table.entries().front());
  });
  Spec set{"--set", "SECTION.KEY=VALUE", "one parameter, e.g. --set " + example + " (repeatable; after --config)"};
  set.set = [this](const std::string& v) { return settings_.push_back(v), true; };
  add(std::move(set));
}

int CommandLine::fail(const std::string& message, bool show_usage) {
  error_ = message;
  std::fprintf(stderr, "%s: %s\n", tool_.c_str(), message.c_str());
  if (show_usage) std::fprintf(stderr, "%s", usage().c_str());
  return 2;
}

void CommandLine::warn(const std::string& message) const {
  std::fprintf(stderr, "%s: warning: %s\n", tool_.c_str(), message.c_str());
}

int CommandLine::parse(int argc, const char* const* argv) {
  size_t next_positional = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") return std::fputs(usage().c_str(), stdout), 0;
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      const size_t eq = a.find('=');
      const std::string name = a.substr(0, eq);
      Spec* s = find(name);
      if (!s) return fail("unknown option '" + a + "'", true);
      std::string value = s->bare;
      if (eq != std::string::npos) {
        if (!s->takes_value) return fail(name + " takes no value (got '" + a + "')");
        value = a.substr(eq + 1);
      } else if (s->takes_value && !s->optional_value) {
        if (i + 1 >= argc) return fail(name + " needs a value (" + s->metavar + ")", true);
        value = argv[++i];
      }
      if (!s->set(value)) return fail(name + " '" + value + "': expected " + s->expected);
      s->given = true;
    } else if (next_positional < positionals_.size()) {
      *positionals_[next_positional++].value = a;
    } else {
      return fail("unexpected argument '" + a + "'", true);
    }
  }
  if (next_positional < positionals_.size() && positionals_[next_positional].required)
    return fail(positionals_[next_positional].metavar + " is required", true);
  for (const Spec& s : specs_)
    if (s.required && !s.given) return fail(s.name + " is required", true);
  return -1;
}

bool CommandLine::given(const std::string& name) const {
  for (const Spec& s : specs_)
    if (s.name == name) return s.given;
  return false;
}

bool CommandLine::loadConfig(const std::string& path, bool deprecated_alias, PipelineParams* p) {
  const std::string option = deprecated_alias ? "--params" : "--config";
  if (!std::ifstream(path).good()) return fail(option + " " + path + ": cannot read the file"), false;
  std::string err;
  if (deprecated_alias && !legacy_section_.empty()) {
    // The old files of this tool were one root-level map of legacy_section_ keys.
    YAML::Node root;
    try {
      root = YAML::LoadFile(path);
    } catch (const std::exception& e) {
      return fail(option + " " + path + ": " + e.what()), false;
    }
    bool has_section = false;
    for (const std::string& s : pipelineSections()) has_section = has_section || (root.IsMap() && root[s]);
    if (root.IsMap() && !has_section) {
      warn(path + ": a root-level map is read as '" + legacy_section_ + ":' (deprecated: put the keys under '" +
           legacy_section_ + ":')");
      if (!loadPipelineSection(legacy_section_, root, p, &err)) return fail(option + " " + path + ": " + err), false;
      return true;
    }
  }
  if (!loadPipelineConfig(path, p, &err)) return fail(option + " " + err), false;
  return true;
}

bool CommandLine::applySetting(const std::string& setting, PipelineParams* p) {
  const size_t eq = setting.find('='), dot = setting.find('.');
  if (eq == std::string::npos) return fail("--set '" + setting + "': expected section.key=value"), false;
  std::string section, key = setting.substr(0, eq);
  if (dot == std::string::npos || dot > eq) {
    // The old form key=value: accepted with a warning where exactly one of the tool's sections has the key.
    std::vector<std::string> having;
    for (const std::string& s : sections_)
      if (hasParam(s, key)) having.push_back(s);
    if (having.size() != 1)
      return fail("--set '" + setting + "': expected section.key=value (" +
                  (having.empty() ? "no " + join(sections_) + " parameter is named '" + key + "'"
                                  : "'" + key + "' is in " + join(having)) +
                  ")"),
             false;
    section = having.front();
    warn("--set " + setting + " is deprecated: use --set " + section + "." + setting);
  } else {
    section = setting.substr(0, dot);
    key = setting.substr(dot + 1, eq - dot - 1);
  }
  if (!contains(sections_, section))
    return fail("--set '" + setting + "': " +
                (contains(pipelineSections(), section) ? tool_ + " does not use " + section + " parameters"
                                                       : "unknown section '" + section + "'") +
                " (sections: " + join(sections_) + ")"),
           false;
  std::string err;
  if (!setPipelineParam(section, key, setting.substr(eq + 1), p, &err))
    return fail("--set '" + setting + "': " + err), false;
  return true;
}

int CommandLine::applyStageParams(PipelineParams* p) {
  if (!config_path_.empty() && !loadConfig(config_path_, config_is_deprecated_alias_, p)) return 2;
  for (const std::string& s : settings_)
    if (!applySetting(s, p)) return 2;
  std::string err;
  bool ok = true;
  forEachStage(*p, [&](const auto& table, const auto& stage) {
    if (ok && contains(sections_, table.section()) && !table.validateInto(stage, &err)) ok = false;
  });
  return ok ? -1 : fail(err);
}

std::string CommandLine::usage() const {
  std::string out = "usage: " + tool_ + (specs_.empty() ? "" : " [options]");
  for (const Positional& p : positionals_) out += " " + (p.required ? p.metavar : "[" + p.metavar + "]");
  out += "\n";
  if (!summary_.empty()) out += summary_ + (summary_.back() == '\n' ? "" : "\n");
  const auto line = [&out](std::string left, const std::string& help) {
    left = "  " + left;
    if (left.size() < 26) left.resize(26, ' ');
    else left += "\n" + std::string(26, ' ');
    std::string h = help;
    for (size_t pos = 0; (pos = h.find('\n', pos)) != std::string::npos; pos += 27) h.insert(pos + 1, 26, ' ');
    out += left + h + "\n";
  };
  for (const Positional& p : positionals_) line(p.metavar, p.help);
  for (const Spec& s : specs_)
    line(s.name + (s.optional_value ? "[=" + s.metavar + "]" : s.takes_value ? " " + s.metavar : ""), s.help);
  line("-h, --help", "this text");
  if (!sections_.empty()) out += parameterHelp();
  return out;
}

std::string CommandLine::parameterHelp() const {
  std::string out = "parameters (--set SECTION.KEY=VALUE, or KEY: VALUE under SECTION: in --config):\n";
  const PipelineParams defaults;
  forEachStage(defaults, [&](const auto& table, const auto&) {
    if (!contains(sections_, table.section())) return;
    std::string row = "  " + table.section() + ":";
    for (const std::string& n : table.names()) {
      if (row.size() + 1 + n.size() > 110) out += row + "\n", row = std::string(4, ' ');
      row += " " + n;
    }
    out += row + "\n";
  });
  out += "  types, defaults, ranges and docs: docs/parameters.md (iraf_vo_params --markdown)\n";
  return out;
}

}  // namespace iraf_vo
