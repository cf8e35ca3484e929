#include "iraf_vo/sim/light_profile.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace iraf_vo {

std::string validate(const LightProfile& p) {
  std::string err = validate(p.scene);
  for (const PhotometricEvent& e : p.scene.events)
    if (e.type == PhotometricEventType::kNoise || e.type == PhotometricEventType::kMotionBlur)
      err += std::string("scene event ") + toString(e.type) + ": the sensor model makes noise and blur; ";
  const std::string s = validate(p.sensor), a = validate(p.ae);
  if (!s.empty()) err += "sensor: " + s;
  if (!a.empty()) err += "auto-exposure: " + a;
  const FlashlightParams& f = p.flashlight;
  if (f.enabled && !(f.intensity > 0.0 && f.reference_distance_m > 0.0 && f.half_angle_deg > 0.0 &&
                     f.half_angle_deg < 90.0 && f.ambient >= 0.0))
    err += "flashlight: need intensity > 0, reference_distance_m > 0, half_angle_deg in (0, 90), ambient >= 0; ";
  if (p.glare.enabled && !(p.glare.spots >= 1 && p.glare.gain > 0.0 && p.glare.radius_m > 0.0))
    err += "glare: need spots >= 1, gain > 0, radius_m > 0; ";
  return err;
}

std::string lightProfileNames() {
  return photometricPresetNames() + "|night|ae_hunting|light_switch|blackout|flashlight|glare";
}

bool lightProfile(const std::string& name, int n, double rate_hz, double reference_exposure_s, bool real_images,
                  uint64_t seed, LightProfile* profile) {
  const bool legacy = name == "clean" || name == "dark" || name == "overexposed" || name == "flicker" || name == "mixed";
  const bool fresh = name == "night" || name == "ae_hunting" || name == "light_switch" || name == "blackout" ||
                     name == "flashlight" || name == "glare";
  if (!legacy && !fresh) return false;
  n = std::max(n, 1);
  rate_hz = rate_hz > 0.0 ? rate_hz : 20.0;
  LightProfile p;
  p.name = name;
  // The light events of today's presets (the vignetting of the simulated lens included); their noise
  // events give way to the sensor model.
  photometricPreset(legacy ? name : "clean", n, real_images, seed, &p.scene);
  p.scene.events.erase(std::remove_if(p.scene.events.begin(), p.scene.events.end(),
                                      [](const PhotometricEvent& e) { return e.type == PhotometricEventType::kNoise; }),
                       p.scene.events.end());
  p.sensor.reference_exposure_s = reference_exposure_s;
  p.meter_against_input = real_images;
  if (real_images) {
    // A real image carries its own sensor's noise: at the reference exposure add only a little more.
    p.sensor.dn_per_electron = 0.02;
    p.sensor.full_well_e = 270.0 / p.sensor.dn_per_electron;
  }
  AutoExposureParams& ae = p.ae;
  ae.initial.time_s = reference_exposure_s;
  ae.initial.gain = 1.0;
  ae.enabled = fresh;  // today's presets: fixed exposure, the light changes show as they are
  ae.max_time_s = std::max(reference_exposure_s, std::min(0.04, 0.9 / rate_hz));
  ae.min_time_s = std::min(ae.min_time_s, reference_exposure_s);
  auto at = [n](double f) { return static_cast<int>(std::lround(f * n)); };
  auto light = [&](int start, int end, double gain) {
    PhotometricEvent e;
    e.type = PhotometricEventType::kLightSwitch;
    e.start_frame = std::min(start, n - 1);
    e.end_frame = std::min(n, std::max(end, e.start_frame + 1));
    e.amplitude = gain;
    p.scene.events.push_back(e);
  };
  if (name == "night") {
    // A dim room: the camera runs at its longest exposure and a gain of 38-48 (the simulator's room) or 48 with
    // the image at 44 % of its normal grey (EuRoC), the read noise amplified by the gain: estimated SNR 4.4-6 on
    // both. Real images get their sensor's conversion gain (EuRoC: 0.05 DN/e-) so the added noise is what that
    // camera adds at gain 48 (its own noise at gain 1 is 1/48 of that).
    light(0, n, real_images ? 0.0023 : 0.006);
    ae.max_gain = 48.0;
    ae.target_grey = 100.0;
    if (real_images) {
      p.sensor.dn_per_electron = SensorParams().dn_per_electron;
      p.sensor.full_well_e = SensorParams().full_well_e;
    }
  } else if (name == "ae_hunting") {
    // Delayed, over-aggressive loop: a limit cycle bounded by the step limit.
    ae.loop_gain = 1.6;
    ae.delay_frames = 2;
    ae.max_step = 1.5;
    ae.dead_band = 0.0;
  } else if (name == "light_switch") {
    light(at(0.25), at(0.40), 0.05);
    light(at(0.60), at(0.75), 0.05);
  } else if (name == "blackout") {
    // The light must return where the camera has mapped, or the test is of a new map, not of the relocalization.
    // The simulator's room motion turns one way all along, about 1.1 deg per frame at 20 Hz: after 2.5 s of
    // darkness (+ the washed-out frames) the camera has turned 63 deg, 23 % of its view was mapped, from that far
    // away: no relocalization, a new map. After 1 s it has turned about 30 deg and relocalizes in 2-3 frames.
    // Real sequences (EuRoC) move slowly: 2.5 s.
    const double seconds = real_images ? 2.5 : 1.0;
    const int len = std::min(at(0.3), static_cast<int>(std::lround(seconds * rate_hz)));
    light(at(0.4), at(0.4) + len, 1e-4);
  } else if (name == "flashlight") {
    // A hand lamp in a dark room: the auto-exposure meters the lit centre and runs at high gain; the periphery,
    // lit by the 0.5 % ambient only, is dark and noisy. As for `night`, real images get their sensor's gain.
    p.flashlight.enabled = true;
    p.flashlight.intensity = 0.03;
    ae.max_gain = 48.0;
    if (real_images) {
      p.sensor.dn_per_electron = SensorParams().dn_per_electron;
      p.sensor.full_well_e = SensorParams().full_well_e;
    }
  } else if (name == "glare") {
    p.glare.enabled = true;
    if (real_images) {
      // No depth: lamps as bright image-space spots crossing the view one after the other.
      for (int k = 0; k < p.glare.spots; ++k) {
        PhotometricEvent e;
        e.type = PhotometricEventType::kSpotlight;
        e.start_frame = at(0.1 + 0.3 * k), e.end_frame = std::min(n, at(0.1 + 0.3 * k + 0.25) + 1);
        e.amplitude = p.glare.gain;
        e.radius = 0.08;
        if (e.end_frame > e.start_frame) p.scene.events.push_back(e);
      }
    }
  }
  *profile = p;
  return true;
}

}  // namespace iraf_vo
