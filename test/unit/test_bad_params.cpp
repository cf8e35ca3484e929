// Bad parameters and stage input to the core APIs: empty / wrong-type images and invalid or extreme parameter
// structs for the enhancer, the feature extractor and the tracker, and malformed parameter yaml. Every case must
// give a clear error naming the field and never crash or throw anything but the documented std::invalid_argument.
// The reproducers of crashes found by the fuzzers (scripts/fuzz.sh) are regression tests here too.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/test_data.h"
#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/enhance/enhance_params.h"
#include "iraf_vo/enhance/enhancer.h"
#include "iraf_vo/features/feature_extractor.h"
#include "iraf_vo/tracking/tracker.h"
#include "iraf_vo/tracking/tracker_params.h"

using namespace iraf_vo;

// ---------------------------------------------------------------- stages
TEST(BadStageInput, EnhancerRejectsEmptyWrongTypeAndInvalidParams) {
  Enhancer e;
  EnhanceParams p;
  EXPECT_THROW(e.enhance(cv::Mat(), p), std::invalid_argument);
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_8UC3, cv::Scalar(1, 2, 3)), p), std::invalid_argument);
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_16UC1, cv::Scalar(1)), p), std::invalid_argument);
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_32FC1, cv::Scalar(0.5)), p), std::invalid_argument);
  EnhanceParams bad = p;
  bad.gaussian_sigma = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(validate(bad).empty());
  EXPECT_THROW(e.enhance(cv::Mat(10, 10, CV_8UC1, cv::Scalar(1)), bad), std::invalid_argument);
  // Tiny images are fine.
  EXPECT_NO_THROW(e.enhance(cv::Mat(1, 1, CV_8UC1, cv::Scalar(7)), p));
}

TEST(BadStageInput, FeatureExtractorRejectsEmptyWrongTypeAndInvalidParams) {
  FeatureExtractor fx;
  FeatureParams p;
  EXPECT_THROW(fx.extract(cv::Mat(), 0.0, p), std::invalid_argument);
  EXPECT_THROW(fx.extract(cv::Mat(40, 40, CV_8UC3, cv::Scalar(1, 2, 3)), 0.0, p), std::invalid_argument);
  FeatureParams bad = p;
  bad.scale_factor = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fx.extract(cv::Mat(40, 40, CV_8UC1, cv::Scalar(1)), 0.0, bad), std::invalid_argument);
  // Images smaller than the FAST/ORB borders give no keypoints, not a crash.
  for (int s : {1, 2, 7, 31, 40}) {
    FeatureFrame f;
    EXPECT_NO_THROW(f = fx.extract(cv::Mat(s, s + 3, CV_8UC1, cv::Scalar(100)), 0.0, p)) << s;
    EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
  }
}

// Found by fuzz_frontend: clahe_tiles = 2^30 passed validate() and made cv::createCLAHE allocate ~16 PB
// (ASan allocation-size-too-big; a std::bad_alloc / OOM kill in a plain build). validate() now bounds every
// field that sizes an allocation or is converted to float.
TEST(BadStageInput, EnhanceParamsOutOfRangeAreRejectedByValidate) {
  Enhancer e;
  const cv::Mat img(20, 30, CV_8UC1, cv::Scalar(40));
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::pair<std::string, EnhanceParams>> bad;
  EnhanceParams p;
  p.method = EnhanceMethod::kClahe;
  p.clahe_tiles = 1 << 30;
  bad.emplace_back("clahe_tiles", p);
  p = EnhanceParams();
  p.gaussian_kernel_size = 2147483647;
  bad.emplace_back("gaussian_kernel_size", p);
  p = EnhanceParams();
  p.gaussian_sigma = inf;
  bad.emplace_back("gaussian_sigma", p);
  p = EnhanceParams();
  p.eta = 1e300;  // float(1e300) is undefined behaviour in the eq. (12) weights
  bad.emplace_back("eta", p);
  p = EnhanceParams();
  p.clahe_clip_limit = inf;
  bad.emplace_back("clahe_clip_limit", p);
  p = EnhanceParams();
  p.dim_lambda = inf;
  bad.emplace_back("lambda", p);
  p = EnhanceParams();
  p.mu_expected = inf;
  bad.emplace_back("mu_expected", p);
  for (const auto& [field, q] : bad) {
    EXPECT_NE(validate(q).find(field), std::string::npos) << field << ": '" << validate(q) << "'";
    EXPECT_THROW(e.enhance(img, q), std::invalid_argument) << field;
  }
  // The largest values in cfg/Enhance.cfg's ranges stay valid and run.
  p = EnhanceParams();
  p.gaussian_kernel_size = 15;
  p.gaussian_sigma = 5.0;
  p.clahe_tiles = 32;
  p.clahe_clip_limit = 40.0;
  p.eta = 5.0;
  p.epsilon = 3.0;
  EXPECT_EQ(validate(p), "");
  for (EnhanceMethod m : {EnhanceMethod::kIraf, EnhanceMethod::kClahe}) {
    p.method = m;
    EXPECT_NO_THROW(e.enhance(img, p));
  }
}

// Extreme but valid() feature params (each field at either end of its table range, then all at the top) on a
// textured image: no crash, no throw, no sanitizer report (run under ASan + UBSan by scripts/test.sh in CI).
TEST(BadStageInput, FeatureExtractorExtremeValidParams) {
  const cv::Mat img = iraf_vo_test::texturedImage(160, 120);
  FeatureExtractor fx;
  const ParamTable<FeatureParams>& table = featureParamTable();
  std::vector<std::pair<std::string, FeatureParams>> cases;
  FeatureParams top;
  for (const auto& e : table.entries()) {
    for (const bool max : {false, true}) {
      FeatureParams p;
      if (e.type == ParamType::kInt) p.*(e.int_field) = static_cast<int>(max ? e.max : e.min);
      else if (e.type == ParamType::kDouble) p.*(e.double_field) = max ? e.max : e.min;
      else continue;
      cases.emplace_back(e.name + (max ? " max" : " min"), p);
    }
    if (e.type == ParamType::kInt) top.*(e.int_field) = static_cast<int>(e.max);
    if (e.type == ParamType::kDouble) top.*(e.double_field) = e.max;
  }
  cases.emplace_back("all at max", top);
  for (const auto& [name, q] : cases) {
    SCOPED_TRACE(name);
    ASSERT_EQ(validate(q), "");  // the ends of every range are valid
    FeatureFrame f;
    EXPECT_NO_THROW(f = fx.extract(img, 0.0, q));
    EXPECT_EQ(f.descriptors.rows, static_cast<int>(f.keypoints.size()));
    for (const cv::KeyPoint& k : f.keypoints) {
      EXPECT_TRUE(k.pt.x >= 0 && k.pt.y >= 0 && k.pt.x < img.cols && k.pt.y < img.rows) << k.pt;
    }
  }
  // n_features = INT_MAX used to pass validate() and throw std::length_error from vector::reserve(4 * n)
  // (signed overflow first): now outside its range.
  FeatureParams huge;
  huge.n_features = std::numeric_limits<int>::max();
  EXPECT_NE(validate(huge).find("n_features"), std::string::npos);
  EXPECT_THROW(fx.extract(img, 0.0, huge), std::invalid_argument);
}

// TrackerParams: fields with only a lower bound accepted +inf (validate() said ""), which then reached int
// casts in the tracker (search radius / cell size -> grid index). Now rejected, naming the field.
TEST(BadStageInput, TrackerParamsRejectInfinity) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validate(TrackerParams()), "");
  for (double TrackerParams::*f : {&TrackerParams::search_radius_px, &TrackerParams::search_radius_wide_px,
                                   &TrackerParams::search_radius_refine_px, &TrackerParams::pnp_threshold_px,
                                   &TrackerParams::init_threshold_px, &TrackerParams::ba_huber_delta,
                                   &TrackerParams::ba_max_solver_time_in_seconds}) {
    TrackerParams p;
    p.*f = inf;
    if (f == &TrackerParams::search_radius_px) p.search_radius_wide_px = inf;
    EXPECT_FALSE(validate(p).empty());
    std::string err;
    auto cam = makeCamera("pinhole-radtan", 640, 480, {400, 400, 320, 240, 0, 0, 0, 0}, &err);
    ASSERT_TRUE(cam) << err;
    EXPECT_THROW(Tracker(cam, p), std::invalid_argument);
  }
}

// Found by fuzz_params_yaml: a params map with a non-scalar key ("? ? 4", a map as key) made
// trackerParamTable().load (and the other tables, same code) throw YAML::TypedBadConversion instead of returning false.
TEST(BadParamsYaml, NonScalarKeyIsAnErrorNotAnException) {
  const YAML::Node node = YAML::Load("? ? 4");
  ASSERT_TRUE(node.IsMap());
  std::string err;
  TrackerParams tp;
  bool ok = true;
  EXPECT_NO_THROW(ok = trackerParamTable().load(node, &tp, &err));
  EXPECT_FALSE(ok);
  EXPECT_FALSE(err.empty());
  EnhanceParams ep;
  err.clear();
  ok = true;
  EXPECT_NO_THROW(ok = enhanceParamTable().load(node, &ep, &err));
  EXPECT_FALSE(ok);
  EXPECT_FALSE(err.empty());
  FeatureParams fp;
  err.clear();
  ok = true;
  EXPECT_NO_THROW(ok = featureParamTable().load(node, &fp, &err));
  EXPECT_FALSE(ok);
}
