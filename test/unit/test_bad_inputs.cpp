// Bad input files to the core APIs: truncated / empty images, broken data.csv, bad trajectory files, camera yaml
// with NaN or negative focal length (bad parameters and stage input: test_bad_params). Every case must give a
// clear error naming the file (or the field) and never crash or throw.
// The reproducers of crashes found by the fuzzers (scripts/fuzz.sh) are regression tests here too.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/trajectory.h"

#include "common/tmp_dir.h"

using namespace iraf_vo;

namespace {

/// This binary's temp folder under tmpRoot() (common/tmp_dir.h removes it at exit).
std::string tmpDir() {
  static const std::string d = [] {
    const std::string p = tmpRoot() + "bad";
    ::mkdir(p.c_str(), 0755);
    return p;
  }();
  return d;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
  ASSERT_TRUE(f.good()) << path;
}

std::string pngBytes(int w = 64, int h = 48) {
  cv::Mat img(h, w, CV_8UC1);
  cv::randu(img, 0, 255);
  std::vector<uchar> buf;
  EXPECT_TRUE(cv::imencode(".png", img, buf));
  return std::string(buf.begin(), buf.end());
}

/// DIR/mav0/cam0/{data.csv, data/}; returns the cam0 folder.
std::string makeAsl(const std::string& name, const std::string& csv) {
  const std::string root = tmpDir() + "/" + name;
  for (const std::string& d : {root, root + "/mav0", root + "/mav0/cam0", root + "/mav0/cam0/data"})
    ::mkdir(d.c_str(), 0755);
  writeFile(root + "/mav0/cam0/data.csv", csv);
  return root + "/mav0/cam0";
}

const char* kEurocYaml =
    "camera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
    "distortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n"
    "resolution: [752, 480]\n";

}  // namespace

// ---------------------------------------------------------------- images
TEST(BadImages, TruncatedPngNamesTheFile) {
  const std::string png = pngBytes();
  const std::string path = tmpDir() + "/truncated.png";
  writeFile(path, png.substr(0, png.size() / 2));
  cv::Mat gray;
  std::string err;
  EXPECT_FALSE(readMono8(path, &gray, &err));
  EXPECT_NE(err.find(path), std::string::npos) << err;
  // Sanity: the untruncated bytes do load (so the test can fail for the right reason).
  const std::string good = tmpDir() + "/good.png";
  writeFile(good, png);
  ASSERT_TRUE(readMono8(good, &gray, &err)) << err;
  EXPECT_EQ(gray.cols, 64);
}

TEST(BadImages, EmptyGarbageAndMissingFiles) {
  cv::Mat gray;
  std::string err;
  const std::string empty = tmpDir() + "/empty.png", garbage = tmpDir() + "/garbage.png";
  writeFile(empty, "");
  writeFile(garbage, std::string("\x89PNG\r\n\x1a\n", 8) + "garbage garbage garbage");
  for (const std::string& p : {empty, garbage, tmpDir() + "/missing.png", tmpDir()}) {
    err.clear();
    EXPECT_FALSE(readMono8(p, &gray, &err)) << p;
    EXPECT_NE(err.find(p), std::string::npos) << err;
  }
}

TEST(BadImages, AslReaderSkipsTruncatedImageAndReportsIt) {
  const std::string cam = makeAsl("asl_trunc", "#timestamp [ns],filename\n100,a.png\n200,b.png\n");
  const std::string png = pngBytes();
  writeFile(cam + "/data/a.png", png);
  writeFile(cam + "/data/b.png", png.substr(0, 40));
  AslImageReader r;
  std::string err;
  ASSERT_TRUE(r.open(cam, &err)) << err;
  ASSERT_EQ(r.size(), 2u);
  cv::Mat gray;
  EXPECT_TRUE(r.loadImage(0, &gray, &err)) << err;
  EXPECT_FALSE(r.loadImage(1, &gray, &err));
  EXPECT_NE(err.find(cam + "/data/b.png"), std::string::npos) << err;
  EXPECT_FALSE(r.loadImage(2, &gray, &err));  // out of range: an error, not a crash
  // Sequential reading skips b.png with a warning naming it.
  r.rewind();
  ImageEntry e;
  int n = 0;
  while (r.next(&e, &gray)) ++n;
  EXPECT_EQ(n, 1);
  bool named = false;
  for (const std::string& w : r.warnings()) named |= w.find("b.png") != std::string::npos;
  EXPECT_TRUE(named);
}

// ---------------------------------------------------------------- data.csv
TEST(BadDataCsv, MissingCsvNamesIt) {
  const std::string root = tmpDir() + "/no_csv/mav0/cam0";
  std::system(("mkdir -p " + root).c_str());
  AslImageReader r;
  std::string err;
  EXPECT_FALSE(r.open(root, &err));
  EXPECT_NE(err.find("data.csv"), std::string::npos) << err;
  EXPECT_FALSE(r.open(tmpDir() + "/does_not_exist", &err));
  EXPECT_FALSE(err.empty());
}

TEST(BadDataCsv, RowsWithMissingImagesAreReportedAndSkipped) {
  const std::string cam = makeAsl("asl_missing", "#timestamp [ns],filename\n100,a.png\n200,gone.png\nnot a row\n");
  writeFile(cam + "/data/a.png", pngBytes());
  AslImageReader r;
  std::string err;
  ASSERT_TRUE(r.open(cam, &err)) << err;
  EXPECT_EQ(r.size(), 1u);
  std::string all;
  for (const std::string& w : r.warnings()) all += w + "\n";
  EXPECT_NE(all.find("gone.png"), std::string::npos) << all;
  EXPECT_NE(all.find("data.csv:4"), std::string::npos) << all;  // malformed row with its line number
}

TEST(BadDataCsv, NoUsableRowIsAnErrorNamingTheCsv) {
  const std::string cam = makeAsl("asl_none", "#timestamp [ns],filename\n100,gone.png\n");
  AslImageReader r;
  std::string err;
  EXPECT_FALSE(r.open(cam, &err));
  EXPECT_NE(err.find(cam + "/data.csv"), std::string::npos) << err;
}

// Found by fuzz_asl_csv: a 19-digit stamp above INT64_MAX made std::stoll throw std::out_of_range.
TEST(BadDataCsv, TimestampOverflowIsAMalformedRowNotAnException) {
  const std::string cam = makeAsl("asl_overflow", "9999999999999999999,a.png\n100,a.png\n");
  writeFile(cam + "/data/a.png", pngBytes());
  AslImageReader r;
  std::string err;
  bool ok = false;
  EXPECT_NO_THROW(ok = r.open(cam, &err));
  ASSERT_TRUE(ok) << err;
  EXPECT_EQ(r.size(), 1u);
  EXPECT_EQ(r.entries()[0].stamp_ns, 100);
  ASSERT_FALSE(r.warnings().empty());
  EXPECT_NE(r.warnings()[0].find("data.csv:1"), std::string::npos) << r.warnings()[0];
}

// ---------------------------------------------------------------- trajectories
TEST(BadTrajectory, MissingEmptyAndGarbageFilesNameTheFile) {
  const std::string empty = tmpDir() + "/empty.txt", garbage = tmpDir() + "/garbage.txt";
  writeFile(empty, "");
  writeFile(garbage, "hello world\n1 2 3\n\x01\x02\x03\n");
  for (const std::string& p : {empty, garbage, tmpDir() + "/missing.txt"}) {
    Trajectory t;
    std::string err;
    EXPECT_FALSE(readTumTrajectory(p, &t, &err)) << p;
    EXPECT_NE(err.find(p), std::string::npos) << err;
    err.clear();
    EXPECT_FALSE(readEurocGroundTruth(p, &t, &err)) << p;
    EXPECT_NE(err.find(p), std::string::npos) << err;
  }
}

TEST(BadTrajectory, NanAndZeroQuaternionRowsAreSkippedWithLineNumbers) {
  const std::string p = tmpDir() + "/nan.txt";
  writeFile(p, "1 0 0 0 0 0 0 1\n2 nan 0 0 0 0 0 1\n3 0 0 0 0 0 0 0\n4 1 0 0 0 0 0 1\n");
  Trajectory t;
  std::string err;
  std::vector<std::string> warnings;
  ASSERT_TRUE(readTumTrajectory(p, &t, &err, &warnings)) << err;
  EXPECT_EQ(t.size(), 2u);
  EXPECT_EQ(warnings.size(), 2u);
  for (const std::string& w : warnings) EXPECT_NE(w.find(p), std::string::npos) << w;
}

// Found by fuzz_trajectory: an all-digit stamp above INT64_MAX made std::stoll throw std::out_of_range.
TEST(BadTrajectory, StampOverflowIsSkippedNotThrown) {
  const std::string tum = tmpDir() + "/overflow.txt", csv = tmpDir() + "/overflow.csv";
  writeFile(tum, "9999999999999999999 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n");
  writeFile(csv, "9999999999999999999,0,0,0,1,0,0,0\n1000000000,0,0,0,1,0,0,0\n");
  Trajectory t;
  std::string err;
  bool ok = false;
  EXPECT_NO_THROW(ok = readTumTrajectory(tum, &t, &err));
  EXPECT_TRUE(ok) << err;
  EXPECT_EQ(t.size(), 1u);
  EXPECT_NO_THROW(ok = readEurocGroundTruth(csv, &t, &err));
  EXPECT_TRUE(ok) << err;
  EXPECT_EQ(t.size(), 1u);
}

// ---------------------------------------------------------------- camera yaml
TEST(BadCamera, NanNegativeAndZeroValuesNameFileAndKey) {
  struct Case {
    std::string from, to, key;
  };
  const std::vector<Case> cases = {
      {"458.654, 457.296", "nan, 457.296", "intrinsics"},
      {"458.654, 457.296", "-458.654, 457.296", "intrinsics"},
      {"458.654, 457.296", "458.654, 0", "intrinsics"},
      {"458.654, 457.296", "458.654, .inf", "intrinsics"},
      {"-0.28340811", ".nan", "distortion_coefficients"},
      {"[752, 480]", "[752, -480]", "resolution"},
      {"[752, 480]", "[0, 480]", "resolution"},
  };
  std::string err;
  const std::string good = tmpDir() + "/good_cam.yaml";
  writeFile(good, kEurocYaml);
  ASSERT_TRUE(loadCamera(good, &err)) << err;  // the unmodified file loads
  int i = 0;
  for (const Case& c : cases) {
    std::string text = kEurocYaml;
    const size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, c.from.size(), c.to);
    const std::string path = tmpDir() + "/bad_cam_" + std::to_string(i++) + ".yaml";
    writeFile(path, text);
    err.clear();
    EXPECT_FALSE(loadCamera(path, &err)) << c.to;
    EXPECT_NE(err.find(path), std::string::npos) << err;
    EXPECT_NE(err.find(c.key), std::string::npos) << err;
  }
}

TEST(BadCamera, TruncatedMissingAndNonYamlFiles) {
  const std::string trunc = tmpDir() + "/trunc_cam.yaml", bin = tmpDir() + "/bin_cam.yaml";
  writeFile(trunc, std::string(kEurocYaml).substr(0, 60));
  writeFile(bin, std::string("\x00\x01\x02[{{: :", 10));
  for (const std::string& p : {trunc, bin, tmpDir() + "/missing_cam.yaml"}) {
    std::string err;
    EXPECT_FALSE(loadCamera(p, &err)) << p;
    EXPECT_NE(err.find(p), std::string::npos) << err;
  }
}

TEST(BadCamera, FactoryRejectsNanAndNegativeFocal) {
  std::string err;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(makeCamera("pinhole-radtan", 752, 480, {nan, 450, 370, 250, 0, 0, 0, 0}, &err));
  EXPECT_FALSE(err.empty());
  EXPECT_FALSE(makeCamera("pinhole-radtan", 752, 480, {-450, 450, 370, 250, 0, 0, 0, 0}, &err));
  EXPECT_FALSE(makeCamera("kannala-brandt", 512, 512, {190, 190, 256, 256, 0, 0, 0}, &err));  // 7 params
  EXPECT_TRUE(makeCamera("pinhole-radtan", 752, 480, {450, 450, 370, 250, 0, 0, 0, 0}, &err)) << err;
}

// Found by fuzz_camera_yaml (clang UBSan float-cast-overflow): resolution [5.7e19, 512] was cast to int before
// the range check. Also rows * cols of a camera_info matrix with huge rows / cols overflowed int.
// (Undefined behaviour only shows under UBSan: scripts/test.sh runs this test in build-asan/ in CI.)
TEST(BadCamera, HugeResolutionAndMatrixSizeAreErrors) {
  std::string text = kEurocYaml;
  text.replace(text.find("[752, 480]"), 10, "[56666666666666666612, 512]");
  std::string err;
  EXPECT_FALSE(loadCameraFromString(text, "huge.yaml", &err));
  EXPECT_NE(err.find("resolution"), std::string::npos) << err;
  EXPECT_NE(err.find("huge.yaml"), std::string::npos) << err;
  const std::string info =
      "image_width: 640\nimage_height: 480\n"
      "camera_matrix: {rows: 3, cols: 3, data: [500, 0, 320, 0, 500, 240, 0, 0, 1]}\n"
      "distortion_model: plumb_bob\n"
      "distortion_coefficients: {rows: 100000, cols: 100000, data: [0, 0, 0, 0, 0]}\n";
  err.clear();
  EXPECT_FALSE(loadCameraFromString(info, "info.yaml", &err));
  EXPECT_NE(err.find("distortion_coefficients"), std::string::npos) << err;
}

// Found by fuzz_camera_yaml: intrinsics [916.654, 457E296, ...] (fy = 4.57e298) loaded and project() returned
// true with non-finite pixels. makeCamera/loadCamera now bound the magnitudes (|f|, |c| <= 1e7 px, |k| <= 1e6).
TEST(BadCamera, AbsurdMagnitudesAreRejected) {
  std::string text = kEurocYaml;
  text.replace(text.find("457.296"), 7, "457E296");
  std::string err;
  EXPECT_FALSE(loadCameraFromString(text, "absurd.yaml", &err));
  EXPECT_NE(err.find("fy"), std::string::npos) << err;
  EXPECT_NE(err.find("absurd.yaml"), std::string::npos) << err;
  EXPECT_FALSE(makeCamera("kannala-brandt", 512, 512, {190, 190, 256, 256, 1e300, 0, 0, 0}, &err));
  EXPECT_NE(err.find("k1"), std::string::npos) << err;
  // A large but real focal length (telephoto, 20000 px) is still fine.
  EXPECT_TRUE(makeCamera("pinhole-radtan", 752, 480, {20000, 20000, 376, 240, 0, 0, 0, 0}, &err)) << err;
}
