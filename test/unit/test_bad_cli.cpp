// Bad input to the command-line tools: each run must exit non-zero, print a message naming the bad
// file on stderr, and not crash (no signal, no sanitizer report). Tools are taken from IRAF_VO_BIN_DIR (built by
// `make` / scripts/setup.sh before the tests run); a tool that is not built is skipped, not failed.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/tmp_dir.h"

namespace {

/// This binary's temp folder under tmpRoot() (common/tmp_dir.h removes it at exit).
std::string tmpDir() {
  static const std::string d = [] {
    const std::string p = tmpRoot() + "badcli";
    ::mkdir(p.c_str(), 0755);
    return p;
  }();
  return d;
}

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

std::string tool(const std::string& name) { return std::string(IRAF_VO_BIN_DIR) + "/" + name; }

#define REQUIRE_TOOL(name) \
  if (!exists(tool(name))) GTEST_SKIP() << "tool not built: " << tool(name)

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
  ASSERT_TRUE(f.good()) << path;
}

struct Run {
  int status = -1;     // exit code, or 128 + signal
  std::string err;     // stderr
};

/// Runs `args` (already shell-quoted where needed) with a time limit; stdout is discarded.
Run run(const std::string& args) {
  static int n = 0;
  const std::string err_file = tmpDir() + "/stderr_" + std::to_string(n++) + ".txt";
  const std::string cmd = "timeout 120 " + args + " > /dev/null 2> " + err_file;
  const int raw = std::system(cmd.c_str());
  Run r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  std::ifstream f(err_file);
  std::stringstream ss;
  ss << f.rdbuf();
  r.err = ss.str();
  return r;
}

/// Non-zero exit that is not a crash: 1..127 and not timeout's 124, no sanitizer report; stderr names `file`.
void expectCleanFailure(const Run& r, const std::string& file, const std::string& what) {
  EXPECT_NE(r.status, 0) << what << "\n" << r.err;
  EXPECT_LT(r.status, 124) << what << " crashed / timed out (status " << r.status << ")\n" << r.err;
  EXPECT_EQ(r.err.find("Sanitizer"), std::string::npos) << what << "\n" << r.err;
  EXPECT_EQ(r.err.find("runtime error"), std::string::npos) << what << "\n" << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << what << ": stderr does not name " << file << "\n" << r.err;
}

std::string pngBytes(int w, int h, int seed = 1) {
  cv::Mat img(h, w, CV_8UC1);
  cv::theRNG().state = seed;
  cv::randu(img, 0, 255);
  std::vector<uchar> buf;
  EXPECT_TRUE(cv::imencode(".png", img, buf));
  return std::string(buf.begin(), buf.end());
}

const char* kCamYaml =
    "camera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
    "distortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
    "resolution: [752, 480]\n";

/// ASL folder DIR/mav0/cam0 with n images of w x h (optionally truncated) and sensor.yaml (kCamYaml by default).
std::string makeAsl(const std::string& name, int n, int w, int h, bool truncated = false,
                    const std::string& yaml = kCamYaml) {
  const std::string root = tmpDir() + "/" + name, cam = root + "/mav0/cam0";
  for (const std::string& d : {root, root + "/mav0", cam, cam + "/data"}) ::mkdir(d.c_str(), 0755);
  std::ofstream csv(cam + "/data.csv");
  csv << "#timestamp [ns],filename\n";
  for (int i = 0; i < n; ++i) {
    const std::string stamp = std::to_string(1000000000LL + i * 50000000LL);
    std::string png = pngBytes(w, h, i + 1);
    if (truncated) png = png.substr(0, png.size() / 3);
    writeFile(cam + "/data/" + stamp + ".png", png);
    csv << stamp << "," << stamp << ".png\n";
  }
  writeFile(cam + "/sensor.yaml", yaml);
  return root;
}

std::string badFocalYaml(const std::string& focal) {
  std::string y = kCamYaml;
  y.replace(y.find("458.654"), 7, focal);
  return y;
}

}  // namespace

TEST(BadCli, Enhance) {
  REQUIRE_TOOL("iraf_vo_enhance");
  const std::string png = tmpDir() + "/enh_trunc.png", out = tmpDir() + "/enh_out";
  const std::string full = pngBytes(64, 48);
  writeFile(png, full.substr(0, full.size() / 2));
  expectCleanFailure(run(tool("iraf_vo_enhance") + " " + png + " " + out), png, "truncated png");
  const std::string missing = tmpDir() + "/enh_missing.png";
  expectCleanFailure(run(tool("iraf_vo_enhance") + " " + missing + " " + out), missing, "missing input");
  const std::string good = tmpDir() + "/enh_good.png", params = tmpDir() + "/enh_params.yaml";
  writeFile(good, full);
  writeFile(params, "gaussian_sigma: .nan\n");
  expectCleanFailure(run(tool("iraf_vo_enhance") + " " + good + " " + out + " --params " + params), params,
                     "NaN param");
  writeFile(params, "gaussian_sigma: [1, 2\n");
  expectCleanFailure(run(tool("iraf_vo_enhance") + " " + good + " " + out + " --params " + params), params,
                     "broken yaml");
  // Sanity: the good image is accepted (so the failures above are about the bad inputs).
  EXPECT_EQ(run(tool("iraf_vo_enhance") + " " + good + " " + out).status, 0);
}

TEST(BadCli, Eval) {
  REQUIRE_TOOL("iraf_vo_eval");
  const std::string good = tmpDir() + "/eval_good.txt", garbage = tmpDir() + "/eval_garbage.txt",
                    empty = tmpDir() + "/eval_empty.txt";
  writeFile(good, "1 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n3 2 0 0 0 0 0 1\n4 3 1 0 0 0 0 1\n");
  writeFile(garbage, "\x89PNG garbage\n1 2\nnan nan nan\n");
  writeFile(empty, "");
  expectCleanFailure(run(tool("iraf_vo_eval") + " " + good + " " + garbage), garbage, "garbage est");
  expectCleanFailure(run(tool("iraf_vo_eval") + " " + empty + " " + good), empty, "empty gt");
  const std::string missing = tmpDir() + "/eval_missing.txt";
  expectCleanFailure(run(tool("iraf_vo_eval") + " " + good + " " + missing), missing, "missing est");
  const std::string cam = tmpDir() + "/eval_cam.yaml";
  writeFile(cam, badFocalYaml(".nan"));
  expectCleanFailure(run(tool("iraf_vo_eval") + " " + good + " " + good + " --camera " + cam), cam, "NaN camera");
  EXPECT_EQ(run(tool("iraf_vo_eval") + " " + good + " " + good).status, 0);
}

TEST(BadCli, AslToBag) {
  REQUIRE_TOOL("iraf_vo_asl_to_bag");
  // data.csv missing
  const std::string root = makeAsl("bag_nocsv", 2, 64, 48);
  ::unlink((root + "/mav0/cam0/data.csv").c_str());
  expectCleanFailure(run(tool("iraf_vo_asl_to_bag") + " " + root + " " + tmpDir() + "/a.bag"), "data.csv",
                     "missing data.csv");
  // every image truncated
  const std::string trunc = makeAsl("bag_trunc", 3, 64, 48, true);
  expectCleanFailure(run(tool("iraf_vo_asl_to_bag") + " " + trunc + " " + tmpDir() + "/b.bag"), ".png",
                     "truncated images");
  // output in a folder that does not exist
  const std::string good = makeAsl("bag_good", 2, 64, 48);
  const std::string bad_out = tmpDir() + "/no/such/dir/c.bag";
  expectCleanFailure(run(tool("iraf_vo_asl_to_bag") + " " + good + " " + bad_out), bad_out, "unwritable bag");
}

TEST(BadCli, Run) {
  REQUIRE_TOOL("iraf_vo_run");
  const std::string out = tmpDir() + "/run_traj.txt";
  // camera yaml with NaN / negative focal length
  const std::string ds = makeAsl("run_ds", 3, 752, 480);
  for (const std::string& f : {std::string(".nan"), std::string("-458.654")}) {
    const std::string cam = tmpDir() + "/run_cam" + f + ".yaml";
    writeFile(cam, badFocalYaml(f));
    expectCleanFailure(run(tool("iraf_vo_run") + " --dataset " + ds + " --camera " + cam + " --out " + out + " --quiet"),
                       cam, "bad focal " + f);
  }
  // corrupt bag
  const std::string bag = tmpDir() + "/run_corrupt.bag";
  writeFile(bag, "#ROSBAG V2.0\n" + std::string(200, '\x07'));
  expectCleanFailure(run(tool("iraf_vo_run") + " --dataset " + bag + " --topic /cam0/image_raw --camera " + ds +
                         "/mav0/cam0/sensor.yaml --out " + out + " --quiet"),
                     bag, "corrupt bag");
  // missing data.csv rows: data.csv without any usable row
  const std::string empty_ds = makeAsl("run_empty", 0, 752, 480);
  expectCleanFailure(run(tool("iraf_vo_run") + " --dataset " + empty_ds + " --out " + out + " --quiet"), "data.csv",
                     "no rows");
  // images whose size does not match the camera (64x48 vs 752x480)
  const std::string small = makeAsl("run_small", 3, 64, 48);
  expectCleanFailure(run(tool("iraf_vo_run") + " --dataset " + small + " --out " + out + " --quiet"), ".png",
                     "image size != camera");
  // every image truncated
  const std::string trunc = makeAsl("run_trunc", 3, 752, 480, true);
  expectCleanFailure(run(tool("iraf_vo_run") + " --dataset " + trunc + " --out " + out + " --quiet"), ".png",
                     "truncated images");
}

TEST(BadCli, Simulate) {
  REQUIRE_TOOL("iraf_vo_simulate");
  for (const std::string& f : {std::string(".nan"), std::string("-458.654")}) {
    const std::string cam = tmpDir() + "/sim_cam" + f + ".yaml";
    writeFile(cam, badFocalYaml(f));
    expectCleanFailure(run(tool("iraf_vo_simulate") + " --preset clean --frames 2 --camera " + cam + " --out " +
                           tmpDir() + "/sim_out"),
                       cam, "bad focal " + f);
  }
}

TEST(BadCli, Degrade) {
  REQUIRE_TOOL("iraf_vo_degrade");
  const std::string root = makeAsl("deg_nocsv", 2, 64, 48);
  ::unlink((root + "/mav0/cam0/data.csv").c_str());
  expectCleanFailure(run(tool("iraf_vo_degrade") + " " + root + " " + tmpDir() + "/deg_out --profile dark"),
                     "data.csv", "missing data.csv");
  const std::string missing = tmpDir() + "/deg_missing";
  expectCleanFailure(run(tool("iraf_vo_degrade") + " " + missing + " " + tmpDir() + "/deg_out2 --profile dark"),
                     missing, "missing dataset");
}

// An ASL folder with a missing and a truncated PNG. iraf_vo_enhance and iraf_vo_run name each file with
// its data.csv line and print how many rows were skipped; enhance exits 1 (some input not processed), run exits 0
// (the frames are skipped, the run goes on; it fails only when no frame can be read).
TEST(BadCli, SkippedImagesAreReported) {
  const std::string root = makeAsl("skip", 5, 752, 480);
  const std::string data = root + "/mav0/cam0/data/";
  const std::string missing = std::to_string(1000000000LL + 2 * 50000000LL) + ".png";    // data.csv line 4
  const std::string truncated = std::to_string(1000000000LL + 3 * 50000000LL) + ".png";  // data.csv line 5
  ASSERT_EQ(::unlink((data + missing).c_str()), 0);
  writeFile(data + truncated, pngBytes(752, 480, 4).substr(0, 300));
  auto expectReported = [&](const auto& r, const std::string& what) {
    EXPECT_NE(r.err.find("data.csv:4: image file missing: " + data + missing), std::string::npos) << what << "\n" << r.err;
    EXPECT_NE(r.err.find("data.csv:5: " + data + truncated + ": unreadable image"), std::string::npos) << what << "\n" << r.err;
    EXPECT_NE(r.err.find("2 of 5 rows of " + root + "/mav0/cam0/data.csv skipped: 1 image file missing, 1 unreadable"),
              std::string::npos)
        << what << "\n" << r.err;
    EXPECT_LT(r.status, 124) << what << " crashed\n" << r.err;
  };
  if (exists(tool("iraf_vo_enhance"))) {
    const auto r = run(tool("iraf_vo_enhance") + " " + root + " --no-write");
    expectReported(r, "iraf_vo_enhance");
    EXPECT_EQ(r.status, 1) << r.err;
  }
  if (exists(tool("iraf_vo_run"))) {
    const auto r = run(tool("iraf_vo_run") + " --dataset " + root + " --out " + tmpDir() + "/skip_traj.txt --quiet");
    expectReported(r, "iraf_vo_run");
    EXPECT_EQ(r.status, 0) << r.err;
  }
}
