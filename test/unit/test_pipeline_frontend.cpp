// The offline pipeline layer: front-end modes, FrontEnd, OfflinePipeline (threads, order, errors) and the pipeline's
// parameter file / overrides.
#include <gtest/gtest.h>
#include <iraf_vo/pipeline/command_line.h>
#include <iraf_vo/pipeline/offline_pipeline.h>
#include <iraf_vo/pipeline/pipeline_params.h>

#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "common/test_data.h"
#include "common/tmp_dir.h"

using namespace iraf_vo;
using iraf_vo_test::texturedImage;

TEST(FrontEndMode, EveryModeParsesBackAndSetsItsSwitches) {
  const FrontEndMode all[] = {FrontEndMode::kIraf,     FrontEndMode::kBaseline, FrontEndMode::kEnhance,
                              FrontEndMode::kAdaptive, FrontEndMode::kCulling,  FrontEndMode::kHe,
                              FrontEndMode::kClahe};
  for (FrontEndMode m : all) {
    FrontEndMode back;
    ASSERT_TRUE(parseFrontEndMode(toString(m), &back)) << toString(m);
    EXPECT_EQ(back, m);
    EXPECT_NE(std::string(frontEndModeList()).find(toString(m)), std::string::npos) << toString(m);
  }
  FrontEndMode m;
  EXPECT_FALSE(parseFrontEndMode("IRAF", &m));
  EnhanceParams ep;
  FeatureParams fp;
  fp.n_features = 777;
  applyFrontEndMode(FrontEndMode::kBaseline, &ep, &fp);
  EXPECT_EQ(ep.method, EnhanceMethod::kNone);
  EXPECT_FALSE(fp.adaptive_threshold);
  EXPECT_FALSE(fp.culling);
  EXPECT_EQ(fp.n_features, 777);  // everything else is kept
  applyFrontEndMode(FrontEndMode::kCulling, &ep, &fp);
  EXPECT_EQ(ep.method, EnhanceMethod::kNone);
  EXPECT_FALSE(fp.adaptive_threshold);
  EXPECT_TRUE(fp.culling);
  applyFrontEndMode(FrontEndMode::kClahe, &ep, &fp);
  EXPECT_EQ(ep.method, EnhanceMethod::kClahe);
  applyFrontEndMode(FrontEndMode::kIraf, &ep, &fp);
  EXPECT_EQ(ep.method, EnhanceMethod::kIraf);
  EXPECT_TRUE(fp.adaptive_threshold && fp.culling);
}

TEST(FrontEnd, ImageToFeaturesEqualsTheStagesCalledByHand) {
  const cv::Mat img = texturedImage(320, 240, 3) * 0.3;  // dim: the enhancement changes the image
  EnhanceParams ep;
  FeatureParams fp;
  fp.scale_factor = 1.3;
  FrontEnd fe(ep, fp);
  FrontEndTiming t;
  const FeatureFrame f = fe.process(img, 12.5, &t);
  Enhancer e;
  FeatureExtractor x;
  const EnhanceResult er = e.enhance(img, ep);
  const FeatureFrame g = x.extract(er.image, 12.5, fp);
  ASSERT_GT(f.keypoints.size(), 10u);
  EXPECT_EQ(f.keypoints.size(), g.keypoints.size());
  EXPECT_EQ(cv::norm(f.descriptors, g.descriptors, cv::NORM_HAMMING), 0.0);
  EXPECT_DOUBLE_EQ(f.stamp, 12.5);
  EXPECT_DOUBLE_EQ(f.scale_factor, 1.3);
  EXPECT_EQ(f.stats.brightness, static_cast<int>(er.brightness));
  EXPECT_GT(t.ms_enhance + t.ms_features, 0.0);
  EXPECT_THROW(fe.process(cv::Mat(), 0.0), std::invalid_argument);
  EXPECT_TRUE(f.image.empty()) << "a monocular front-end holds no image per frame";
  FrontEnd fe_stereo(ep, fp, true);
  const FeatureFrame s = fe_stereo.process(img, 12.5);
  ASSERT_EQ(s.image.size(), img.size()) << "the stereo front-end carries the enhanced image";
  EXPECT_EQ(cv::norm(s.image, er.image, cv::NORM_INF), 0.0);
  EXPECT_EQ(s.keypoints.size(), f.keypoints.size());
}

namespace {

/// n textured frames; frame `bad` is unreadable, frame `wrong_size` has another size.
class FakeSource : public FrameSource {
 public:
  FakeSource(int n, int bad = -1, int wrong_size = -1) : n_(n), bad_(bad), wrong_size_(wrong_size) {}
  size_t size() const override { return n_; }
  bool read(long index, SourceImage* out) override {
    if (index >= n_) return false;
    reads.push_back(index);
    out->stamp = 0.1 * index;
    if (index == bad_)
      out->error = "broken file";
    else
      out->gray = texturedImage(index == wrong_size_ ? 200 : 160, 120, static_cast<unsigned>(index + 1));
    return true;
  }
  std::string describe(long index) const override { return "frame" + std::to_string(index) + ".png"; }
  std::vector<long> reads;

 private:
  int n_, bad_, wrong_size_;
};

std::vector<FrontEndItem> runAll(FakeSource* src, long first, long last) {
  PipelineOptions o;
  o.first = first;
  o.last = last;
  o.width = 160;
  o.height = 120;
  o.camera_name = "cam.yaml";
  o.queue_capacity = 2;
  OfflinePipeline p(src, EnhanceParams(), FeatureParams(), o);
  std::vector<FrontEndItem> out;
  for (FrontEndItem it; p.next(&it);) out.push_back(it);
  return out;
}

}  // namespace

TEST(OfflinePipeline, FramesArriveInOrderWithinTheRangeAndErrorsAreFlagged) {
  FakeSource src(12, /*bad=*/5);
  const std::vector<FrontEndItem> items = runAll(&src, 2, 9);
  ASSERT_EQ(items.size(), 7u);
  for (size_t k = 0; k < items.size(); ++k) {
    EXPECT_EQ(items[k].index, static_cast<long>(2 + k));
    EXPECT_DOUBLE_EQ(items[k].frame.stamp, 0.1 * items[k].index);
    EXPECT_FALSE(items[k].fatal);
    EXPECT_EQ(items[k].error, items[k].index == 5) << items[k].index;
    if (!items[k].error) {
      EXPECT_GT(items[k].frame.keypoints.size(), 0u) << items[k].index;
    }
  }
  EXPECT_EQ(items[3].message, "broken file");
  EXPECT_EQ(runAll(&src, 10, 40).size(), 0u + 2u);  // the source ends before `last`
}

TEST(OfflinePipeline, AnImageOfAnotherSizeIsFatalAndNamesBothFiles) {
  FakeSource src(6, -1, /*wrong_size=*/3);
  const std::vector<FrontEndItem> items = runAll(&src, 0, 6);
  ASSERT_GE(items.size(), 4u);
  EXPECT_TRUE(items[3].fatal);
  EXPECT_NE(items[3].message.find("frame3.png"), std::string::npos) << items[3].message;
  EXPECT_NE(items[3].message.find("cam.yaml"), std::string::npos) << items[3].message;
  EXPECT_NE(items[3].message.find("200x120"), std::string::npos) << items[3].message;
}

TEST(OfflinePipeline, StoppingEarlyJoinsTheThreads) {
  FakeSource src(1000);
  PipelineOptions o;
  o.last = 1000;
  o.width = 160;
  o.height = 120;
  {
    OfflinePipeline p(&src, EnhanceParams(), FeatureParams(), o);
    FrontEndItem it;
    ASSERT_TRUE(p.next(&it));
  }  // destructor with ~1000 frames left
  EXPECT_LT(src.reads.size(), 20u);
}

TEST(PipelineParams, ConfigFileThenOverridesNameTheirErrors) {
  const std::string path = tmpRoot() + "pipeline.yaml";
  std::ofstream(path) << "enhance: {mu_expected: 80}\nfeatures: {n_features: 600}\ntracker: {ba_window_size: 8}\n"
                         "other_tool: {anything: 1}\n";
  PipelineParams p;
  std::string err;
  ASSERT_TRUE(loadPipelineConfig(path, &p, &err)) << err;
  EXPECT_DOUBLE_EQ(p.enhance.mu_expected, 80.0);
  EXPECT_EQ(p.features.n_features, 600);
  EXPECT_EQ(p.tracker.ba_window_size, 8);
  ASSERT_TRUE(applyPipelineSetting("features.culling=false", &p, &err)) << err;
  EXPECT_FALSE(p.features.culling);
  ASSERT_TRUE(applyPipelineSetting("enhance.method=he", &p, &err)) << err;
  EXPECT_EQ(p.enhance.method, EnhanceMethod::kHe);
  EXPECT_FALSE(applyPipelineSetting("tracker.no_such=1", &p, &err));
  EXPECT_NE(err.find("no_such"), std::string::npos) << err;
  EXPECT_FALSE(applyPipelineSetting("camera.fx=1", &p, &err));
  EXPECT_NE(err.find("camera"), std::string::npos) << err;
  EXPECT_FALSE(applyPipelineSetting("ba_window_size=3", &p, &err));
  EXPECT_EQ(validate(p), "");
  p.tracker.ba_window_size = 1;
  EXPECT_NE(validate(p).find("ba_window_size"), std::string::npos);

  std::ofstream(path) << "tracker: {scale_factor: 1.2}\n";  // moved to the features (FeatureFrame)
  EXPECT_FALSE(loadPipelineConfig(path, &p, &err));
  EXPECT_NE(err.find(path), std::string::npos) << err;
  EXPECT_NE(err.find("scale_factor"), std::string::npos) << err;
  EXPECT_FALSE(loadPipelineConfig(tmpRoot() + "missing.yaml", &p, &err));
}

// Resolution rule (pipeline_params.h, docs/evaluation.md): the documented values for four cameras; fields
// given by a config file or a setting are kept.
TEST(PipelineParams, ResolutionRuleValuesAndUserSettings) {
  struct Case {
    int w, h;
    double f;
    int n_features, cell_size, n_levels;
    double radius, wide, refine;
    int min_matches, min_triangulated, parallax_points;
    double triangulation_parallax_deg;
  };
  const Case cases[] = {
      {752, 480, 458.654, 1000, 35, 8, 15.0, 40.0, 4.0, 100, 60, 50, 1.0},  // EuRoC: the struct defaults
      {1241, 376, 718.856, 1150, 40, 8, 23.51, 62.69, 6.27, 115, 69, 57, 1.0},
      {512, 512, 190.978, 850, 30, 8, 6.25, 16.66, 2.0, 85, 51, 43, 1.0},
      {240, 180, 200.0, 500, 30, 5, 6.54, 17.44, 2.0, 50, 30, 25, 1.0},
  };
  for (const Case& c : cases) {
    const ResolutionDefaults d = resolutionDefaults(c.w, c.h, c.f);
    SCOPED_TRACE(std::to_string(c.w) + "x" + std::to_string(c.h));
    EXPECT_EQ(d.n_features, c.n_features);
    EXPECT_EQ(d.cell_size, c.cell_size);
    EXPECT_EQ(d.n_levels, c.n_levels);
    EXPECT_NEAR(d.search_radius_px, c.radius, 0.01);
    EXPECT_NEAR(d.search_radius_wide_px, c.wide, 0.01);
    EXPECT_NEAR(d.search_radius_refine_px, c.refine, 0.01);
    EXPECT_EQ(d.init_min_matches, c.min_matches);
    EXPECT_EQ(d.init_min_triangulated, c.min_triangulated);
    EXPECT_EQ(d.init_min_parallax_points, c.parallax_points);
    EXPECT_NEAR(d.min_triangulation_parallax_deg, c.triangulation_parallax_deg, 0.001);
    PipelineParams p;
    applyResolutionRule(c.w, c.h, c.f, false, &p);
    EXPECT_NEAR(p.tracker.min_triangulation_parallax_deg, c.triangulation_parallax_deg, 0.001);
    EXPECT_EQ(p.features.n_features, c.n_features);
    EXPECT_EQ(p.features.cell_size, c.cell_size);
    EXPECT_EQ(validate(p), "");
  }
  // At EuRoC's size the rule reproduces the struct defaults.
  const ResolutionDefaults euroc = resolutionDefaults(752, 480, 458.654);
  EXPECT_EQ(euroc.n_features, FeatureParams().n_features);
  EXPECT_EQ(euroc.cell_size, FeatureParams().cell_size);
  EXPECT_EQ(euroc.n_levels, FeatureParams().n_levels);
  EXPECT_DOUBLE_EQ(euroc.search_radius_px, TrackerParams().search_radius_px);
  EXPECT_EQ(euroc.init_min_matches, TrackerParams().init_min_matches);
  EXPECT_EQ(euroc.init_min_triangulated, TrackerParams().init_min_triangulated);
  EXPECT_EQ(euroc.init_min_parallax_points, TrackerParams().init_min_parallax_points);
  EXPECT_EQ(euroc.min_triangulation_parallax_deg, TrackerParams().min_triangulation_parallax_deg);  // exactly
  // Fisheye: the triangulation parallax follows 1 / focal (TUM-VI f 191: 2.4 deg; a fisheye at EuRoC's focal: 1 deg).
  EXPECT_EQ(resolutionDefaults(512, 512, 190.978, 1.2, true).min_triangulation_parallax_deg, 2.4);
  EXPECT_EQ(resolutionDefaults(752, 480, 0.5 * (458.654 + 457.296), 1.2, true).min_triangulation_parallax_deg, 1.0);
  PipelineParams fisheye;
  applyResolutionRule(512, 512, 190.978, true, &fisheye);
  EXPECT_EQ(fisheye.tracker.min_triangulation_parallax_deg, 2.4);

  PipelineParams p;
  std::string err;
  ASSERT_TRUE(applyPipelineSetting("features.n_features=700", &p, &err)) << err;
  EXPECT_FALSE(applyPipelineSetting("tracker.no_such=1", &p, &err));
  EXPECT_EQ(p.user_set.count("tracker.no_such"), 0u);
  const std::string path = tmpRoot() + "rule.yaml";
  std::ofstream(path) << "tracker: {search_radius_px: 9}\n";
  ASSERT_TRUE(loadPipelineConfig(path, &p, &err)) << err;
  applyResolutionRule(240, 180, 200.0, false, &p);
  EXPECT_EQ(p.features.n_features, 700);          // --set
  EXPECT_DOUBLE_EQ(p.tracker.search_radius_px, 9.0);  // config file
  EXPECT_EQ(p.features.n_levels, 5);              // rule
  EXPECT_NEAR(p.tracker.search_radius_wide_px, 17.44, 0.01);
}

// ---- CommandLine (pipeline/command_line.h), the parser of every tool: option values, --config / --set, the
// deprecated forms, and the messages (each names the option, the parameter and the value).
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

std::string writeCliFile(const std::string& name, const std::string& text) {
  const std::string path = tmpRoot() + "cli_" + name;
  std::ofstream(path) << text;
  return path;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

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
  EXPECT_TRUE(contains(u.cli.error(), "'two'")) << u.cli.error();
  Tool v({});
  EXPECT_EQ(v.run({"in", "--bogus"}), 2);
  EXPECT_TRUE(contains(v.cli.error(), "--bogus")) << v.cli.error();
  Tool w({});
  EXPECT_EQ(w.run({"in", "--name"}), 2);
  EXPECT_TRUE(contains(w.cli.error(), "--name needs a value")) << w.cli.error();
  Tool x({});
  EXPECT_EQ(x.run({"--quiet"}), 2);
  EXPECT_EQ(x.cli.error(), "INPUT is required");
  Tool y({});
  EXPECT_EQ(y.run({"in", "extra"}), 2);
  EXPECT_TRUE(contains(y.cli.error(), "'extra'")) << y.cli.error();
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
  EXPECT_TRUE(contains(unused_section.cli.error(), "does not use tracker parameters")) << unused_section.cli.error();
  Tool bad_key({"features"});
  EXPECT_EQ(bad_key.run({"in", "--set", "features.n_featurez=500"}), 2);
  EXPECT_TRUE(contains(bad_key.cli.error(), "unknown features parameter 'n_featurez'")) << bad_key.cli.error();
  Tool bad_value({"features"});
  EXPECT_EQ(bad_value.run({"in", "--set", "features.n_features=many"}), 2);
  EXPECT_TRUE(contains(bad_value.cli.error(), "bad value 'many' for features parameter 'n_features'"))
      << bad_value.cli.error();
  Tool out_of_range({"features"});
  EXPECT_EQ(out_of_range.run({"in", "--set", "features.n_features=20"}), 2);
  EXPECT_EQ(out_of_range.cli.error(), "invalid features parameters: n_features must be in [50, 10000] (got 20)");
  Tool no_equals({"features"});
  EXPECT_EQ(no_equals.run({"in", "--set", "features.n_features"}), 2);
  EXPECT_TRUE(contains(no_equals.cli.error(), "expected section.key=value")) << no_equals.cli.error();
}

TEST(CommandLine, ConfigThenSetInOrder) {
  const std::string cfg = writeCliFile("ok.yaml", "features:\n  n_features: 600\n  cell_size: 40\nother: 1\n");
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
  const std::string bad = writeCliFile("bad.yaml", "features:\n  n_features: 20\n");
  Tool u({"features"});
  EXPECT_EQ(u.run({"in", "--config", bad}), 2);
  EXPECT_TRUE(contains(u.cli.error(), bad) && contains(u.cli.error(), "n_features must be in [50, 10000] (got 20)"))
      << u.cli.error();
}

TEST(CommandLine, DeprecatedFormsStillWorkWhereUnambiguous) {
  // --params = --config; a root-level map is the tool's legacy section.
  const std::string root_map = writeCliFile("root.yaml", "mu_expected: 50\n");
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
  EXPECT_TRUE(contains(v.cli.error(), "no features parameter is named 'eta'")) << v.cli.error();
}

TEST(CommandLine, HelpListsTheSettableParameters) {
  Tool t({"enhance", "features"});
  const std::string help = t.cli.usage();
  for (const char* name : {"--config FILE", "--set SECTION.KEY=VALUE", "enhance: method", "mu_expected", "n_features",
                           "eq23_literal"})
    EXPECT_TRUE(contains(help, name)) << name << " missing in:\n" << help;
  EXPECT_FALSE(contains(help, "ba_window_size")) << help;  // not a section of this tool
}
