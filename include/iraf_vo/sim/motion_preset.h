// Motion presets of the simulator (ROS-free): each motion brings its own default camera, frame rate,
// length, exposure / motion blur and scene texture resolution. Combined with any photometric preset.
//
//   motion         camera              rate   frames  blur (renders x exposure)  scene (texels/m)
//   room           pinhole (EuRoC)     20 Hz  400     1 (none)                   room (256)
//   drive          kitti 1241x376      10 Hz  100     3 x 2 ms                   street (128), 10 m/s
//   slider         davis240 240x180    25 Hz  100     3 x 10 ms                  slider table (512), 0.25 m/s
//   handheld_fast  pinhole | fisheye   20 Hz  300     4 x 8 ms                   room (256), <= 3 deg/frame
//   highway        kitti 1241x376      10 Hz  100     3 x 2 ms                   highway (128), 10 m/s
#pragma once

#include <string>

#include "iraf_vo/sim/trajectory.h"

namespace iraf_vo {

struct MotionPreset {
  TrajectoryParams traj;
  std::string camera = "pinhole";  // makeSimCamera name
  double rate_hz = 20.0;
  int frames = 400;
  int motion_blur_samples = 1;
  double exposure_time_s = 0.01;
  double texels_per_m = 256.0;
  double brightness = 1.25;  // SimParams::brightness (exposure): drive / handheld_fast mean grey ~100-120 like
                             // KITTI / EuRoC frames
};

/// The defaults of a motion (table above). traj.motion is set (highway: also its drive_turn_* and
/// drive_vibration_deg); every other trajectory field keeps its default.
MotionPreset motionPreset(MotionKind motion);

}  // namespace iraf_vo
