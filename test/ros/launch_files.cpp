// rostest: the launch files users are told to run, each started with `roslaunch` on a small simulated bag
// (iraf_vo_simulate, 120 frames of the room at 20 Hz through the launch file's own camera yaml, made a bag with
// `rosrun iraf_vo iraf_vo_asl_to_bag`):
//   1. euroc.launch bag:=... image:=/cam0/image_raw/compressed rate:=0.5 loop:=true base_frame:=base_link
//      base_from_camera_file:=true trajectory_file:=... record:=... (rviz:=true on an Xvfb display when Xvfb is
//      installed): odometry of base_link, base_link -> cam0 on /tf_static, tracking_events (NEW_MAP epoch 1), rviz
//      alive; `rostopic echo -n 1` of tracking_status / tracking_events / diagnostics and
//      `rosservice call /tracker/save_trajectory "path: ..."`; after SIGINT (Ctrl-C) the console's summary and
//      "trajectory written to" lines, the trajectory file and the recorded bag.
//   2. tumvi.launch bag:=... loop:=true (fisheye): odometry and epoch 1; `rosrun dynamic_reconfigure dynparam set
//      /enhance mu_expected 60` (in use per `dynparam get`, logged "112 -> 60") and `rosservice call /tracker/reset`
//      (a NEW_MAP event, cause restart).
//   3. live.launch camera:=/camera transport:=raw camera_file:=... base_frame:=base_link camera_frame:=cam0
//      publish_camera_tf:=true camera_xyz_ypr:=... fed by `rosbag play`: odometry of base_link, base_link -> cam0.
//   4. live.launch camera:=/camera image:=/camera/image_rect rectified:=true transport:=raw, no calibration file:
//      a pinhole bag played onto image_rect and a camera_info publisher: odometry.
//   5. tumvi_stereo.launch on a simulated stereo bag (iraf_vo_simulate --stereo; skipped while the simulator has no
//      stereo rig): odometry.
//   6. live_stereo.launch left:=/stereo/left right:=/stereo/right with the EuRoC yaml files, fed by `rosbag play` of
//      a stereo bag of the shared EuRoC frames 0-59 (skipped when absent): odometry, the tracker in stereo mode.
//   (euroc_stereo.launch: stereo.test.)
#include <gtest/gtest.h>

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/transform_listener.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "common/child_process.h"
#include "common/wait_for.h"
#include "iraf_vo/TrackingEvent.h"
#include "iraf_vo/io/trajectory.h"

using iraf_vo::test::Child;
using iraf_vo::test::waitFor;

namespace {

std::string g_dir;
const std::string kConfig = std::string(IRAF_VO_SOURCE_DIR) + "/config/";
const std::string kBin = IRAF_VO_BIN_DIR;

bool sh(const std::string& cmd) { return std::system(cmd.c_str()) == 0; }

std::string readFile(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Watch {
  ros::NodeHandle nh;
  std::mutex m;
  std::vector<nav_msgs::OdometryConstPtr> odom;
  std::vector<iraf_vo::TrackingEventConstPtr> events;
  ros::Subscriber odom_sub, events_sub;
  explicit Watch(const std::string& ns = "") {
    odom_sub = nh.subscribe<nav_msgs::Odometry>(ns + "/odometry", 100, [this](const nav_msgs::OdometryConstPtr& o) {
      std::lock_guard<std::mutex> l(m);
      odom.push_back(o);
    });
    events_sub = nh.subscribe<iraf_vo::TrackingEvent>(ns + "/tracking_events", 10,
                                                      [this](const iraf_vo::TrackingEventConstPtr& e) {
                                                        std::lock_guard<std::mutex> l(m);
                                                        events.push_back(e);
                                                      });
  }
  size_t odomCount() {
    std::lock_guard<std::mutex> l(m);
    return odom.size();
  }
  bool hasNewMap(uint32_t epoch) {
    std::lock_guard<std::mutex> l(m);
    for (const auto& e : events)
      if (e->kind == iraf_vo::TrackingEvent::NEW_MAP && e->epoch == epoch) return true;
    return false;
  }
  bool hasNewMap(const std::string& cause) {
    std::lock_guard<std::mutex> l(m);
    for (const auto& e : events)
      if (e->kind == iraf_vo::TrackingEvent::NEW_MAP && e->cause == cause) return true;
    return false;
  }
};

/// A simulated bag of the room through `camera` (yaml); extra: iraf_vo_asl_to_bag options ("" = raw images).
std::string renderBag(const std::string& name, const std::string& camera, const std::string& extra) {
  const std::string dir = g_dir + "/" + name;
  const std::string bag = g_dir + "/" + name + ".bag";
  const bool ok = sh(kBin + "/iraf_vo_simulate --preset clean --frames 120 --camera " + camera + " --out " + dir +
                     " > " + dir + ".sim.log 2>&1") &&
                  sh("rosrun iraf_vo iraf_vo_asl_to_bag " + dir + " " + bag + " " + extra + " > " + dir + ".bag.log 2>&1");
  return ok ? bag : "";
}

}  // namespace

TEST(LaunchFiles, EurocWithACompressedBag) {
  const std::string bag = renderBag("euroc", kConfig + "euroc_cam0.yaml", "--compressed");
  ASSERT_FALSE(bag.empty()) << "cannot render the bag (see " << g_dir << ")";
  Watch w;
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  const std::string log = g_dir + "/euroc.log", traj = g_dir + "/euroc_traj.txt";
  // rviz:=true needs a display: a private Xvfb one when Xvfb is installed (xvfb package), else rviz is not started.
  const bool xvfb = sh("command -v Xvfb > /dev/null 2>&1");
  const std::string display = ":" + std::to_string(50 + getpid() % 200);
  std::unique_ptr<Child> x_server;
  if (xvfb) x_server.reset(new Child("Xvfb " + display + " -nolisten tcp -screen 0 1280x1024x24", g_dir + "/xvfb.log"));
  else std::printf("[ SKIPPED  ] rviz:=true: Xvfb is not installed (apt-get install xvfb)\n");
  Child launch(std::string(xvfb ? "env DISPLAY=" + display + " " : "") + "roslaunch iraf_vo euroc.launch bag:=" + bag +
               " image:=/cam0/image_raw/compressed delay:=2 rate:=0.5 loop:=true rviz:=" + (xvfb ? "true" : "false") +
               " base_frame:=base_link base_from_camera_file:=true trajectory_file:=" + traj + " record:=" + g_dir +
               "/rec", log);
  Child echo_status("rostopic echo -n 1 /tracking_status", g_dir + "/echo_tracking_status.txt");
  Child echo_events("rostopic echo -n 1 /tracking_events", g_dir + "/echo_tracking_events.txt");
  Child echo_diagnostics("rostopic echo -n 1 /diagnostics", g_dir + "/echo_diagnostics.txt");
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
  EXPECT_TRUE(waitFor([&] { return w.hasNewMap(1); }, 5.0)) << "no NEW_MAP event for epoch 1";
  {
    std::lock_guard<std::mutex> l(w.m);
    if (!w.odom.empty()) {
      EXPECT_EQ(w.odom.back()->child_frame_id, "base_link");
    }
  }
  EXPECT_TRUE(waitFor([&] { return tf.canTransform("base_link", "cam0", ros::Time(0)); }, 5.0))
      << "no static TF base_link -> cam0 from base_from_camera_file";
  if (xvfb) {
    EXPECT_TRUE(sh("timeout 20 rosnode ping -c 1 /rviz > /dev/null 2>&1")) << "rviz is not running; " << readFile(log);
    std::istringstream lines(readFile(log));
    for (std::string line; std::getline(lines, line);)
      EXPECT_FALSE(line.find("[rviz-") != std::string::npos && line.find("has died") != std::string::npos) << line;
  }
  // The README's command-line checks on the running graph (the echoes started with the launch: the bag is short).
  for (const std::string topic : {"tracking_status", "tracking_events", "diagnostics"}) {
    const std::string out = g_dir + "/echo_" + topic + ".txt";
    EXPECT_TRUE(waitFor([&] { return readFile(out).find("header") != std::string::npos; }, 20.0))
        << "rostopic echo -n 1 /" << topic << ": " << readFile(out);
  }
  const std::string echo = g_dir + "/echo.txt", cli_traj = g_dir + "/cli_traj.txt";
  EXPECT_TRUE(sh("timeout 30 rosservice call /tracker/save_trajectory \"path: '" + cli_traj + "'\" > " + echo + " 2>&1"))
      << readFile(echo);
  EXPECT_NE(readFile(echo).find("success: True"), std::string::npos) << readFile(echo);
  iraf_vo::Trajectory saved;
  std::string save_err;
  EXPECT_TRUE(iraf_vo::readTumTrajectory(cli_traj, &saved, &save_err)) << save_err;
  ros::WallDuration(2.0).sleep();
  launch.stop();
  // Ctrl-C: the tracker's summary and the final trajectory write reach the console log.
  const std::string console = readFile(log);
  EXPECT_NE(console.find("tracker: summary: "), std::string::npos) << "no shutdown summary; " << console;
  EXPECT_NE(console.find("trajectory written to " + traj + " ("), std::string::npos)
      << "no 'trajectory written to " << traj << "'; " << console;
  iraf_vo::Trajectory t;
  std::string err;
  EXPECT_TRUE(iraf_vo::readTumTrajectory(traj, &t, &err)) << err;
  EXPECT_GT(t.size(), 20u);
  EXPECT_TRUE(sh("ls " + g_dir + "/rec_*.bag > /dev/null 2>&1")) << "record:= wrote no bag";
}

TEST(LaunchFiles, TumviWithAFisheyeBag) {
  const std::string bag = renderBag("tumvi", kConfig + "tumvi_cam0.yaml", "");
  ASSERT_FALSE(bag.empty()) << "cannot render the bag (see " << g_dir << ")";
  Watch w;
  const std::string log = g_dir + "/tumvi.log";
  Child launch("roslaunch iraf_vo tumvi.launch bag:=" + bag + " delay:=2 loop:=true", log);
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
  EXPECT_TRUE(w.hasNewMap(1));
  // The README's tuning and reset from the command line on the running graph (the bag loops: frames keep coming).
  const std::string out = g_dir + "/tumvi_cli.txt";
  EXPECT_TRUE(sh("timeout 30 rosrun dynamic_reconfigure dynparam set /enhance mu_expected 60 > " + out + " 2>&1"))
      << readFile(out);
  EXPECT_TRUE(sh("timeout 30 rosrun dynamic_reconfigure dynparam get /enhance > " + out + " 2>&1")) << readFile(out);
  EXPECT_NE(readFile(out).find("'mu_expected': 60.0"), std::string::npos) << "dynparam get /enhance: " << readFile(out);
  EXPECT_TRUE(sh("timeout 30 rosservice call /tracker/reset > " + out + " 2>&1")) << readFile(out);
  EXPECT_NE(readFile(out).find("success: True"), std::string::npos) << readFile(out);
  EXPECT_TRUE(waitFor([&] { return w.hasNewMap("restart"); }, 30.0))
      << "no NEW_MAP (restart) after rosservice call /tracker/reset; " << readFile(log);
  launch.stop();  // the console (INFO on stdout) is complete once roslaunch exits
  EXPECT_NE(readFile(log).find("enhance: mu_expected 112 -> 60"), std::string::npos) << readFile(log);
}

TEST(LaunchFiles, LiveCameraFedByABag) {
  const std::string raw_bag = renderBag("live", kConfig + "euroc_cam0.yaml", "--topic /camera/image_raw");
  ASSERT_FALSE(raw_bag.empty());
  Watch w;
  const std::string log = g_dir + "/live.log";
  // The README's z-up robot: odom -> base_link, base_link -> cam0 published by the launch file.
  Child launch("roslaunch iraf_vo live.launch camera:=/camera transport:=raw camera_file:=" + kConfig +
               "euroc_cam0.yaml base_frame:=base_link camera_frame:=cam0 publish_camera_tf:=true "
               "camera_xyz_ypr:=\"0.1 0 0.3 -1.5707963 0 -1.5707963\"", log);
  tf2_ros::Buffer tf;
  tf2_ros::TransformListener listener(tf);
  ros::WallDuration(3.0).sleep();  // the nodelets subscribe
  Child player("rosbag play -q " + raw_bag, g_dir + "/live_play.log");
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
  {
    std::lock_guard<std::mutex> l(w.m);
    if (!w.odom.empty()) {
      EXPECT_EQ(w.odom.back()->child_frame_id, "base_link");
    }
  }
  EXPECT_TRUE(waitFor([&] { return tf.canTransform("base_link", "cam0", ros::Time(0)); }, 5.0))
      << "no base_link -> cam0 from publish_camera_tf";
}

TEST(LaunchFiles, LiveRectifiedCameraWithCameraInfo) {
  // A rectified camera: the room through a distortion-free pinhole, played onto /camera/image_rect, the calibration
  // only from /camera/camera_info (P), as image_proc's outputs would give.
  const std::string yaml = g_dir + "/pinhole.yaml";
  ASSERT_TRUE(sh("sed 's/^distortion_coefficients:.*/distortion_coefficients: [0, 0, 0, 0]/' " + kConfig +
                 "euroc_cam0.yaml > " + yaml));
  const std::string raw_bag = renderBag("rect", yaml, "--topic /camera/image_raw");
  ASSERT_FALSE(raw_bag.empty());
  Watch w;
  const std::string log = g_dir + "/rect.log";
  Child launch("roslaunch iraf_vo live.launch camera:=/camera image:=/camera/image_rect rectified:=true "
               "transport:=raw", log);
  Child info("rostopic pub -r 5 /camera/camera_info sensor_msgs/CameraInfo \"{width: 752, height: 480, "
             "P: [458.654, 0, 367.215, 0, 0, 457.296, 248.375, 0, 0, 0, 1, 0]}\"", g_dir + "/rect_info.log");
  ros::WallDuration(3.0).sleep();  // the nodelets subscribe and get the calibration
  Child player("rosbag play -q " + raw_bag + " /camera/image_raw:=/camera/image_rect", g_dir + "/rect_play.log");
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
}

TEST(LaunchFiles, TumviStereoWithASimulatedStereoBag) {
  const std::string dir = g_dir + "/tumvi_stereo", bag = dir + ".bag";
  if (!sh(kBin + "/iraf_vo_simulate --help 2>&1 | grep -q -- --stereo"))
    GTEST_SKIP() << "iraf_vo_simulate renders no stereo pair: no simulated stereo bag";
  ASSERT_TRUE(sh(kBin + "/iraf_vo_simulate --preset clean --frames 120 --stereo --camera " + kConfig +
                 "tumvi_cam0.yaml --out " + dir + " > " + dir + ".sim.log 2>&1") &&
              sh(kBin + "/iraf_vo_asl_to_bag " + dir + " " + bag + " > " + dir + ".bag.log 2>&1"))
      << readFile(dir + ".sim.log") << readFile(dir + ".bag.log");
  Watch w;
  const std::string log = g_dir + "/tumvi_stereo.log";
  // The simulator's own rig (its cam1 sensor.yaml), not the real TUM-VI extrinsics of config/tumvi_cam1.yaml.
  Child launch("roslaunch iraf_vo tumvi_stereo.launch bag:=" + bag + " delay:=2 camera_file:=" + dir +
                   "/mav0/cam0/sensor.yaml right_camera_file:=" + dir + "/mav0/cam1/sensor.yaml",
               log);
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
  launch.stop();  // the log is complete once roslaunch exits
  EXPECT_NE(readFile(log).find("tracker: stereo, baseline"), std::string::npos) << readFile(log);
}

TEST(LaunchFiles, LiveStereoFedByABag) {
  const std::string euroc = std::string(IRAF_VO_SHARED_DIR) + "/data/euroc_mh01_600";
  if (!sh("test -f " + euroc + "/mav0/cam1/data.csv"))
    GTEST_SKIP() << euroc << " with cam1 is not there: no stereo bag to play";
  // 60 frames of both cameras (ASL folder of links) -> a stereo bag -> rosbag play onto the live topics.
  const std::string asl = g_dir + "/live_stereo", bag = asl + ".bag";
  for (const std::string cam : {"cam0", "cam1"})
    ASSERT_TRUE(sh("mkdir -p " + asl + "/mav0/" + cam + "/data && head -61 " + euroc + "/mav0/" + cam +
                   "/data.csv > " + asl + "/mav0/" + cam + "/data.csv && tail -n +2 " + asl + "/mav0/" + cam +
                   "/data.csv | cut -d, -f2 | tr -d '\\r' | xargs -I{} ln -s " + euroc + "/mav0/" + cam +
                   "/data/{} " + asl + "/mav0/" + cam + "/data/{}"));
  ASSERT_TRUE(sh(kBin + "/iraf_vo_asl_to_bag " + asl + " " + bag + " --topic /stereo/left/image_raw --right-topic "
                 "/stereo/right/image_raw > " + asl + ".bag.log 2>&1")) << readFile(asl + ".bag.log");
  Watch w;
  const std::string log = g_dir + "/live_stereo.log";
  Child launch("roslaunch iraf_vo live_stereo.launch transport:=raw camera_file:=" + kConfig +
               "euroc_cam0.yaml right_camera_file:=" + kConfig + "euroc_cam1.yaml", log);
  ros::WallDuration(3.0).sleep();  // the nodelets subscribe
  Child player("rosbag play -q -r 0.5 " + bag, g_dir + "/live_stereo_play.log");
  EXPECT_TRUE(waitFor([&] { return w.odomCount() >= 20; }, 90.0)) << "no odometry; " << readFile(log);
  player.stop();
  launch.stop();  // the log is complete once roslaunch exits
  EXPECT_NE(readFile(log).find("tracker: stereo, baseline 0.110"), std::string::npos) << readFile(log);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "launch_files_test");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  char tmpl[] = "/tmp/iraf_vo_launch_files_XXXXXX";
  if (!mkdtemp(tmpl)) return 1;
  g_dir = tmpl;
  const int rc = RUN_ALL_TESTS();
  std::system(("rm -rf " + g_dir).c_str());
  return rc;
}
