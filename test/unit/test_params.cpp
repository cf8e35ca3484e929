// Parameter tables (common/param_table.h): per stage, cfg/<Stage>.cfg == table == struct defaults; validation from
// the table's ranges; the table's text / YAML loading. The cfg files are parsed as text (the generator's gen.add(...) / group.add(...) lines).
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <new>
#include <regex>
#include <set>
#include <sstream>

#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/features/feature_params.h"
#include "iraf_vo/tracking/tracker_params.h"

using namespace iraf_vo;

namespace {

struct CfgParam {
  std::string name, type, doc, def, min, max;
};

std::vector<CfgParam> readCfg(const std::string& stage) {
  std::ifstream f(std::string(IRAF_VO_SOURCE_DIR) + "/cfg/" + stage + ".cfg");
  EXPECT_TRUE(f.good()) << stage;
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  // .add("name", type_t, 0, "doc", default[, min, max][, edit_method=...])
  const std::regex add(
      R"re(\.add\("(\w+)",\s*(\w+),\s*0,\s*"([^"]*)",\s*("[^"]*"|[^,\)]+)(?:,\s*([^,\)=]+),\s*([^,\)=]+))?)re");
  std::vector<CfgParam> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), add); it != std::sregex_iterator(); ++it)
    out.push_back({(*it)[1], (*it)[2], (*it)[3], (*it)[4], (*it)[5], (*it)[6]});
  return out;
}

ParamType typeOf(const std::string& cfg_type) {
  if (cfg_type == "int_t") return ParamType::kInt;
  if (cfg_type == "double_t") return ParamType::kDouble;
  if (cfg_type == "bool_t") return ParamType::kBool;
  return ParamType::kText;
}

/// cfg default text -> the text ParamTable::get() gives for the same value.
std::string canonical(const CfgParam& c) {
  if (c.type == "bool_t") return c.def == "True" ? "true" : "false";
  if (c.type == "str_t") return c.def.substr(1, c.def.size() - 2);
  if (c.type == "double_t") return formatDouble(std::stod(c.def));
  return c.def;
}

/// Every cfg parameter but `nodelet_only` is a table entry of the same type, doc, range and default (the struct's
/// default), every entry is in the cfg, and no two entries share a member.
template <class S>
void expectCfgMatchesTable(const std::string& stage, const ParamTable<S>& table,
                           const std::set<std::string>& nodelet_only = {}) {
  const std::vector<CfgParam> cfg = readCfg(stage);
  ASSERT_FALSE(cfg.empty()) << stage;
  std::set<std::string> in_cfg;
  const S defaults{};
  for (const CfgParam& c : cfg) {
    in_cfg.insert(c.name);
    if (nodelet_only.count(c.name)) continue;
    const ParamEntry<S>* e = table.find(c.name);
    ASSERT_TRUE(e) << c.name << " of cfg/" << stage << ".cfg is not in the " << table.section() << " table";
    EXPECT_EQ(e->type, typeOf(c.type)) << c.name;
    EXPECT_EQ(e->doc, c.doc) << c.name;
    EXPECT_EQ(table.get(defaults, *e), canonical(c)) << c.name << ": struct default != cfg default";
    if (e->type == ParamType::kInt || e->type == ParamType::kDouble) {
      EXPECT_EQ(e->min, std::stod(c.min)) << c.name;
      EXPECT_EQ(e->max, std::stod(c.max)) << c.name;
    }
  }
  for (const ParamEntry<S>& e : table.entries()) EXPECT_TRUE(in_cfg.count(e.name)) << e.name << " missing in cfg";
  EXPECT_EQ(table.entries().size() + nodelet_only.size(), in_cfg.size());
  for (size_t i = 0; i < table.entries().size(); ++i)
    for (size_t j = i + 1; j < table.entries().size(); ++j) {
      const ParamEntry<S>& a = table.entries()[i];
      const ParamEntry<S>& b = table.entries()[j];
      if (a.type != b.type || a.type == ParamType::kText) continue;
      EXPECT_FALSE(a.int_field == b.int_field && a.double_field == b.double_field && a.bool_field == b.bool_field)
          << a.name << " and " << b.name << " point to the same field";
    }
}

/// get() of every entry parses back with set() on a default struct to the same bytes (zeroed storage so padding
/// compares equal), and a value other than the default changes the struct.
template <class S>
void expectTextRoundTrip(const ParamTable<S>& table) {
  for (const ParamEntry<S>& e : table.entries()) {
    alignas(S) unsigned char sa[sizeof(S)], sb[sizeof(S)];
    std::memset(sa, 0, sizeof(sa));
    std::memset(sb, 0, sizeof(sb));
    S& a = *new (sa) S();
    S& b = *new (sb) S();
    std::string err;
    ASSERT_TRUE(table.set(&a, e.name, table.get(b, e), &err)) << e.name << ": " << err;
    EXPECT_EQ(std::memcmp(&a, &b, sizeof(S)), 0) << e.name;
    if (e.type == ParamType::kText) continue;
    const std::string other =
        e.type == ParamType::kBool ? (table.get(b, e) == "true" ? "false" : "true") : formatDouble(e.max);
    if (other == table.get(b, e)) continue;
    ASSERT_TRUE(table.set(&a, e.name, other, &err)) << e.name << ": " << err;
    EXPECT_NE(std::memcmp(&a, &b, sizeof(S)), 0) << e.name << " = " << other << " did not change the struct";
    EXPECT_EQ(table.get(a, e), other) << e.name;
  }
}

/// Each int / double row: both ends of its range pass the row's check; a value just below and just above it makes
/// the stage's validate() name the row and its range; an odd row rejects an even value.
template <class S>
void expectValidationFollowsTheTable(const ParamTable<S>& table, std::string (*validate_stage)(const S&)) {
  ASSERT_EQ(validate_stage(S{}), "") << table.section();
  for (const ParamEntry<S>& e : table.entries()) {
    if (e.type != ParamType::kInt && e.type != ParamType::kDouble) continue;
    const auto with = [&e](double v) {
      S p{};
      if (e.type == ParamType::kInt) p.*(e.int_field) = static_cast<int>(v);
      else p.*(e.double_field) = v;
      return p;
    };
    for (double end : {e.min, e.max}) EXPECT_EQ(table.checkRange(with(end), e), "") << e.name << " = " << end;
    const bool is_int = e.type == ParamType::kInt;
    const double inf = std::numeric_limits<double>::infinity();
    for (double v : {is_int ? e.min - 1 : std::nextafter(e.min, -inf), is_int ? e.max + 1 : std::nextafter(e.max, inf)}) {
      const std::string msg = validate_stage(with(v));
      EXPECT_NE(msg.find(e.name + " must be " + table.rangeText(e) + " (got "), std::string::npos)
          << e.name << " = " << v << ": '" << msg << "'";
    }
    if (e.odd) {
      EXPECT_NE(validate_stage(with(e.min + 1)).find(e.name + " must be odd"), std::string::npos) << e.name;
    }
  }
}

}  // namespace

TEST(ParamTables, EnhanceCfgEqualsTableEqualsStruct) {
  expectCfgMatchesTable("Enhance", enhanceParamTable(), {"enabled"});
  expectTextRoundTrip(enhanceParamTable());
}

TEST(ParamTables, FeaturesCfgEqualsTableEqualsStruct) {
  expectCfgMatchesTable("Features", featureParamTable());
  expectTextRoundTrip(featureParamTable());
}

TEST(ParamTables, TrackerCfgEqualsTableEqualsStruct) {
  expectCfgMatchesTable("Tracker", trackerParamTable());
  expectTextRoundTrip(trackerParamTable());
  EXPECT_EQ(trackerParamTable().find("scale_factor"), nullptr);  // travels with the features (FeatureFrame)
}

TEST(ParamTables, TextParsersAreStrict) {
  int i = 0;
  double d = 0;
  bool b = false;
  EXPECT_TRUE(parseIntText("12", &i) && i == 12);
  EXPECT_TRUE(parseIntText("-3.0", &i) && i == -3);
  EXPECT_FALSE(parseIntText("7.5", &i));
  EXPECT_FALSE(parseIntText("12abc", &i));
  EXPECT_FALSE(parseIntText("", &i));
  EXPECT_FALSE(parseIntText("1e12", &i));  // out of int range
  EXPECT_TRUE(parseDoubleText("2.447", &d) && d == 2.447);
  EXPECT_FALSE(parseDoubleText("nan", &d));
  EXPECT_FALSE(parseDoubleText("inf", &d));
  EXPECT_FALSE(parseDoubleText("1e999", &d));
  EXPECT_TRUE(parseBoolText("True", &b) && b);
  EXPECT_TRUE(parseBoolText("off", &b) && !b);
  EXPECT_FALSE(parseBoolText("maybe", &b));
  for (double x : {0.1, 2.447, 1.0 / 3.0, 1e-7, 254.0}) EXPECT_EQ(std::stod(formatDouble(x)), x);
}

TEST(ParamTables, YamlLoadNamesTheKeyAndIsAllOrNothing) {
  const ParamTable<FeatureParams>& t = featureParamTable();
  FeatureParams p;
  std::string err;
  ASSERT_TRUE(t.load(YAML::Load("{n_features: 500, culling: false, alpha: 2.5}"), &p, &err)) << err;
  EXPECT_EQ(p.n_features, 500);
  EXPECT_FALSE(p.culling);
  EXPECT_DOUBLE_EQ(p.alpha, 2.5);
  EXPECT_TRUE(t.load(YAML::Node(), &p, &err));  // nothing to change
  const FeatureParams before = p;
  for (const char* bad : {"{n_features: 100, no_such_key: 1}", "{n_features: [1, 2]}", "{n_features: lots}",
                          "{n_features: 200, center_window: 4}", "[1, 2]"}) {
    err.clear();
    EXPECT_FALSE(t.load(YAML::Load(bad), &p, &err)) << bad;
    EXPECT_FALSE(err.empty()) << bad;
    EXPECT_EQ(p.n_features, before.n_features) << bad << ": changed although the load failed";
  }
  t.load(YAML::Load("{no_such_key: 1}"), &p, &err);
  EXPECT_NE(err.find("no_such_key"), std::string::npos) << err;
  t.load(YAML::Load("{n_features: lots}"), &p, &err);
  EXPECT_NE(err.find("n_features"), std::string::npos) << err;
  EXPECT_NE(err.find("lots"), std::string::npos) << err;
  t.load(YAML::Load("{center_window: 4}"), &p, &err);
  EXPECT_NE(err.find("center_window"), std::string::npos) << err;
}

TEST(ParamTables, EnumEntriesTakeTheEnumNames) {
  EnhanceParams p;
  std::string err;
  ASSERT_TRUE(enhanceParamTable().set(&p, "method", "clahe", &err)) << err;
  EXPECT_EQ(p.method, EnhanceMethod::kClahe);
  EXPECT_FALSE(enhanceParamTable().set(&p, "method", "fancy", &err));
  EXPECT_NE(err.find("fancy"), std::string::npos) << err;
  EXPECT_EQ(p.method, EnhanceMethod::kClahe);
  EXPECT_EQ(enhanceParamTable().get(p, *enhanceParamTable().find("method")), "clahe");
}

TEST(ParamValidation, EveryRowRejectsValuesOutsideItsRange) {
  expectValidationFollowsTheTable<EnhanceParams>(enhanceParamTable(), validate);
  expectValidationFollowsTheTable<FeatureParams>(featureParamTable(), validate);
  expectValidationFollowsTheTable<TrackerParams>(trackerParamTable(), validate);
}

// The messages, spelled out: the parameter, its range, the value. Values the hand-written checks accepted
// (n_features 20, rho -1) are outside the table ranges and now rejected.
TEST(ParamValidation, MessagesNameTheParameterAndItsRange) {
  EnhanceParams e;
  e.gaussian_kernel_size = 4;
  e.eta = -0.5;
  EXPECT_EQ(validate(e), "gaussian_kernel_size must be odd and in [1, 15] (got 4); eta must be in [0, 5] (got -0.5)");
  FeatureParams f;
  f.n_features = 20;
  f.rho = -1;
  EXPECT_EQ(validate(f), "n_features must be in [50, 10000] (got 20); rho must be in [0, 10] (got -1)");
  TrackerParams t;
  t.ba_window_size = 1;
  EXPECT_EQ(validate(t), "ba_window_size must be in [2, 100] (got 1)");
  std::string err;
  EXPECT_FALSE(trackerParamTable().validateInto(t, &err));
  EXPECT_EQ(err, "invalid tracker parameters: ba_window_size must be in [2, 100] (got 1)");
}

TEST(ParamValidation, TrackerCrossFieldRules) {
  TrackerParams t;
  t.search_radius_wide_px = 10;  // < search_radius_px 15, each in its own range
  EXPECT_EQ(validate(t), "search_radius_wide_px must be >= search_radius_px (got 10 < 15)");
  t = TrackerParams();
  t.ba_window_size = 30;  // > max_map_keyframes 25
  EXPECT_EQ(validate(t), "max_map_keyframes must be >= ba_window_size (got 25 < 30)");
  t.max_map_keyframes = 30;
  EXPECT_EQ(validate(t), "");
}
