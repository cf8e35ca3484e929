// Light profiles of the simulated camera (ROS-free): what the scene's light does over the sequence and
// how the camera exposes it. A profile = scene illumination events (photometric.h: ramps, switches,
// flicker, spotlight, shadow, vignetting) + a flashlight cone or glare spots + the sensor (sensor_model.h)
// + the auto-exposure controller (auto_exposure.h). ImageFormation (image_formation.h) applies it.
//
//   clean        normal light, fixed exposure
//   dark / overexposed / flicker / mixed   the photometric presets' light events, fixed exposure
//   night        0.6 % of the normal light all along (0.23 % on real images): the longest exposure and gain
//                38-48, read noise amplified by the gain (estimated SNR 4.4-6, as a dim room at high gain)
//   ae_hunting   normal light, auto-exposure loop too aggressive for its lag: exposure oscillating about
//                0.4x-2.5x of the right one with a period under 1 s, clipping at the peaks
//   light_switch the light goes off (5 % left) and on twice; the auto-exposure recovers after each switch
//   blackout     no light at all (mean grey < 5) for 1 s (2.5 s on real images), then the light returns
//                (saturated, recovering)
//   flashlight   dark room (0.5 % ambient) lit only by a weak cone fixed to the camera (3 % of the normal
//                light at 2 m on its axis, so the camera runs at high gain, up to 48): falls off with the angle
//                from the optical axis and with distance^2 (needs the renderer's depth)
//   glare        bright lamps in the scene (x16 radiance) saturate parts of the view; the auto-exposure
//                meters them and darkens the rest
#pragma once

#include <cstdint>
#include <string>

#include "iraf_vo/sim/auto_exposure.h"
#include "iraf_vo/sim/photometric.h"
#include "iraf_vo/sim/sensor_model.h"

namespace iraf_vo {

/// Light cone fixed to the camera (on its optical axis): irradiance gain
///   ambient + intensity * exp(-0.5 (angle / sigma)^2) * (reference_distance / distance)^2,
/// sigma such that the gain halves at half_angle_deg.
struct FlashlightParams {
  bool enabled = false;
  double intensity = 0.1;           // gain on the axis at reference_distance_m (the flashlight profile: 0.03)
  double reference_distance_m = 2.0;
  double half_angle_deg = 28.0;
  double ambient = 0.005;           // the dark room's remaining light (share of the normal light)
};

/// Bright lamps (world-anchored on the simulator; image-space spots on real images) whose radiance is
/// multiplied by up to 1 + gain, soft edge over radius_m.
struct GlareParams {
  bool enabled = false;
  int spots = 3;
  double gain = 15.0;
  double radius_m = 0.35;
};

struct LightProfile {
  std::string name = "clean";
  PhotometricParams scene;  // illumination events (no noise / blur events: the sensor and the shutter make them)
  SensorParams sensor;
  AutoExposureParams ae;
  FlashlightParams flashlight;
  GlareParams glare;
  // Real images were exposed by their own camera: the auto-exposure aims at each input's own mean grey
  // (metered = target * output / input), so normal light keeps the reference exposure.
  bool meter_against_input = false;
};

/// Returns a message naming the first bad field, or "" when usable.
std::string validate(const LightProfile& p);

/// The profile `name` for a sequence of num_frames at rate_hz (frame ranges and durations scale with them);
/// `real_images`: for real 8-bit images (iraf_vo_degrade): no vignetting, lighter added noise, glare as
/// image-space spots, the auto-exposure metered against the input.
/// `reference_exposure_s`: the exposure at which the input radiance is in DN. Returns false for an unknown name.
bool lightProfile(const std::string& name, int num_frames, double rate_hz, double reference_exposure_s,
                  bool real_images, uint64_t seed, LightProfile* profile);
/// "clean|dark|overexposed|flicker|mixed|night|ae_hunting|light_switch|blackout|flashlight|glare".
std::string lightProfileNames();

}  // namespace iraf_vo
