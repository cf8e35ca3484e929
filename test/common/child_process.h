// rostests: a process the test starts (roslaunch, rosbag play) in its own process group, its output in a log file,
// stopped with SIGINT like Ctrl-C (then SIGKILL of the group after a timeout).
#pragma once

#include <ros/ros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <string>

namespace iraf_vo {
namespace test {

/// A process this test starts (its own process group), stopped with SIGINT like Ctrl-C.
class Child {
 public:
  Child(const std::string& cmd, const std::string& log) {
    pid_ = fork();
    if (pid_ == 0) {
      setpgid(0, 0);
      execl("/bin/sh", "sh", "-c", ("exec " + cmd + " > " + log + " 2>&1").c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~Child() { stop(); }
  /// SIGINT, then up to `seconds` for a clean exit, then SIGKILL of the group.
  void stop(double seconds = 30.0) {
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (ros::WallTime::now() > end) {
        kill(-pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      ros::WallDuration(0.1).sleep();
    }
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

}  // namespace test
}  // namespace iraf_vo
