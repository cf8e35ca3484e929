// The simulator's stereo rig (ROS-free; the tracker's calibrated pair is camera/stereo_rig.h): the right
// camera (cam1) beside the left one (cam0, whose pose
// the trajectory and the ground truth give), both with the same intrinsics. T_C0_C1 is a shift of the
// baseline along the left camera's x axis, optionally turned by a small rotation (real rigs are not
// perfectly parallel): yaw about y (toe-in), pitch about x, roll about z, in degrees.
#pragma once

#include <Eigen/Geometry>
#include <string>

namespace iraf_vo {

struct SimStereoRig {
  double baseline_m = 0.0;  // <= 0: the default of the camera (defaultStereoBaseline)
  double yaw_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;
};

/// Baseline (m) of the stereo rig each simulator camera models: pinhole (EuRoC) 0.110, fisheye (TUM-VI)
/// 0.101, kitti 0.54, davis240 (event-camera stereo rigs) 0.10, a sensor.yaml path 0.10.
double defaultStereoBaseline(const std::string& camera);

/// Returns a message naming the first bad field, or "" when usable (baseline <= 5 m, angles within 10 deg).
std::string validate(const SimStereoRig& rig);

/// Pose of the right camera in the left camera's frame (x right, y down, z forward): the rig's rotation
/// and the translation (baseline, 0, 0). `camera` gives the default baseline.
Eigen::Isometry3d rightCameraInLeft(const SimStereoRig& rig, const std::string& camera);

}  // namespace iraf_vo
