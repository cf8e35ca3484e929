// rostest test/ros/ros_graph.test: the graph as a ROS user runs it on a live camera.
//   1. NoCalibration: without ~camera_file and before any camera_info, tracking_status says why at ~1 Hz and
//      /diagnostics reports ERROR; an invalid camera_info (all-zero K) is named in that reason.
//   2. CompressedBagWithCameraInfo: a bag with sensor_msgs/CompressedImage (png) + camera_info (plumb_bob), played
//      with rosbag play through enhance (OpenCV decoding) -> features -> tracker: odometry odom -> base_link with a
//      positive-definite covariance and a twist, z up (z-up base), TF odom -> base_link, /diagnostics of enhance and tracker.
//   3. BurstIsCounted: a burst far above what the graph can process: the missed frames are counted in
//      tracking_status / diagnostics and reported as a warning on /rosout.
//   4. TransportFallbackAndSizeGuard: the EnhanceNodelet whose transport cannot load runs on raw (the manager did
//      not abort) and rejects an image whose size differs from its calibration, without stalling the next frame.
//   5. FisheyeCameraInfo: an equidistant camera_info reconfigures the tracker (Kannala-Brandt in /diagnostics).
#include <gtest/gtest.h>

#include "common/wait_for.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Eigenvalues>
#include <cstdlib>
#include <functional>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <unistd.h>

#include "iraf_vo/TrackingStatus.h"
#include "iraf_vo/camera/camera_loader.h"
#include "iraf_vo/io/image_folder.h"

namespace {

const int kFrames = 160;
std::string g_dir, g_error;
std::vector<sensor_msgs::CompressedImage> g_frames;  // png, stamps from the simulator
sensor_msgs::CameraInfo g_info;

using iraf_vo::test::waitFor;

/// Everything the tests watch, subscribed once in main() (a subscription made inside a test may miss the first
/// messages while its connections come up).
struct Recorder {
  ros::NodeHandle nh;
  ros::Subscriber status_sub, odom_sub, diag_sub, log_sub;
  std::mutex mutex;
  std::vector<iraf_vo::TrackingStatusConstPtr> status;
  std::vector<nav_msgs::OdometryConstPtr> odom;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> diag;
  std::vector<std::string> warnings;

  Recorder() {
    status_sub = nh.subscribe<iraf_vo::TrackingStatus>("/tracking_status", 200, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      status.push_back(m);
    });
    odom_sub = nh.subscribe<nav_msgs::Odometry>("/odometry", 200, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      odom.push_back(m);
    });
    diag_sub = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      for (const auto& s : m->status) diag[s.name] = s;
    });
    log_sub = nh.subscribe<rosgraph_msgs::Log>("/rosout", 500, [this](const auto& m) {
      std::lock_guard<std::mutex> l(mutex);
      if (m->level >= rosgraph_msgs::Log::WARN) warnings.push_back(m->msg);
    });
  }
};
Recorder* g_rec = nullptr;

class RosGraphTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!g_error.empty()) GTEST_SKIP() << g_error;
  }
  /// Value of `key` in the latest /diagnostics status `name` ("" if none yet).
  std::string diagValue(const std::string& name, const std::string& key) {
    std::lock_guard<std::mutex> l(mutex_);
    auto it = diag_.find(name);
    if (it == diag_.end()) return "";
    for (const auto& kv : it->second.values)
      if (kv.key == key) return kv.value;
    return "";
  }
  int diagLevel(const std::string& name) {
    std::lock_guard<std::mutex> l(mutex_);
    auto it = diag_.find(name);
    return it == diag_.end() ? -1 : it->second.level;
  }
  bool warned(const std::string& text) {
    std::lock_guard<std::mutex> l(mutex_);
    for (const std::string& w : warnings_)
      if (w.find(text) != std::string::npos) return true;
    return false;
  }

  ros::NodeHandle nh_;
  std::mutex& mutex_ = g_rec->mutex;
  std::vector<iraf_vo::TrackingStatusConstPtr>& status_ = g_rec->status;
  std::vector<nav_msgs::OdometryConstPtr>& odom_ = g_rec->odom;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus>& diag_ = g_rec->diag;
  std::vector<std::string>& warnings_ = g_rec->warnings;
};

// ---- 1 ----
TEST_F(RosGraphTest, NoCalibration) {
  size_t n0 = 0;
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    return (n0 = status_.size()) > 0;
  }, 15.0)) << "no tracking_status without calibration";
  const ros::WallTime t0 = ros::WallTime::now();
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    return status_.size() >= n0 + 2;
  }, 15.0)) << "tracking_status stopped";
  const double span = (ros::WallTime::now() - t0).toSec();
  std::lock_guard<std::mutex> l(mutex_);
  EXPECT_GE(span, 0.9) << "published faster than 1 Hz";  // two more messages: at least one full period
  EXPECT_LE(span, 4.0) << "published much slower than 1 Hz";
  EXPECT_EQ(status_.back()->state, iraf_vo::TrackingStatus::NOT_INITIALIZED);
  EXPECT_NE(status_.back()->reason.find("waiting for camera_info on /cam0/camera_info"), std::string::npos)
      << status_.back()->reason;
  ASSERT_TRUE(diag_.count("tracker: tracking"));
  EXPECT_EQ(diag_["tracker: tracking"].level, diagnostic_msgs::DiagnosticStatus::ERROR);
}

TEST_F(RosGraphTest, InvalidCameraInfoIsReported) {
  ros::Publisher pub = nh_.advertise<sensor_msgs::CameraInfo>("/cam0/camera_info", 1);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() >= 1; }, 10.0)) << "tracker / enhance subscribe (one connection)";
  sensor_msgs::CameraInfo bad = g_info;
  bad.K = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // an uncalibrated camera
  bad.P = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  pub.publish(bad);
  EXPECT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    return !status_.empty() && status_.back()->reason.find("no calibration: invalid camera_info on /cam0/camera_info: ") == 0;
  }, 5.0)) << (status_.empty() ? "" : status_.back()->reason);
}

// ---- 2 ----
TEST_F(RosGraphTest, CompressedBagWithCameraInfo) {
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  // The lazy chain subscribes enhance to the compressed topic once the tracker listens to features.
  ros::Publisher probe = nh_.advertise<sensor_msgs::CompressedImage>("/cam0/image_raw/compressed", 1);
  ASSERT_TRUE(waitFor([&] { return probe.getNumSubscribers() > 0; }, 30.0)) << "enhance did not subscribe";
  const std::string cmd = "rosbag play -q -d 1 -r 0.5 " + g_dir + "/cam0.bag > " + g_dir + "/play.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    return !status_.empty() && status_.back()->header.stamp == g_frames.back().header.stamp;
  }, 10.0)) << "the last frame of the bag did not reach the tracker";
  ros::WallDuration(1.0).sleep();

  nav_msgs::OdometryConstPtr last;
  int tracked = 0, with_twist = 0;
  {
    std::lock_guard<std::mutex> l(mutex_);
    std::printf("[ros_graph] bag: %zu odometry, last status %s, %ld tracked, %ld missed, %ld dropped\n", odom_.size(),
                status_.back()->state_name.c_str(), static_cast<long>(status_.back()->tracked),
                static_cast<long>(status_.back()->missed_frames), static_cast<long>(status_.back()->dropped_frames));
    ASSERT_GE(odom_.size(), 20u) << "too few tracked frames from the compressed bag";
    for (const auto& o : odom_) {
      EXPECT_EQ(o->header.frame_id, "odom");
      EXPECT_EQ(o->child_frame_id, "base_link");
      Eigen::Matrix<double, 6, 6> C;
      for (int i = 0; i < 36; ++i) C(i / 6, i % 6) = o->pose.covariance[i];
      EXPECT_LT((C - C.transpose()).norm(), 1e-9 * C.norm());
      using Solver = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>;
      EXPECT_GT(Solver(C).eigenvalues().minCoeff(), 0.0);
      if (o->twist.covariance[0] > 0) ++with_twist;
      // z-up base (base_to_cam0 in ros_graph.test; the simulated body pitches / rolls by < 15 deg): z-up odom.
      const Eigen::Quaterniond q(o->pose.pose.orientation.w, o->pose.pose.orientation.x, o->pose.pose.orientation.y,
                                 o->pose.pose.orientation.z);
      EXPECT_GT((q.normalized() * Eigen::Vector3d::UnitZ()).z(), 0.9) << "base z axis not up in odom";
      ++tracked;
    }
    last = odom_.back();
  }
  EXPECT_GE(with_twist, tracked / 2) << "twist from consecutive poses";
  // TF odom -> base_link = the odometry pose.
  ASSERT_TRUE(tf_buffer.canTransform("odom", "base_link", last->header.stamp, ros::Duration(3.0)));
  const auto tf = tf_buffer.lookupTransform("odom", "base_link", last->header.stamp);
  EXPECT_NEAR(tf.transform.translation.x, last->pose.pose.position.x, 1e-6);
  EXPECT_NEAR(tf.transform.translation.z, last->pose.pose.position.z, 1e-6);
  // Diagnostics: the calibration came from camera_info, the enhance input is compressed.
  ASSERT_TRUE(waitFor([&] { return diagValue("tracker: tracking", "camera").find("pinhole") != std::string::npos; },
                      5.0)) << diagValue("tracker: tracking", "camera");
  EXPECT_EQ(diagValue("enhance: input", "transport"), "compressed");
  EXPECT_EQ(diagValue("enhance: input", "topic"), "/cam0/image_raw/compressed");
  EXPECT_NE(diagValue("tracker: tracking", "frames"), "0");
}

// ---- 3 ----
TEST_F(RosGraphTest, BurstIsCounted) {
  ros::Publisher pub = nh_.advertise<sensor_msgs::CompressedImage>("/cam0/image_raw/compressed", 200);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  ros::WallDuration(0.5).sleep();
  // 200 Hz stamps, published as fast as possible: the subscriber queues overflow.
  const ros::Time base = g_frames.back().header.stamp + ros::Duration(1.0);
  for (int i = 0; i < 150; ++i) {
    sensor_msgs::CompressedImage m = g_frames[i % 40];
    m.header.stamp = base + ros::Duration(0.005 * i);
    pub.publish(m);
  }
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> l(mutex_);
    return !status_.empty() && status_.back()->missed_frames > 0;
  }, 20.0)) << "no missed frames counted";
  long missed = 0;
  {
    std::lock_guard<std::mutex> l(mutex_);
    missed = status_.back()->missed_frames;
  }
  std::printf("[ros_graph] burst: %ld frames missed\n", missed);
  EXPECT_TRUE(waitFor([&] { return warned("frame(s) missed"); }, 5.0)) << "no warning on /rosout";
  EXPECT_TRUE(waitFor([&] { return std::atol(diagValue("tracker: tracking", "missed frames").c_str()) > 0; }, 5.0));
}

// ---- 4 ----
TEST_F(RosGraphTest, TransportFallbackAndSizeGuard) {
  std::vector<sensor_msgs::ImageConstPtr> out;
  std::mutex m;
  ros::Subscriber sub = nh_.subscribe<sensor_msgs::Image>("/raw_cam/image_enhanced", 10,
                                                          [&](const sensor_msgs::ImageConstPtr& i) {
                                                            std::lock_guard<std::mutex> l(m);
                                                            out.push_back(i);
                                                          });
  ros::Publisher pub = nh_.advertise<sensor_msgs::Image>("/raw_cam/image", 2);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 20.0))
      << "the enhance nodelet with an unloadable transport did not fall back to raw";
  auto image = [](int w, int h, double stamp) {
    sensor_msgs::ImagePtr i = boost::make_shared<sensor_msgs::Image>();
    i->header.stamp = ros::Time(stamp);
    i->encoding = "mono8";
    i->width = w;
    i->height = h;
    i->step = w;
    i->data.assign(static_cast<size_t>(w) * h, 100);
    return i;
  };
  pub.publish(image(376, 240, 1.0));
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(m); return out.size() == 1; }, 10.0));
  pub.publish(image(4000, 4000, 1.05));
  ros::WallDuration(0.2).sleep();
  const ros::WallTime t0 = ros::WallTime::now();
  pub.publish(image(376, 240, 1.10));
  ASSERT_TRUE(waitFor([&] { std::lock_guard<std::mutex> l(m); return out.size() >= 2; }, 10.0));
  std::printf("[ros_graph] frame after the oversize one: %.3f s\n", (ros::WallTime::now() - t0).toSec());
  {
    std::lock_guard<std::mutex> l(m);
    EXPECT_EQ(out.size(), 2u);
    EXPECT_EQ(out.back()->header.stamp, ros::Time(1.10)) << "the 4000x4000 image went through";
  }
  EXPECT_TRUE(waitFor([&] { return diagValue("enhance_raw: input", "rejected frames (size)") == "1"; }, 5.0))
      << diagValue("enhance_raw: input", "rejected frames (size)");
  EXPECT_EQ(diagValue("enhance_raw: input", "transport"), "raw");
  EXPECT_EQ(diagLevel("enhance_raw: input"), diagnostic_msgs::DiagnosticStatus::WARN);
}

// ---- 5 ----
TEST_F(RosGraphTest, FisheyeCameraInfo) {
  ros::Publisher pub = nh_.advertise<sensor_msgs::CameraInfo>("/cam0/camera_info", 1, true);
  sensor_msgs::CameraInfo info = g_info;
  info.distortion_model = "equidistant";
  info.D = {0.01, -0.002, 0.0005, -0.0001};
  pub.publish(info);
  EXPECT_TRUE(waitFor([&] {
    return diagValue("tracker: tracking", "camera").find("kannala-brandt") != std::string::npos;
  }, 10.0)) << diagValue("tracker: tracking", "camera");
  EXPECT_TRUE(waitFor([&] { return warned("calibration changed"); }, 5.0));
}

bool prepare(std::string* error) {
  char tmpl[] = "/tmp/iraf_vo_ros_graph_XXXXXX";
  if (!mkdtemp(tmpl)) return (*error = "mkdtemp failed"), false;
  g_dir = tmpl;
  const std::string cam_file = std::string(IRAF_VO_SOURCE_DIR) + "/test/ros/sim_cam0_376x240.yaml";
  const std::string cmd = std::string(IRAF_VO_BIN_DIR) + "/iraf_vo_simulate --preset clean --frames " +
                          std::to_string(kFrames) + " --camera " + cam_file + " --out " + g_dir + " > " + g_dir +
                          "/sim.log 2>&1";
  if (std::system(cmd.c_str()) != 0) return (*error = "failed: " + cmd), false;
  const iraf_vo::CameraModelPtr cam = iraf_vo::loadCamera(cam_file, error);
  if (!cam) return false;
  const std::vector<double> p = cam->parameters();  // fx fy cx cy k1 k2 p1 p2
  g_info.width = cam->width();
  g_info.height = cam->height();
  g_info.distortion_model = "plumb_bob";
  g_info.D.assign(p.begin() + 4, p.end());
  g_info.K = {p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1};
  g_info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  g_info.P = {p[0], 0, p[2], 0, 0, p[1], p[3], 0, 0, 0, 1, 0};
  g_info.header.frame_id = "cam0";
  iraf_vo::AslImageReader reader;
  if (!reader.open(g_dir, error)) return false;
  rosbag::Bag bag(g_dir + "/cam0.bag", rosbag::bagmode::Write);
  for (size_t i = 0; i < reader.entries().size(); ++i) {
    cv::Mat gray;
    if (!reader.loadImage(i, &gray, error)) return false;
    sensor_msgs::CompressedImage m;
    m.header.stamp.fromNSec(static_cast<uint64_t>(reader.entries()[i].stamp_ns));
    m.header.frame_id = "cam0";
    m.format = "mono8; png compressed ";
    cv::imencode(".png", gray, m.data);
    g_info.header.stamp = m.header.stamp;
    bag.write("/cam0/camera_info", m.header.stamp, g_info);
    bag.write("/cam0/image_raw/compressed", m.header.stamp, m);
    g_frames.push_back(m);
  }
  bag.close();
  return static_cast<int>(g_frames.size()) == kFrames || ((*error = "wrong frame count"), false);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "ros_graph_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  g_rec = new Recorder();
  if (!prepare(&g_error)) std::fprintf(stderr, "ros_graph test: %s\n", g_error.c_str());
  const int rc = RUN_ALL_TESTS();
  if (!g_dir.empty()) std::system(("rm -rf " + g_dir).c_str());
  return rc;
}
