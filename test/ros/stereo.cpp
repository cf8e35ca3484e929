// rostest: euroc_stereo.launch on a stereo bag made here from EuRoC MH_01 (../shared data; skipped with a message when
// absent): cam0 frames 0-79 and cam1 frames 0-49 (the right camera stops mid-bag), written by aslToBag, played at
// half rate. The stereo graph
//   * tracks from the first frames (first odometry at frame 0 or 1: a metric map from one stereo frame);
//   * publishes metric odometry: the distance travelled over 0.5 s segments matches the ground truth within 5 %;
//   * keeps odometry going after the right camera stopped, with one warning on /rosout ("left camera only") and the
//     left-only frames counted in /diagnostics; the metric scale observed (no weak-scale warning);
//   * builds the same first map as iraf_vo_run --stereo on that frame: as many stereo map points (the matches are
//     sub-pixel refined on the enhanced images, which the Features messages do not carry), every pair with its
//     images.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>

#include "common/child_process.h"
#include "common/test_data.h"
#include "common/wait_for.h"
#include "iraf_vo/TrackingStatus.h"
#include "iraf_vo/io/trajectory.h"
#include "iraf_vo/ros/bag_reader.h"

using iraf_vo::test::Child;
using iraf_vo::test::waitFor;

namespace {

std::string g_dir;
constexpr int kFrames = 80, kRightFrames = 50;

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// DIR/mav0/<cam>/data.csv + links to the first `n` images of the shared EuRoC camera.
bool linkCamera(const std::string& euroc, const std::string& dir, const std::string& cam, int n) {
  const std::string src = euroc + "/mav0/" + cam, dst = dir + "/mav0/" + cam;
  if (std::system(("mkdir -p '" + dst + "/data'").c_str()) != 0) return false;
  std::ifstream in(src + "/data.csv");
  std::ofstream out(dst + "/data.csv");
  std::string line;
  int rows = 0;
  while (rows < n && std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    out << line << "\n";
    const std::string name = line.substr(line.find(',') + 1);
    if (std::system(("ln -s '" + src + "/data/" + name + "' '" + dst + "/data/" + name + "'").c_str()) != 0) return false;
    ++rows;
  }
  return rows == n;
}

struct Watch {
  ros::NodeHandle nh;
  std::mutex m;
  std::vector<nav_msgs::OdometryConstPtr> odom;
  std::vector<std::string> warnings;
  std::map<std::string, std::string> tracker_diag;
  iraf_vo::TrackingStatusConstPtr first_map;  // the status of the frame that built the first map
  ros::Subscriber odom_sub, log_sub, diag_sub, status_sub;
  Watch() {
    status_sub = nh.subscribe<iraf_vo::TrackingStatus>("/tracking_status", 500, [this](const auto& s) {
      std::lock_guard<std::mutex> l(m);
      if (s->initialized_now && !first_map) first_map = s;
    });
    odom_sub = nh.subscribe<nav_msgs::Odometry>("/odometry", 500, [this](const nav_msgs::OdometryConstPtr& o) {
      std::lock_guard<std::mutex> l(m);
      odom.push_back(o);
    });
    log_sub = nh.subscribe<rosgraph_msgs::Log>("/rosout", 500, [this](const rosgraph_msgs::LogConstPtr& e) {
      std::lock_guard<std::mutex> l(m);
      if (e->level == rosgraph_msgs::Log::WARN) warnings.push_back(e->msg);
    });
    diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50, [this](const auto& a) {
      std::lock_guard<std::mutex> l(m);
      for (const auto& s : a->status)
        if (s.name.find("tracker") != std::string::npos)
          for (const auto& kv : s.values) tracker_diag[kv.key] = kv.value;
    });
  }
  size_t odomAfter(double t) {
    std::lock_guard<std::mutex> l(m);
    size_t n = 0;
    for (const auto& o : odom) n += o->header.stamp.toSec() > t;
    return n;
  }
};

}  // namespace

TEST(Stereo, EurocBagMetricOdometryAndTheRightCameraStopping) {
  const std::string euroc = iraf_vo_test::sharedData("euroc_mh01_600");
  if (euroc.empty() || !iraf_vo_test::exists(euroc + "/mav0/cam1/data.csv"))
    GTEST_SKIP() << "../shared/data/euroc_mh01_600 with cam1 is not there: no stereo bag to play";
  const std::string asl = g_dir + "/asl", bag = g_dir + "/stereo.bag";
  ASSERT_TRUE(linkCamera(euroc, asl, "cam0", kFrames) && linkCamera(euroc, asl, "cam1", kRightFrames));
  std::string err;
  size_t n_right = 0;
  ASSERT_EQ(iraf_vo::aslToBag(asl, bag, iraf_vo::AslToBagOptions(), &err, nullptr, &n_right), size_t(kFrames)) << err;
  ASSERT_EQ(n_right, size_t(kRightFrames));
  iraf_vo::Trajectory gt;
  ASSERT_TRUE(iraf_vo::readTrajectory(euroc + "/groundtruth/groundtruth_tum_cam0.txt", &gt, &err)) << err;
  const double t0 = gt.stamps[0], period = 0.05;

  Watch w;
  const std::string log = g_dir + "/launch.log";
  Child launch("roslaunch iraf_vo euroc_stereo.launch bag:=" + bag + " rate:=0.5 delay:=3", log);
  const double t_right_end = t0 + (kRightFrames - 1) * period;
  EXPECT_TRUE(waitFor([&] { return w.odomAfter(t0 + (kFrames - 4) * period) > 0; }, 50.0))
      << "no odometry to the end of the bag; " << readFile(log);
  ros::WallDuration(1.5).sleep();  // the last /diagnostics
  launch.stop();

  std::lock_guard<std::mutex> l(w.m);
  ASSERT_FALSE(w.odom.empty()) << readFile(log);
  EXPECT_LE(w.odom.front()->header.stamp.toSec(), t0 + 1.5 * period) << "stereo starts at the first frames";
  EXPECT_GE(w.odom.size(), size_t(kFrames * 9 / 10)) << "tracked frames";
  size_t after_right = 0;
  for (const auto& o : w.odom) after_right += o->header.stamp.toSec() > t_right_end + 0.5 * period;
  EXPECT_GE(after_right, size_t((kFrames - kRightFrames) * 9 / 10)) << "odometry goes on with the left camera";
  // Metric: distance over 10-frame segments, odometry vs ground truth (same stamps).
  std::map<long, Eigen::Vector3d> odom_at;
  for (const auto& o : w.odom) {
    const auto& p = o->pose.pose.position;
    odom_at[std::lround((o->header.stamp.toSec() - t0) / period)] = Eigen::Vector3d(p.x, p.y, p.z);
  }
  double d_odom = 0.0, d_gt = 0.0;
  for (long k = 0; k + 10 < kFrames; k += 10) {
    if (!odom_at.count(k) || !odom_at.count(k + 10)) continue;
    d_odom += (odom_at[k + 10] - odom_at[k]).norm();
    d_gt += (gt.poses[k + 10].translation() - gt.poses[k].translation()).norm();
  }
  ASSERT_GT(d_gt, 0.3) << "too few odometry samples at the segment ends";
  std::printf("stereo graph: first pose %.2f frames after the first image, %zu poses of %d frames, travelled %.3f m, "
              "ground truth %.3f m (ratio %.3f)\n", (w.odom.front()->header.stamp.toSec() - t0) / period,
              w.odom.size(), kFrames, d_odom, d_gt, d_odom / d_gt);
  EXPECT_NEAR(d_odom / d_gt, 1.0, 0.05) << "travelled " << d_odom << " m, ground truth " << d_gt << " m";
  long stereo_warnings = 0;
  for (const auto& m : w.warnings) stereo_warnings += m.find("left camera only") != std::string::npos;
  EXPECT_EQ(stereo_warnings, 1) << "one warning when the right camera stops";
  const auto it = w.tracker_diag.find("left-only frames");
  ASSERT_NE(it, w.tracker_diag.end()) << "no stereo counters in /diagnostics";
  EXPECT_GE(std::atol(it->second.c_str()), (kFrames - kRightFrames) * 9 / 10);
  const auto unrefined = w.tracker_diag.find("stereo pairs without images (not sub-pixel refined)");
  ASSERT_NE(unrefined, w.tracker_diag.end());
  EXPECT_EQ(unrefined->second, "0") << "every pair was matched on its images";
  // The metric scale is observed on EuRoC (hundreds of pose inliers within the 25 m the pair measures): no false alarm.
  const auto close = w.tracker_diag.find("close stereo inliers per frame");
  ASSERT_NE(close, w.tracker_diag.end()) << "no metric scale values in /diagnostics";
  EXPECT_GT(std::atof(close->second.c_str()), 15.0);
  const auto weak = w.tracker_diag.find("frames with a weak metric scale");
  ASSERT_NE(weak, w.tracker_diag.end());
  EXPECT_EQ(weak->second, "0");
  for (const auto& m : w.warnings) EXPECT_EQ(m.find("metric scale weakly observed"), std::string::npos) << m;

  // The first map against the offline runner's on the same frame (same cameras, parameters and core).
  ASSERT_TRUE(w.first_map != nullptr) << "no tracking_status with initialized_now";
  const long k = std::lround((w.first_map->header.stamp.toSec() - t0) / period);
  const std::string src = IRAF_VO_SOURCE_DIR, frame_log = g_dir + "/offline_frames.csv";
  const std::string run = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_run --quiet --stereo --dataset " + asl +
                          " --camera " + src + "/config/euroc_cam0.yaml --right-camera " + src +
                          "/config/euroc_cam1.yaml --config " + src + "/config/euroc.yaml --first " +
                          std::to_string(k) + " --frames 1 --out " + g_dir + "/offline.txt --frame-log " + frame_log +
                          " > " + g_dir + "/offline.log 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << run << "\n" << readFile(g_dir + "/offline.log");
  std::istringstream rows(readFile(frame_log));
  std::string header, row, state, cell;
  ASSERT_TRUE(std::getline(rows, header) && std::getline(rows, row)) << readFile(frame_log);
  std::istringstream cells(row);
  std::vector<std::string> c;
  while (std::getline(cells, cell, ',')) c.push_back(cell);
  ASSERT_GE(c.size(), 6u) << row;  // index,stamp,state,keypoints,matches,inliers: the map points of the first map
  ASSERT_EQ(c[2], "tracking") << row;
  std::printf("first map at frame %ld: %d stereo map points in ROS, %s offline\n", k, w.first_map->inliers,
              c[5].c_str());
  EXPECT_EQ(w.first_map->inliers, std::atoi(c[5].c_str())) << "the ROS stereo map differs from iraf_vo_run --stereo";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "stereo_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  char tmpl[] = "/tmp/iraf_vo_stereo_XXXXXX";
  if (!mkdtemp(tmpl)) return 1;
  g_dir = tmpl;
  const int rc = RUN_ALL_TESTS();
  if (rc == 0) std::system(("rm -rf " + g_dir).c_str());
  else std::fprintf(stderr, "stereo test: bag and launch log kept in %s\n", g_dir.c_str());
  return rc;
}
