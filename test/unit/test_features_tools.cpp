// Command-line contract of the feature tools: bad input -> non-zero exit; keypoint_curve writes its CSV.
// Runs the binaries from IRAF_VO_BIN_DIR (skips when they are not built).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "common/test_data.h"

namespace fs = std::filesystem;

namespace {

std::string tool(const std::string& name) { return std::string(IRAF_VO_BIN_DIR) + "/" + name; }

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST(FeatureTools, BenchRejectsBadInput) {
  const std::string bench = tool("iraf_vo_bench_frontend");
  if (!fs::exists(bench)) GTEST_SKIP() << bench << " not built";
  EXPECT_NE(run(bench), 0);
  EXPECT_NE(run(bench + " --dataset /nonexistent_iraf_dir"), 0);
  EXPECT_NE(run(bench + " --dataset /tmp --frames x"), 0);
  EXPECT_NE(run(bench + " --bogus"), 0);
}

TEST(FeatureTools, CullingTableRejectsBadInput) {
  const std::string table = tool("iraf_vo_culling_table");
  if (!fs::exists(table)) GTEST_SKIP() << table << " not built";
  EXPECT_NE(run(table), 0);
  EXPECT_NE(run(table + " --dataset /nonexistent_iraf_dir"), 0);
  EXPECT_NE(run(table + " --dataset /tmp --bins 0"), 0);
  EXPECT_NE(run(table + " --dataset /tmp --set features.s_min=abc"), 0);
  EXPECT_NE(run(table + " --dataset /tmp --set nosection"), 0);
  EXPECT_NE(run(table + " --bogus"), 0);
  EXPECT_EQ(run(table + " --help"), 0);
}

TEST(FeatureTools, KeypointCurveWritesCsv) {
  const std::string curve = tool("iraf_vo_keypoint_curve");
  if (!fs::exists(curve)) GTEST_SKIP() << curve << " not built";
  EXPECT_NE(run(curve + " --input /nonexistent_iraf_dir"), 0);
  EXPECT_NE(run(curve + " --min 30 --max 10"), 0);
  const fs::path dir = fs::temp_directory_path() / ("iraf_vo_curve_" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  EXPECT_NE(run(curve + " --input " + dir.string()), 0) << "no images must be an error";
  cv::imwrite((dir / "sub" / "a.png").string(), iraf_vo_test::texturedImage(200, 150));
  const fs::path csv = dir / "out.csv";
  ASSERT_EQ(run(curve + " --input " + dir.string() + " --output " + csv.string() + " --min 10 --max 30 --step 10"), 0);
  std::ifstream in(csv);
  std::string line;
  int rows = 0, adaptive = 0;
  std::getline(in, line);
  EXPECT_EQ(line, "image,variant,threshold,keypoints,global_threshold,cell_threshold_median");
  while (std::getline(in, line)) {
    ++rows;
    adaptive += line.find(",adaptive,") != std::string::npos;
    EXPECT_EQ(line.rfind("sub/a.png,", 0), 0u) << line;
  }
  EXPECT_EQ(rows, 2 * (3 + 1));  // original + enhanced, thresholds 10/20/30 + adaptive
  EXPECT_EQ(adaptive, 2);
  fs::remove_all(dir);
}
