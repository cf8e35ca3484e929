// Smooth 6-DoF camera trajectory of the simulator (ROS-free): an elliptic loop through the default
// room with height, yaw, pitch and roll variations (sums of sinusoids). The camera looks ~50 deg
// outwards from the travel direction, so textured walls/boxes are 1.5-6 m away and there is sideways
// parallax from the first frame (monocular initialization).
#pragma once

#include <Eigen/Geometry>

namespace iraf_vo {

struct TrajectoryParams {
  double loop_period_s = 20.0;  // one loop around the ellipse at speed 1 (20 s = 400 frames at 20 Hz)
  double speed = 1.0;           // multiplies the rate along the loop (and every angle rate)
  double radius_x = 1.2;        // ellipse semi-axes (m)
  double radius_y = 0.8;
  double height = 1.4;          // mean camera height (m)
  double height_amplitude = 0.15;
  double look_outward_deg = 50.0;  // yaw offset from the travel direction towards the outside
  double yaw_amplitude_deg = 6.0;
  double pitch_down_deg = 6.0;     // mean pitch (looking down)
  double pitch_amplitude_deg = 5.0;
  double roll_amplitude_deg = 4.0;
  double start_phase = 0.0;        // loop phase (rad) at t = 0
};

/// Camera pose T_W_C at time t (s): camera optical frame (x right, y down, z forward) in the room's
/// world frame (z up).
Eigen::Isometry3d trajectoryPose(const TrajectoryParams& params, double t);

}  // namespace iraf_vo
