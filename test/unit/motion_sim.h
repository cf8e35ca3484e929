// A simulated motion preset set up as iraf_vo_simulate does (camera, scene, clean light), rendered in-process by
// the tests that track a road.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <iraf_vo/sim/light_profile.h>
#include <iraf_vo/sim/motion_preset.h>
#include <iraf_vo/sim/renderer.h>
#include <iraf_vo/sim/scene_presets.h>

namespace iraf_vo {

struct MotionSim {
  MotionPreset preset;
  SimParams sim;
  CameraModelPtr camera;  // null: error says why
  std::shared_ptr<const Scene> scene;
  LightProfile light;
  std::string error;
};

inline MotionSim makeMotionSim(MotionKind kind, const std::string& camera, int frames, int threads, uint64_t seed,
                               const std::string& light = "clean") {
  MotionSim m;
  m.preset = motionPreset(kind);
  const MotionPreset& mp = m.preset;
  m.sim.camera = camera;
  m.sim.rate_hz = mp.rate_hz;
  m.sim.frames = frames;
  m.sim.brightness = mp.brightness;
  m.sim.exposure_time_s = mp.exposure_time_s;
  m.sim.motion_blur_samples = mp.motion_blur_samples;
  m.sim.threads = threads;
  m.sim.seed = seed;
  m.camera = makeSimCamera(camera, 0, 0, &m.error);
  if (!m.camera) return m;
  SceneParams sp;
  sp.texels_per_m = mp.texels_per_m;
  sp.seed = seed;
  m.scene = std::make_shared<const Scene>(
      makeMotionScene(sp, mp.traj, (mp.frames - 1) / m.sim.rate_hz + m.sim.exposure_time_s));
  if (!lightProfile(light, mp.frames, m.sim.rate_hz, m.sim.exposure_time_s, false, seed, &m.light)) {
    m.error = "no light profile " + light;
    m.camera.reset();
  }
  return m;
}

}  // namespace iraf_vo
