// Camera trajectories of the simulator (ROS-free), one per motion preset:
//   room           smooth 6-DoF elliptic loop through the default room (sums of sinusoids). The camera looks
//                  ~50 deg outwards from the travel direction, so textured walls/boxes are 1.5-6 m away and
//                  there is sideways parallax from the first frame (monocular initialization).
//   drive          a car on a street (KITTI-like): constant speed along a gently curving centreline
//                  (S-curves, heading +-drive_turn_deg), camera 1.65 m above the road in the right lane,
//                  looking forward, small pitch/roll vibrations.
//   highway        the drive's car on a highway: the same pose model with wide curves (heading +-4 deg over
//                  600 m), an open road with far structure (motionPreset sets the drive_* fields).
//   slider         pure sideways translation on a linear slider (constant speed, back and forth over
//                  slider_travel_m), fixed attitude looking at a table with near objects and a far wall.
//   handheld_fast  the room loop with fast hand-held rotations (yaw/pitch/roll swings, up to ~3 deg per
//                  frame at 20 Hz).
// Any motion can start standing still: static_start_s seconds at the pose of t = 0, then a smooth
// acceleration (constant over start_ramp_s) to the motion's speed.
#pragma once

#include <Eigen/Geometry>

#include <string>

namespace iraf_vo {

enum class MotionKind { kRoom = 0, kDrive = 1, kSlider = 2, kHandheldFast = 3, kHighway = 4 };
const char* toString(MotionKind m);
/// Parses room | drive | slider | handheld_fast | highway.
bool parseMotionKind(const std::string& s, MotionKind* m);
/// "room|drive|slider|handheld_fast|highway".
std::string motionKindNames();

struct TrajectoryParams {
  MotionKind motion = MotionKind::kRoom;
  // Standing still at the start (any motion): pose of t = 0 for static_start_s, then the motion's clock
  // accelerates linearly over start_ramp_s (position and velocity continuous).
  double static_start_s = 0.0;
  double start_ramp_s = 1.0;

  // room / handheld_fast
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
  // handheld_fast: extra hand rotations (amplitude deg, frequency Hz; peak rate = 2 pi f A)
  double hand_yaw_deg = 12.0, hand_yaw_hz = 0.42;
  double hand_pitch_deg = 7.0, hand_pitch_hz = 0.61;
  double hand_roll_deg = 5.0, hand_roll_hz = 0.33;

  // drive and highway (road along +x from the origin, z up)
  double drive_speed_mps = 10.0;      // 1 m per frame at 10 Hz
  double drive_height_m = 1.65;       // KITTI camera height
  double drive_lane_offset_m = -1.75; // camera left (+) / right (-) of the street centreline
  double drive_turn_deg = 12.0;       // heading amplitude of the S-curves
  double drive_turn_period_m = 140.0; // arc length of one S-curve period
  double drive_vibration_deg = 0.25;  // pitch/roll vibration amplitude

  // slider (camera looks along +y; slides along +x, centred on x = 0)
  double slider_speed_mps = 0.25;  // 10 mm per frame at 25 Hz
  double slider_travel_m = 1.0;    // back and forth between x = -travel/2 and +travel/2
  double slider_y_m = -0.5;        // camera position across the table (the far wall is at y = 3.5)
  double slider_height_m = 0.95;
  double slider_pitch_down_deg = 10.0;
};

/// Returns a message naming the first bad field, or "" when usable.
std::string validate(const TrajectoryParams& params);

/// The motion's own clock at time t (s): 0 during the static start, then accelerating over
/// start_ramp_s; t itself when static_start_s == 0.
double motionClock(const TrajectoryParams& params, double t);

/// Camera pose T_W_C at time t (s): camera optical frame (x right, y down, z forward) in the scene's
/// world frame (z up).
Eigen::Isometry3d trajectoryPose(const TrajectoryParams& params, double t);

/// Drive: point (x, y) of the street centreline at arc length s (m) and its heading (rad, from +x).
Eigen::Vector2d drivePath(const TrajectoryParams& params, double s, double* heading = nullptr);

}  // namespace iraf_vo
