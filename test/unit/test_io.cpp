// ASL image folder reader, trajectory readers (TUM / EuRoC) and the TUM writer.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>

#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sys/stat.h>

#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/common/shared_library.h"
#include "iraf_vo/io/image_codecs.h"
#include "iraf_vo/io/image_folder.h"
#include "iraf_vo/io/trajectory.h"

using namespace iraf_vo;

#include "common/tmp_dir.h"

namespace {

std::string tmpDir(const std::string& name) {
  const std::string d = tmpRoot() + "iraf_vo_io_" + name;
  std::system(("rm -rf '" + d + "' && mkdir -p '" + d + "'").c_str());
  return d;
}
void writeFile(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
}
bool contains(const std::vector<std::string>& v, const std::string& needle) {
  for (const auto& s : v)
    if (s.find(needle) != std::string::npos) return true;
  return false;
}
std::string sharedData(const std::string& rel) {
  const std::string p = std::string(IRAF_VO_SHARED_DIR) + "/data/" + rel;
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 ? p : std::string();
}

/// Temp ASL folder: gray 8-bit, colour, 16-bit images, a missing file, a corrupt file, malformed rows.
std::string makeAslFolder() {
  const std::string root = tmpDir("asl");
  const std::string cam = root + "/mav0/cam0";
  std::system(("mkdir -p '" + cam + "/data'").c_str());
  cv::Mat g(20, 30, CV_8UC1);
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) g.at<uchar>(r, c) = static_cast<uchar>(r * 7 + c);
  cv::imwrite(cam + "/data/1000000000.png", g);
  cv::Mat colour(20, 30, CV_8UC3, cv::Scalar(10, 200, 30));
  cv::imwrite(cam + "/data/1050000000.png", colour);
  cv::Mat g16(20, 30, CV_16UC1, cv::Scalar(256 * 77 + 12));
  cv::imwrite(cam + "/data/1100000000.png", g16);
  writeFile(cam + "/data/1200000000.png", "this is not a png");
  writeFile(cam + "/data.csv",
            "#timestamp [ns],filename\n"
            "1000000000,1000000000.png\n"
            "1100000000,1100000000.png\r\n"   // CRLF + out of order
            "1050000000, 1050000000.png\n"
            "not_a_number,foo.png\n"          // line 5: malformed
            "1150000000,1150000000.png\n"     // line 6: missing file
            "1200000000,1200000000.png\n"     // corrupt file
            "1250000000\n");                  // line 8: malformed
  writeFile(cam + "/sensor.yaml",
            "%YAML:1.0\ncamera_model: pinhole\nintrinsics: [100, 100, 15, 10]\nresolution: [30, 20]\n"
            "distortion_model: radial-tangential\ndistortion_coefficients: [0, 0, 0, 0]\n");
  return root;
}

}  // namespace

TEST(AslImageReader, ReadsFolderReportsProblemsAndConverts) {
  const std::string root = makeAslFolder();
  for (const std::string& dir : {root, root + "/mav0", root + "/mav0/cam0/"}) {
    AslImageReader reader;
    std::string err;
    ASSERT_TRUE(reader.open(dir, &err)) << dir << ": " << err;
    ASSERT_EQ(reader.size(), 4u) << dir;  // 3 good + the corrupt one (detected at load time)
    EXPECT_EQ(reader.entries()[0].stamp_ns, 1000000000);
    EXPECT_EQ(reader.entries()[1].stamp_ns, 1050000000);  // sorted
    EXPECT_DOUBLE_EQ(reader.entries()[2].stamp(), 1.1);
    EXPECT_EQ(reader.rootDir(), root);
    EXPECT_TRUE(contains(reader.warnings(), "data.csv:5: malformed row")) << dir;
    EXPECT_TRUE(contains(reader.warnings(), "data.csv:8: malformed row")) << dir;
    EXPECT_TRUE(contains(reader.warnings(), "data.csv:6: image file missing: " + root + "/mav0/cam0/data/1150000000.png"));
  }
  AslImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(root, &err)) << err;
  cv::Mat img;
  ASSERT_TRUE(reader.loadImage(0, &img, &err)) << err;
  EXPECT_EQ(img.type(), CV_8UC1);
  EXPECT_EQ(img.at<uchar>(2, 3), 2 * 7 + 3);
  ASSERT_TRUE(reader.loadImage(1, &img, &err)) << err;  // colour -> gray
  EXPECT_EQ(img.type(), CV_8UC1);
  EXPECT_NEAR(img.at<uchar>(5, 5), 0.114 * 10 + 0.587 * 200 + 0.299 * 30, 1.0);
  ASSERT_TRUE(reader.loadImage(2, &img, &err)) << err;  // 16 bit -> 8 bit
  EXPECT_EQ(img.type(), CV_8UC1);
  EXPECT_EQ(img.at<uchar>(0, 0), 77);
  EXPECT_EQ(reader.missingCount(), 1u);
  EXPECT_EQ(reader.badRowCount(), 2u);
  EXPECT_FALSE(reader.loadImage(3, &img, &err));
  EXPECT_NE(err.find("1200000000.png"), std::string::npos) << err;
  EXPECT_NE(err.find("data.csv:7: "), std::string::npos) << err;  // the data.csv line of the corrupt file
  EXPECT_EQ(reader.unreadableCount(), 1u);
  EXPECT_FALSE(reader.loadImage(99, &img, &err));

  // Sequential iteration skips the corrupt image and reports it.
  ImageEntry e;
  int n = 0;
  while (reader.next(&e, &img)) ++n;
  EXPECT_EQ(n, 3);
  EXPECT_TRUE(contains(reader.warnings(), "data.csv:7: " + root + "/mav0/cam0/data/1200000000.png: unreadable image"));
  // Summary over the 7 data rows: 1 missing, 1 unreadable (counted once: loadImage(3) above and next()), 2 malformed.
  EXPECT_EQ(reader.unreadableCount(), 1u);
  EXPECT_EQ(reader.skippedSummary(), "4 of 7 rows of " + root + "/mav0/cam0/data.csv skipped: 1 image file missing, "
                                     "1 unreadable, 2 malformed / duplicate rows");

  CameraModelPtr cam = reader.loadCamera(&err);
  ASSERT_TRUE(cam) << err;
  EXPECT_EQ(cam->width(), 30);
}

TEST(AslImageWriter, WriteThenRead) {
  const std::string root = tmpDir("writer");
  const auto cam = makeCamera("kannala-brandt", 40, 30, {20, 21, 19.5, 14.5, 0.01, 0.001, -0.002, 0.0002}, nullptr);
  ASSERT_TRUE(cam);
  AslImageWriter w;
  std::string err;
  ASSERT_TRUE(w.open(root, &err, cam.get())) << err;
  std::vector<cv::Mat> imgs;
  cv::theRNG().state = 5;
  for (int k = 0; k < 3; ++k) {
    cv::Mat img(30, 40, CV_8UC1);
    cv::randu(img, cv::Scalar(0), cv::Scalar(256));
    imgs.push_back(img);
    ASSERT_TRUE(w.write(1000000000LL + k * 50000000LL, img, &err)) << err;
  }
  EXPECT_FALSE(w.write(1000000000LL, imgs[0], &err));  // not increasing
  EXPECT_NE(err.find("not after"), std::string::npos) << err;
  EXPECT_FALSE(w.write(2000000000LL, cv::Mat(), &err));
  EXPECT_FALSE(w.write(2000000000LL, cv::Mat(3, 3, CV_32FC1), &err));
  w.close();
  EXPECT_EQ(w.count(), 3u);
  AslImageReader r;
  ASSERT_TRUE(r.open(root, &err)) << err;
  ASSERT_EQ(r.size(), 3u);
  EXPECT_TRUE(r.warnings().empty());
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(r.entries()[k].stamp_ns, 1000000000LL + static_cast<int64_t>(k) * 50000000LL);
    cv::Mat g;
    ASSERT_TRUE(r.loadImage(k, &g, &err)) << err;
    EXPECT_EQ(cv::norm(g, imgs[k], cv::NORM_INF), 0.0);
  }
  CameraModelPtr c2 = r.loadCamera(&err);
  ASSERT_TRUE(c2) << err;
  EXPECT_EQ(c2->modelName(), "kannala-brandt");
  EXPECT_EQ(c2->parameters(), cam->parameters());
  AslImageWriter bad;
  EXPECT_FALSE(bad.open("/proc/iraf_vo_cannot_write", &err));
  EXPECT_NE(err.find("/proc/iraf_vo_cannot_write"), std::string::npos) << err;
}

TEST(AslImageReader, BadFolders) {
  AslImageReader reader;
  std::string err;
  EXPECT_FALSE(reader.open("/nonexistent/folder", &err));
  EXPECT_NE(err.find("/nonexistent/folder"), std::string::npos) << err;
  const std::string d = tmpDir("asl_empty");
  writeFile(d + "/data.csv", "#timestamp [ns],filename\n");
  EXPECT_FALSE(reader.open(d, &err));
  EXPECT_NE(err.find("data.csv"), std::string::npos) << err;
  EXPECT_FALSE(reader.loadCamera(&err));
  EXPECT_NE(err.find("sensor.yaml"), std::string::npos) << err;
  cv::Mat img;
  EXPECT_FALSE(readMono8(d + "/nope.png", &img, &err));
  EXPECT_NE(err.find("nope.png"), std::string::npos);
  EXPECT_FALSE(toGray8(cv::Mat(), &img, &err));
  EXPECT_FALSE(toGray8(cv::Mat(4, 4, CV_32FC1, cv::Scalar(0.5)), &img, &err));
}

TEST(AslImageReader, SharedEurocFolder) {
  const std::string dir = sharedData("euroc_mh01_600");
  if (dir.empty()) GTEST_SKIP() << "shared EuRoC data absent";
  AslImageReader reader;
  std::string err;
  ASSERT_TRUE(reader.open(dir, &err)) << err;
  EXPECT_EQ(reader.size(), 600u);
  EXPECT_TRUE(reader.warnings().empty()) << reader.warnings().front();
  EXPECT_EQ(reader.entries().front().stamp_ns, 1403636584763555584LL);
  EXPECT_EQ(reader.entries().back().stamp_ns, 1403636614713555456LL);
  cv::Mat img;
  ASSERT_TRUE(reader.loadImage(0, &img, &err)) << err;
  EXPECT_EQ(img.cols, 752);
  EXPECT_EQ(img.rows, 480);
  EXPECT_EQ(img.type(), CV_8UC1);
  CameraModelPtr cam = reader.loadCamera(&err);
  ASSERT_TRUE(cam) << err;
  EXPECT_DOUBLE_EQ(cam->parameters()[0], 458.654);
}

TEST(Trajectory, SharedEurocGroundTruthTum) {
  const std::string path = sharedData("euroc_mh01_600/groundtruth/groundtruth_tum_cam0.txt");
  if (path.empty()) GTEST_SKIP() << "shared EuRoC ground truth absent";
  Trajectory t;
  std::string err;
  std::vector<std::string> warnings;
  ASSERT_TRUE(readTrajectory(path, &t, &err, Eigen::Matrix4d::Identity(), &warnings)) << err;
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(t.size(), 600u);
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(Eigen::Quaterniond(t.poses[i].linear()).norm(), 1.0, 1e-9);
    EXPECT_NEAR((t.poses[i].linear().transpose() * t.poses[i].linear() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-9);
    if (i) {
      EXPECT_GT(t.stamps[i], t.stamps[i - 1]);
    }
  }
  EXPECT_NEAR(t.stamps.front(), 1403636584.763555584, 1e-6);
  EXPECT_NEAR(t.poses.front().translation().x(), 4.6525036096, 1e-9);
  // Quaternion order x y z w: first line has qw = 0.4990939432.
  EXPECT_NEAR(std::abs(Eigen::Quaterniond(t.poses.front().linear()).w()), 0.4990939432, 1e-6);
  EXPECT_NEAR(std::abs(Eigen::Quaterniond(t.poses.front().linear()).x()), 0.6771809676, 1e-6);
}

TEST(Trajectory, TumReadWriteRoundTripNanosecondsAndComments) {
  const std::string d = tmpDir("traj");
  // ns stamps auto-detected; comment lines, a malformed line and a bad quaternion are skipped with warnings.
  writeFile(d + "/a.txt",
            "# comment\n"
            "1403636584763555584 1 2 3 0 0 0 1\n"
            "1403636584813555456 1.5 2 3 0 0 0.7071067811865476 0.7071067811865476\n"
            "1403636584863555584 1 2 3 0 0 0\n"
            "1403636584913555584 1 2 3 0 0 0 0\n"
            "\n");
  Trajectory t;
  std::string err;
  std::vector<std::string> w;
  ASSERT_TRUE(readTumTrajectory(d + "/a.txt", &t, &err, &w)) << err;
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t.stamps[0], 1403636584.763555584, 1e-6);
  EXPECT_NEAR(t.stamps[1] - t.stamps[0], 0.049999872, 1e-6);
  EXPECT_TRUE(contains(w, "a.txt:4: expected 8"));
  EXPECT_TRUE(contains(w, "a.txt:5: quaternion norm"));
  ASSERT_TRUE(writeTumTrajectory(d + "/b.txt", t, &err)) << err;
  Trajectory t2;
  ASSERT_TRUE(readTumTrajectory(d + "/b.txt", &t2, &err)) << err;
  ASSERT_EQ(t2.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(t2.stamps[i], t.stamps[i], 1e-6);
    EXPECT_LT((t2.poses[i].matrix() - t.poses[i].matrix()).norm(), 1e-8);
  }
  // The written file has 9 decimals (evo reads seconds).
  std::ifstream f(d + "/b.txt");
  std::string header, line;
  std::getline(f, header);
  std::getline(f, line);
  EXPECT_EQ(header[0], '#');
  EXPECT_EQ(line.substr(0, line.find(' ')).size(), std::string("1403636584.763555527").size()) << line;

  EXPECT_FALSE(readTumTrajectory(d + "/missing.txt", &t, &err));
  EXPECT_NE(err.find("missing.txt"), std::string::npos);
  writeFile(d + "/empty.txt", "# only a comment\n");
  EXPECT_FALSE(readTrajectory(d + "/empty.txt", &t, &err));
  EXPECT_NE(err.find("empty.txt"), std::string::npos);
}

TEST(Trajectory, EurocCsvAppliesTBS) {
  const std::string d = tmpDir("euroc_gt");
  std::system(("mkdir -p '" + d + "/mav0/state_groundtruth_estimate0'").c_str());
  const std::string csv = d + "/mav0/state_groundtruth_estimate0/data.csv";
  // Body rotated 90 deg about z (q = w 0.7071, z 0.7071) at (1, 2, 3); extra velocity/bias columns ignored.
  writeFile(csv,
            "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], v_x\n"
            "1403636580838555648,1,2,3,0.7071067811865476,0,0,0.7071067811865476,0.1\n"
            "1403636580843555328,1,2,3,1,0,0,0,0.1\n"
            "1403636580848555520,bad,2,3,1,0,0,0,0.1\n");
  Eigen::Matrix4d T_BS = Eigen::Matrix4d::Identity();
  T_BS(0, 3) = 0.5;  // camera 0.5 m along body x
  Trajectory t;
  std::string err;
  std::vector<std::string> w;
  ASSERT_TRUE(readTrajectory(d, &t, &err, T_BS, &w)) << err;  // directory form + auto-detect
  ASSERT_EQ(t.size(), 2u);
  EXPECT_TRUE(contains(w, "data.csv:4: non-numeric"));
  EXPECT_NEAR(t.stamps[0], 1403636580.838555648, 1e-6);
  // T_W_C = T_W_B * T_BS: body x axis points to world y.
  EXPECT_NEAR(t.poses[0].translation().x(), 1.0, 1e-9);
  EXPECT_NEAR(t.poses[0].translation().y(), 2.5, 1e-9);
  EXPECT_NEAR(t.poses[1].translation().x(), 1.5, 1e-9);
}

// Optional libraries are loaded from beside libiraf_vo_core.so (common/shared_library.h); a missing library or
// symbol gives nullptr and a message naming it, and the codecs read and write through the loaded plugin.
TEST(SharedLibrary, LoadsSiblingsAndNamesWhatIsMissing) {
  std::string err;
  EXPECT_EQ(iraf_vo::openSiblingLibrary("libiraf_vo_no_such_plugin.so", &err), nullptr);
  EXPECT_NE(err.find("libiraf_vo_no_such_plugin.so"), std::string::npos) << err;
  err.clear();
  void* h = iraf_vo::openSiblingLibrary("libiraf_vo_codecs.so", &err);
  ASSERT_NE(h, nullptr) << err;
  void* api = iraf_vo::findLibrarySymbol(h, "iraf_vo_image_codecs_api_v1", "libiraf_vo_codecs.so", &err);
  ASSERT_NE(api, nullptr) << err;
  // Found beside libiraf_vo_core.so (not only through ctest's LD_LIBRARY_PATH): same folder as the core.
  auto folderOf = [](const void* address) {
    Dl_info info;
    if (dladdr(address, &info) == 0 || !info.dli_fname) return std::string("?");
    const std::string path = info.dli_fname;
    return path.substr(0, path.rfind('/'));
  };
  EXPECT_EQ(folderOf(api), folderOf(reinterpret_cast<const void*>(&iraf_vo::openSiblingLibrary)));
  EXPECT_EQ(iraf_vo::findLibrarySymbol(h, "iraf_vo_no_such_symbol", "libiraf_vo_codecs.so", &err), nullptr);
  EXPECT_NE(err.find("iraf_vo_no_such_symbol"), std::string::npos) << err;
  const std::string path = tmpDir("codecs") + "/c.png";
  cv::Mat img(7, 9, CV_16UC1);
  cv::randu(img, cv::Scalar(0), cv::Scalar(65536));
  ASSERT_TRUE(iraf_vo::codecs::imwrite(path, img));
  const cv::Mat back = iraf_vo::codecs::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(back.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(back, img, cv::NORM_INF), 0.0);
  EXPECT_TRUE(iraf_vo::codecs::imread(path + ".missing", cv::IMREAD_UNCHANGED).empty());
}
