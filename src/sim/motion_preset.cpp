#include "iraf_vo/sim/motion_preset.h"

namespace iraf_vo {

MotionPreset motionPreset(MotionKind motion) {
  MotionPreset p;
  p.traj.motion = motion;
  switch (motion) {
    case MotionKind::kRoom: break;
    case MotionKind::kDrive:
      // KITTI: 10 Hz, ~1 m between frames; short exposure in daylight.
      p.camera = "kitti", p.rate_hz = 10.0, p.frames = 100;
      p.motion_blur_samples = 3, p.exposure_time_s = 0.002, p.texels_per_m = 128.0, p.brightness = 1.5;
      break;
    case MotionKind::kHighway:
      // KITTI highway-like: the drive's camera and timing; wide curves, a smoother ride.
      p.camera = "kitti", p.rate_hz = 10.0, p.frames = 100;
      p.motion_blur_samples = 3, p.exposure_time_s = 0.002, p.texels_per_m = 128.0, p.brightness = 1.5;
      p.traj.drive_turn_deg = 4.0, p.traj.drive_turn_period_m = 600.0, p.traj.drive_vibration_deg = 0.15;
      break;
    case MotionKind::kSlider:
      // 1 m of travel at 0.25 m/s = 100 frames at 25 Hz; indoor exposure.
      p.camera = "davis240", p.rate_hz = 25.0, p.frames = 100;
      p.motion_blur_samples = 3, p.exposure_time_s = 0.01, p.texels_per_m = 512.0;
      break;
    case MotionKind::kHandheldFast:
      p.frames = 300, p.motion_blur_samples = 4, p.exposure_time_s = 0.008, p.brightness = 1.6;
      break;
  }
  return p;
}

}  // namespace iraf_vo
