// TrackerParams: validation and YAML loading.
#include <gtest/gtest.h>
#include <iraf_vo/tracking/tracker.h>
#include <iraf_vo/tracking/tracker_params.h>
#include <yaml-cpp/yaml.h>


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
  ASSERT_TRUE(trackerParamTable().load(YAML::Load("{ba_window_size: 7, mapping_thread: false, search_radius_px: 12.5}"), &p, &err))
      << err;
  EXPECT_EQ(p.ba_window_size, 7);
  EXPECT_FALSE(p.mapping_thread);
  EXPECT_DOUBLE_EQ(p.search_radius_px, 12.5);
  TrackerParams q;
  EXPECT_FALSE(trackerParamTable().load(YAML::Load("{no_such_key: 1}"), &q, &err));
  EXPECT_NE(err.find("no_such_key"), std::string::npos);
  EXPECT_FALSE(trackerParamTable().load(YAML::Load("{ba_window_size: abc}"), &q, &err));
  EXPECT_NE(err.find("abc"), std::string::npos);
  EXPECT_FALSE(trackerParamTable().load(YAML::Load("{ba_window_size: 1}"), &q, &err));  // fails validation
  EXPECT_NE(err.find("ba_window_size"), std::string::npos);
  EXPECT_EQ(q.ba_window_size, TrackerParams().ba_window_size);  // unchanged on failure
}

// cfg/Tracker.cfg == table == struct defaults: test_params.cpp (ParamTables.TrackerCfgEqualsTableEqualsStruct).
