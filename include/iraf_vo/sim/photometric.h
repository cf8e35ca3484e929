// Photometric events (ROS-free): illumination changes and sensor effects applied per frame to a
// rendered radiance image or to a real 8-bit image. Each event has a frame range and an amplitude;
// events combine (multiplicative gains, then blur, then noise, then clipping to 8 bits).
//
// Order per frame:  I = radiance * vignetting * spot/shadow * (gain ramps, switches, flicker, over-exposure)
//                   I = directional motion blur (I)          (real images; the renderer has true motion blur)
//                   I = I + N(0, shot_noise * I + read_noise^2)   (seeded per frame)
//                   out = saturate_cast<uint8>(I)             (over-exposure clips at 255)
#pragma once

#include <opencv2/core.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace iraf_vo {

enum class PhotometricEventType {
  kGainRamp = 0,      // global gain ramps 1 -> amplitude over ramp_frames, holds, ramps back (dark: amplitude < 1)
  kOverExposure = 1,  // like kGainRamp with amplitude > 1: bright image, clipped at 255
  kLightSwitch = 2,   // abrupt gain step to amplitude for the whole range (light off/on, exposure jump)
  kFlicker = 3,       // gain alternates 1 / (1 - amplitude) every period_frames / 2 frames
  kSpotlight = 4,     // Gaussian light spot (gain 1 + amplitude at its centre, sigma = radius * width)
                      // moving left to right across the image over the range
  kShadow = 5,        // soft dark band (gain 1 - amplitude, width = radius * width) sweeping left to right
  kVignetting = 6,    // gain 1 - amplitude * (r / r_corner)^2
  kNoise = 7,         // Gaussian noise: std^2 = shot_noise * I + amplitude^2 (amplitude = read noise std, DN)
  kMotionBlur = 8,    // directional box blur of length amplitude px at angle_deg
};
const char* toString(PhotometricEventType t);
bool parsePhotometricEventType(const std::string& s, PhotometricEventType* t);

struct PhotometricEvent {
  PhotometricEventType type = PhotometricEventType::kGainRamp;
  int start_frame = 0;
  int end_frame = -1;       // exclusive; -1 = to the end of the sequence
  double amplitude = 0.0;   // meaning per type (see PhotometricEventType)
  int ramp_frames = 0;      // kGainRamp / kOverExposure: frames to reach the amplitude (and to come back)
  int period_frames = 2;    // kFlicker: full period (2 = alternate every frame)
  double radius = 0.25;     // kSpotlight / kShadow: size as a fraction of the image width
  double shot_noise = 0.0;  // kNoise: shot-noise factor (DN): variance += shot_noise * I
  double angle_deg = 0.0;   // kMotionBlur: direction
  bool activeAt(int frame) const { return frame >= start_frame && (end_frame < 0 || frame < end_frame); }
};

struct PhotometricParams {
  std::vector<PhotometricEvent> events;
  uint64_t seed = 1;  // noise: the generator of frame f is seeded with (seed, f) -> deterministic, order-free
};

/// Returns a message naming the first bad event field, or "" when usable.
std::string validate(const PhotometricParams& params);

/// Preset names: clean, dark, overexposed, flicker, mixed. Frame ranges scale with num_frames.
/// `real_images`: for already-noisy real images (iraf_vo_degrade): no vignetting, lighter noise, and
/// extra abrupt exposure jumps in `mixed`. Returns false for an unknown name.
bool photometricPreset(const std::string& name, int num_frames, bool real_images, uint64_t seed,
                       PhotometricParams* params);
/// "clean|dark|overexposed|flicker|mixed".
std::string photometricPresetNames();

/// Global gain of the frame from the gain-type events (ramp, over-exposure, switch, flicker).
double globalGain(const PhotometricParams& params, int frame);

/// The light part of applyPhotometric: `in` (CV_8UC1 or CV_32FC1) times the spatial and global gains of
/// the events active at `frame` (vignetting, spotlight, shadow, ramps, switches, flicker) -> CV_32FC1,
/// unclipped. Throws std::invalid_argument for an empty image or another type.
void applyIllumination(const cv::Mat& in, int frame, const PhotometricParams& params, cv::Mat* out);

/// Applies every event active at `frame` to `in` (CV_8UC1 or CV_32FC1 radiance in 8-bit units) and
/// writes the CV_8UC1 result. Throws std::invalid_argument for an empty image or another type.
void applyPhotometric(const cv::Mat& in, int frame, const PhotometricParams& params, cv::Mat* out);

/// events.csv: "# type,start_frame,end_frame,amplitude,ramp_frames,period_frames,radius,shot_noise" then
/// one line per event (end_frame resolved to num_frames when open).
bool writeEventsCsv(const std::string& path, const PhotometricParams& params, int num_frames, std::string* error);

}  // namespace iraf_vo
