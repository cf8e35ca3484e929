// TrackerParams: validation, YAML loading, and cfg/Tracker.cfg naming / defaults consistency.
#include <gtest/gtest.h>
#include <iraf_vo/tracking/tracker.h>
#include <iraf_vo/tracking/tracker_params_io.h>
#include <yaml-cpp/yaml.h>

#include <cstring>
#include <fstream>
#include <new>
#include <regex>
#include <set>
#include <sstream>

using namespace iraf_vo;

TEST(TrackerParams, DefaultsValidateAndBadValuesAreNamed) {
  EXPECT_EQ(validate(TrackerParams()), "");
  TrackerParams p;
  p.max_map_keyframes = 5;
  p.ba_window_size = 10;
  EXPECT_NE(validate(p).find("max_map_keyframes"), std::string::npos);
  p = TrackerParams();
  p.search_radius_px = -1;
  EXPECT_NE(validate(p).find("search_radius_px"), std::string::npos);
}

TEST(TrackerParams, YamlLoading) {
  TrackerParams p;
  std::string err;
  ASSERT_TRUE(loadTrackerParams(YAML::Load("{ba_window_size: 7, mapping_thread: false, search_radius_px: 12.5}"), &p, &err))
      << err;
  EXPECT_EQ(p.ba_window_size, 7);
  EXPECT_FALSE(p.mapping_thread);
  EXPECT_DOUBLE_EQ(p.search_radius_px, 12.5);
  TrackerParams q;
  EXPECT_FALSE(loadTrackerParams(YAML::Load("{no_such_key: 1}"), &q, &err));
  EXPECT_NE(err.find("no_such_key"), std::string::npos);
  EXPECT_FALSE(loadTrackerParams(YAML::Load("{ba_window_size: abc}"), &q, &err));
  EXPECT_NE(err.find("abc"), std::string::npos);
  EXPECT_FALSE(loadTrackerParams(YAML::Load("{ba_window_size: 1}"), &q, &err));  // fails validation
  EXPECT_NE(err.find("ba_window_size"), std::string::npos);
  EXPECT_EQ(q.ba_window_size, TrackerParams().ba_window_size);  // unchanged on failure
}

// Every cfg parameter is a TrackerParams field with the same default, and every field is in the cfg.
TEST(TrackerParams, CfgMatchesStruct) {
  std::ifstream f(std::string(IRAF_VO_SOURCE_DIR) + "/cfg/Tracker.cfg");
  ASSERT_TRUE(f.good());
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  const std::regex add(R"re(\.add\("(\w+)",\s*(\w+),\s*0,\s*"[^"]*",\s*([^,\)]+))re");
  std::set<std::string> in_cfg;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), add); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[1], type = (*it)[2];
    std::string def = (*it)[3];
    in_cfg.insert(name);
    // Setting the cfg default on a default struct must be accepted and leave it equal to the default.
    // Zeroed storage so padding bytes compare equal (the constructor only writes the fields).
    alignas(TrackerParams) unsigned char sa[sizeof(TrackerParams)], sb[sizeof(TrackerParams)];
    std::memset(sa, 0, sizeof(sa));
    std::memset(sb, 0, sizeof(sb));
    TrackerParams& a = *new (sa) TrackerParams();
    TrackerParams& b = *new (sb) TrackerParams();
    std::string err;
    if (type == "bool_t") def = def == "True" ? "true" : "false";
    ASSERT_TRUE(setTrackerParam(&a, name, def, &err)) << name << ": " << err;
    EXPECT_EQ(std::memcmp(&a, &b, sizeof(TrackerParams)), 0) << name << " default differs from the cfg (" << def << ")";
  }
  for (const std::string& n : trackerParamNames()) EXPECT_TRUE(in_cfg.count(n)) << n << " missing in cfg/Tracker.cfg";
  EXPECT_EQ(in_cfg.size(), trackerParamNames().size());
}
