// Image sensor of the simulator (ROS-free): irradiance x exposure time -> photo-electrons with Poisson
// shot noise and a full-well capacity, read noise before the analog gain, ADC noise after it, 8-bit
// quantization and clipping. The irradiance image is in DN at the reference exposure (the exposure time
// at which the renderer's radiance, or a real image, is taken as it is) and unity gain:
//
//   electrons  = Poisson(irradiance * (exposure / reference_exposure) / dn_per_electron), <= full_well
//   DN         = round((electrons + N(0, read_noise_e)) * dn_per_electron * gain + N(0, adc_noise_dn)
//                      + black_level_dn), clipped to [0, 255]
//
// So with the default parameters var(DN) = gain * dn_per_electron * mean + (gain * dn_per_electron *
// read_noise_e)^2 + adc_noise_dn^2 + 1/12 (quantization) below saturation.
#pragma once

#include <opencv2/core.hpp>
#include <cstdint>
#include <string>

namespace iraf_vo {

struct SensorParams {
  // Defaults fitted to EuRoC MH_01's still frames (var = 0.050-0.053 * mean + 0.27-0.45 DN^2).
  double full_well_e = 5400.0;     // a pixel holds at most this many electrons (270 DN at unity gain)
  double dn_per_electron = 0.05;   // ADC conversion at unity gain (255 DN = 5100 e-)
  double read_noise_e = 10.0;      // pixel read noise before the analog gain (electrons rms)
  double adc_noise_dn = 0.3;       // noise after the gain (DN rms)
  double black_level_dn = 0.0;     // offset added before quantization
  double reference_exposure_s = 0.01;  // exposure at which the irradiance image is in DN (unity gain)
};

/// Returns a message naming the first bad field, or "" when usable.
std::string validate(const SensorParams& p);

/// Exposure of one frame: shutter time and analog gain.
struct Exposure {
  double time_s = 0.01;
  double gain = 1.0;
  /// Total exposure relative to the reference (time / reference * gain): the brightness factor.
  double relative(const SensorParams& s) const { return time_s / s.reference_exposure_s * gain; }
};

class SensorModel {
 public:
  /// Throws std::invalid_argument for bad parameters.
  explicit SensorModel(const SensorParams& params);

  /// Exposes `irradiance` (CV_32FC1, DN at the reference exposure and unity gain, >= 0) with `exposure`
  /// and writes the CV_8UC1 image. Noise comes from one generator seeded with `noise_seed`: the same
  /// seed gives the same image. Throws std::invalid_argument for an empty image or another type.
  void expose(const cv::Mat& irradiance, const Exposure& exposure, uint64_t noise_seed, cv::Mat* out) const;

  /// Noise-free DN of an irradiance (before clipping at 255, after the full well).
  double expectedDn(double irradiance, const Exposure& exposure) const;
  /// Variance (DN^2) of the output at mean DN `mean_dn` (below saturation) and analog gain `gain`,
  /// quantization included.
  double noiseVarianceDn(double mean_dn, double gain) const;

  const SensorParams& params() const { return p_; }

 private:
  SensorParams p_;
};

/// 64-bit mixer (splitmix64 finalizer) for per-frame seeds.
uint64_t mixSeed(uint64_t x);

}  // namespace iraf_vo
