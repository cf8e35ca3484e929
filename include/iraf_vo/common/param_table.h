// One parameter table per stage (SVO Pro style: one options struct per module, read by one loader). A table lists
// every field of a parameter struct once, one row per field: name (= struct field = cfg/<Stage>.cfg parameter = YAML
// key), member, accepted range and one-line doc (= the cfg description). The default is the struct's own
// (default-constructed S). The table drives YAML loading, `--set section.key=value`, ROS private parameters, the
// dynamic_reconfigure bridge (src/nodelets/param_bridge.h), validation (each row's range, then the struct's
// cross-field rule) and docs/parameters.md; test_params checks cfg == table == struct defaults. ROS-free.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace iraf_vo {

enum class ParamType { kInt, kDouble, kBool, kText };  // kText: strings and enums (as their names)
const char* toString(ParamType t);

/// Strict text parsers shared by every table: the whole text must parse. Int also takes integral decimals ("5.0");
/// double must be finite; bool takes true/false, 1/0, yes/no, on/off (as YAML) in lower, Title or UPPER case.
bool parseIntText(const std::string& s, int* v);
bool parseDoubleText(const std::string& s, double* v);
bool parseBoolText(const std::string& s, bool* v);
/// Shortest text that parses back to the same double.
std::string formatDouble(double v);

template <class S>
struct ParamEntry {
  std::string name;
  ParamType type = ParamType::kInt;
  int S::*int_field = nullptr;
  double S::*double_field = nullptr;
  bool S::*bool_field = nullptr;
  std::function<std::string(const S&)> get_text;         // kText
  std::function<bool(const std::string&, S*)> set_text;  // kText: false for an unknown name
  double min = 0.0, max = 0.0;  // accepted range, inclusive (kInt / kDouble): validation and the cfg slider
  bool odd = false;  // odd values only (the cfg slider may give even ones: the ROS bridge rounds them up to odd)
  std::string doc;   // = the cfg description
};

template <class S>
ParamEntry<S> intParam(std::string name, int S::*f, int min, int max, std::string doc, bool odd = false) {
  ParamEntry<S> e;
  e.name = std::move(name), e.type = ParamType::kInt, e.int_field = f, e.min = min, e.max = max, e.odd = odd;
  e.doc = std::move(doc);
  return e;
}
template <class S>
ParamEntry<S> doubleParam(std::string name, double S::*f, double min, double max, std::string doc) {
  ParamEntry<S> e;
  e.name = std::move(name), e.type = ParamType::kDouble, e.double_field = f, e.min = min, e.max = max;
  e.doc = std::move(doc);
  return e;
}
template <class S>
ParamEntry<S> boolParam(std::string name, bool S::*f, std::string doc) {
  ParamEntry<S> e;
  e.name = std::move(name), e.type = ParamType::kBool, e.bool_field = f, e.doc = std::move(doc);
  return e;
}
/// An enum field stored by name: `to_string(E)` and `parse(text, E*)` are the enum's own functions.
template <class S, class E>
ParamEntry<S> enumParam(std::string name, E S::*f, const char* (*to_string)(E), bool (*parse)(const std::string&, E*),
                        std::string doc) {
  ParamEntry<S> e;
  e.name = std::move(name), e.type = ParamType::kText, e.doc = std::move(doc);
  e.get_text = [f, to_string](const S& p) { return std::string(to_string(p.*f)); };
  e.set_text = [f, parse](const std::string& s, S* p) { return parse(s, &(p->*f)); };
  return e;
}

template <class S>
class ParamTable {
 public:
  /// The rules between fields of one struct: "" when they hold, else messages naming the fields.
  using CrossCheck = std::string (*)(const S&);
  /// `section`: the YAML section / --set prefix ("enhance"); `cross_check`: null when the fields are independent;
  /// `cross_check_doc`: what it checks, for docs/parameters.md.
  ParamTable(std::string section, std::vector<ParamEntry<S>> entries, CrossCheck cross_check = nullptr,
             std::string cross_check_doc = "")
      : section_(std::move(section)),
        entries_(std::move(entries)),
        cross_check_(cross_check),
        cross_check_doc_(std::move(cross_check_doc)) {}

  const std::string& section() const { return section_; }
  const std::string& crossCheckDoc() const { return cross_check_doc_; }
  const std::vector<ParamEntry<S>>& entries() const { return entries_; }

  /// "" when every field is in its row's range (odd where marked) and the cross-field rule holds; else one message
  /// per violation ("name must be in [min, max] (got v)"), joined by "; ".
  std::string validate(const S& p) const {
    std::string out;
    const auto add = [&out](const std::string& m) {
      if (!m.empty()) out += (out.empty() ? "" : "; ") + m;
    };
    for (const ParamEntry<S>& e : entries_) add(checkRange(p, e));
    if (cross_check_) add(cross_check_(p));
    return out;
  }

  /// "" or "<name> must be [odd and ]in [min, max] (got v)" for one row (kBool / kText: always "").
  std::string checkRange(const S& p, const ParamEntry<S>& e) const {
    bool ok = true;
    if (e.type == ParamType::kInt) {
      const int v = p.*(e.int_field);
      ok = v >= e.min && v <= e.max && (!e.odd || v % 2 != 0);
    } else if (e.type == ParamType::kDouble) {
      const double v = p.*(e.double_field);
      ok = v >= e.min && v <= e.max;  // false for NaN
    }
    return ok ? "" : e.name + " must be " + rangeText(e) + " (got " + get(p, e) + ")";
  }

  /// The accepted values as text: "in [1, 15]", "odd and in [1, 15]", "true or false", or "" (kText: see the doc).
  static std::string rangeText(const ParamEntry<S>& e) {
    switch (e.type) {
      case ParamType::kInt:
      case ParamType::kDouble:
        return std::string(e.odd ? "odd and " : "") + "in [" + formatDouble(e.min) + ", " + formatDouble(e.max) + "]";
      case ParamType::kBool: return "true or false";
      case ParamType::kText: return "";
    }
    return "";
  }

  /// The default of a row: its value in a default-constructed S (the struct's initializers are the defaults).
  std::string defaultText(const ParamEntry<S>& e) const { return get(S{}, e); }

  const ParamEntry<S>* find(const std::string& name) const {
    for (const ParamEntry<S>& e : entries_)
      if (e.name == name) return &e;
    return nullptr;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> n;
    for (const ParamEntry<S>& e : entries_) n.push_back(e.name);
    return n;
  }

  /// Sets one field from text ("ba_window_size", "12"). false + *error naming the key (and the value).
  bool set(S* p, const std::string& key, const std::string& value, std::string* error) const {
    const ParamEntry<S>* e = find(key);
    if (!e) return fail(error, "unknown " + section_ + " parameter '" + key + "'");
    bool ok = false;
    switch (e->type) {
      case ParamType::kInt: ok = parseIntText(value, &(p->*(e->int_field))); break;
      case ParamType::kDouble: ok = parseDoubleText(value, &(p->*(e->double_field))); break;
      case ParamType::kBool: ok = parseBoolText(value, &(p->*(e->bool_field))); break;
      case ParamType::kText: ok = e->set_text(value, p); break;
    }
    if (!ok)
      return fail(error, "bad value '" + value + "' for " + section_ + " parameter '" + key + "' (expected " +
                             toString(e->type) + ")");
    return true;
  }

  /// The field's value as text (parses back with set()).
  std::string get(const S& p, const ParamEntry<S>& e) const {
    switch (e.type) {
      case ParamType::kInt: return std::to_string(p.*(e.int_field));
      case ParamType::kDouble: return formatDouble(p.*(e.double_field));
      case ParamType::kBool: return p.*(e.bool_field) ? "true" : "false";
      case ParamType::kText: return e.get_text(p);
    }
    return "";
  }

  /// Reads every key of a YAML map (null: nothing to change), then validates. All or nothing: *p is changed only
  /// on success. Unknown keys, non-scalar or unparsable values and invalid results -> false + *error naming the key.
  bool load(const YAML::Node& node, S* p, std::string* error) const {
    if (!node.IsDefined() || node.IsNull()) return true;
    if (!node.IsMap()) return fail(error, section_ + " parameters must be a YAML map of key: value");
    S q = *p;
    for (const auto& kv : node) {
      const std::string key = kv.first.as<std::string>("");  // fallback: a non-scalar key (e.g. "? ? 4") threw
      if (!kv.second.IsScalar()) return fail(error, section_ + " parameter '" + key + "' must be a scalar");
      if (!set(&q, key, kv.second.Scalar(), error)) return false;
    }
    if (!validateInto(q, error)) return false;
    *p = q;
    return true;
  }

  /// "" or "invalid <section> parameters: ..." for *error.
  bool validateInto(const S& p, std::string* error) const {
    const std::string v = validate(p);
    return v.empty() || fail(error, "invalid " + section_ + " parameters: " + v);
  }

 private:
  static bool fail(std::string* error, const std::string& m) {
    if (error) *error = m;
    return false;
  }

  std::string section_;
  std::vector<ParamEntry<S>> entries_;
  CrossCheck cross_check_;
  std::string cross_check_doc_;
};

}  // namespace iraf_vo
