// rostests: poll a condition on the wall clock (callbacks run on an AsyncSpinner) until it holds or time runs out.
#pragma once

#include <ros/ros.h>

#include <functional>

namespace iraf_vo {
namespace test {

/// True as soon as cond() holds; false when `seconds` (wall time) passed or ROS shut down first.
inline bool waitFor(const std::function<bool()>& cond, double seconds = 5.0) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (cond()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return cond();
}

}  // namespace test
}  // namespace iraf_vo
